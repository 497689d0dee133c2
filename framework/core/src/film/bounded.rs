//! The load budget every loader of the framework reads under: a file is checked to be a
//! regular file under [`LoadBudget::max_file_bytes`] before it is read.

use std::io::{self, Read};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::Error;

/// What the loaders may read and decode: every file the framework opens (scene file, OBJ, MTL,
/// image) is checked against it before it is read, every image before it is decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadBudget {
    /// The largest file, in bytes, that a loader reads.
    pub max_file_bytes: u64,
    /// The largest image, in pixels (width · height, summed over the parts of an OpenEXR file).
    pub max_pixels: u64,
    /// The most memory, in bytes, that decoding one image may take: the decoder's pixels, their
    /// linear float copy and the texels or film made from them.
    pub max_decode_bytes: u64,
}

impl LoadBudget {
    /// The budget in force unless [`LoadBudget::install`] changes it: files up to 256 MiB,
    /// images up to 2²⁵ pixels (8192 × 4096) and 1 GiB of memory to decode one.
    pub const DEFAULT: Self = Self {
        max_file_bytes: 256 << 20,
        max_pixels: 1 << 25,
        max_decode_bytes: 1 << 30,
    };

    /// The budget the loaders use now (process-wide).
    pub fn current() -> Self {
        Self {
            max_file_bytes: BUDGET[0].load(Ordering::Relaxed),
            max_pixels: BUDGET[1].load(Ordering::Relaxed),
            max_decode_bytes: BUDGET[2].load(Ordering::Relaxed),
        }
    }

    /// Makes this the budget of every later load in the process.
    pub fn install(self) {
        BUDGET[0].store(self.max_file_bytes, Ordering::Relaxed);
        BUDGET[1].store(self.max_pixels, Ordering::Relaxed);
        BUDGET[2].store(self.max_decode_bytes, Ordering::Relaxed);
    }
}

impl Default for LoadBudget {
    fn default() -> Self {
        Self::DEFAULT
    }
}

static BUDGET: [AtomicU64; 3] = [
    AtomicU64::new(LoadBudget::DEFAULT.max_file_bytes),
    AtomicU64::new(LoadBudget::DEFAULT.max_pixels),
    AtomicU64::new(LoadBudget::DEFAULT.max_decode_bytes),
];

/// Reads a whole file after checking that it is a regular file (not a directory, FIFO, device
/// or socket, which could block or never end) of at most `budget.max_file_bytes` bytes.
pub fn read_bounded(path: &Path, budget: &LoadBudget) -> io::Result<Vec<u8>> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    // Opening a FIFO for reading blocks until a writer comes; without blocking it does not,
    // and the check below refuses it. Reads of a regular file ignore the flag.
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut options, libc::O_NONBLOCK);
    let file = options.open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("is not a regular file but {}", file_kind(&meta.file_type())),
        ));
    }
    let too_big = |size: u64| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "is {size} bytes; the load budget allows files of at most {} bytes",
                budget.max_file_bytes
            ),
        )
    };
    if meta.len() > budget.max_file_bytes {
        return Err(too_big(meta.len()));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    // The file may grow while it is read: read one byte past the limit to notice.
    file.take(budget.max_file_bytes + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > budget.max_file_bytes {
        return Err(too_big(bytes.len() as u64));
    }
    Ok(bytes)
}

/// Reads a text file under the budget (see [`read_bounded`]); a file that is not UTF-8 is
/// refused with the line and byte where it stops being text.
pub fn read_text_bounded(path: &Path, budget: &LoadBudget) -> io::Result<String> {
    String::from_utf8(read_bounded(path, budget)?).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let bytes = e.as_bytes();
        let line = 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count();
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "is not a text file: byte {at} (line {line}) is 0x{:02x}, which is not UTF-8",
                bytes[at]
            ),
        )
    })
}

fn file_kind(kind: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a directory"
    } else {
        "not a file"
    }
}

/// A message on one line: its lines joined with "; ".
pub(crate) fn one_line(message: &str) -> String {
    message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

pub(super) fn create_parent(path: &Path) -> Result<(), Error> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))
        }
        _ => Ok(()),
    }
}
