//! Image files in and out, and the load budget every loader of the framework reads under.
//!
//! A file is checked to be a regular file under [`LoadBudget::max_file_bytes`] before it is
//! read; an image's header is read and its size checked against the budget before a decoder
//! allocates anything, and the decoders run with the `image` crate's [`image::Limits`] set
//! and behind `catch_unwind`, so a malformed file ends in an error naming it, never in a panic,
//! an abort or an exhausted memory.

use std::io::{self, Cursor, Read};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec3;

use super::{Film, ToneMap};
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

/// An image decoded under the budget, as linear-or-encoded RGB floats.
pub(crate) struct DecodedImage {
    /// The pixels, row by row from the top, as the file stores them (no transfer function
    /// applied).
    pub rgb: image::Rgb32FImage,
    /// Whether the file holds floats (OpenEXR, Radiance HDR), i.e. linear values.
    pub is_float: bool,
}

/// Bytes per pixel that the framework adds to a decoder's own output: the linear float RGB
/// copy and the texels or film made from it.
const FLOAT_COPIES_BYTES_PER_PIXEL: u64 = 2 * 12;

/// Reads and decodes the image file `path` under `budget`. The error is the reason only (the
/// caller names the file): a file that is not a regular file or too large, an unknown
/// format, an image over the pixel or memory budget (refused from its header, before any
/// decoding), a decoder's error, or a decoder's panic.
pub(crate) fn decode_image(path: &Path, budget: &LoadBudget) -> Result<DecodedImage, String> {
    decode_image_reason(path, budget).map_err(|reason| one_line(&reason))
}

fn decode_image_reason(path: &Path, budget: &LoadBudget) -> Result<DecodedImage, String> {
    let bytes = read_bounded(path, budget).map_err(|e| e.to_string())?;
    let reader = image::ImageReader::new(Cursor::new(bytes.as_slice()))
        .with_guessed_format()
        .map_err(|e| e.to_string())?;
    let format = reader.format().ok_or_else(|| {
        "the file is not an image raylab reads (PNG, JPEG, OpenEXR or Radiance HDR)".to_string()
    })?;
    let decoded = crate::panic::catch_panic(|| {
        if format == image::ImageFormat::OpenExr {
            check_exr_header(&bytes, budget)?;
        }
        decode_under_budget(reader, budget)
    })
    .map_err(|caught| {
        format!(
            "the {} decoder failed on this file (it panicked: {})",
            format_name(format),
            caught.message
        )
    })??;
    Ok(decoded)
}

fn format_name(format: image::ImageFormat) -> &'static str {
    match format {
        image::ImageFormat::Png => "PNG",
        image::ImageFormat::Jpeg => "JPEG",
        image::ImageFormat::OpenExr => "OpenEXR",
        image::ImageFormat::Hdr => "Radiance HDR",
        _ => "image",
    }
}

fn decode_under_budget(
    mut reader: image::ImageReader<Cursor<&[u8]>>,
    budget: &LoadBudget,
) -> Result<DecodedImage, String> {
    use image::ImageDecoder;
    let side = u32::try_from(budget.max_pixels).unwrap_or(u32::MAX);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(side);
    limits.max_image_height = Some(side);
    limits.max_alloc = Some(budget.max_decode_bytes);
    reader.limits(limits);
    let decoder = reader.into_decoder().map_err(|e| e.to_string())?;
    let (width, height) = decoder.dimensions();
    let colour = decoder.color_type();
    check_size(
        u64::from(width),
        u64::from(height),
        u64::from(colour.bytes_per_pixel()),
        budget,
    )?;
    if width == 0 || height == 0 {
        return Err("the image has no pixels".into());
    }
    let is_float = matches!(colour, image::ColorType::Rgb32F | image::ColorType::Rgba32F);
    let img = image::DynamicImage::from_decoder(decoder).map_err(|e| e.to_string())?;
    Ok(DecodedImage {
        rgb: img.into_rgb32f(),
        is_float,
    })
}

/// Refuses an image of `width × height` pixels whose decoder output takes
/// `decoder_bytes_per_pixel` bytes a pixel when it is over the pixel or memory budget.
fn check_size(
    width: u64,
    height: u64,
    decoder_bytes_per_pixel: u64,
    budget: &LoadBudget,
) -> Result<(), String> {
    let pixels = width.saturating_mul(height);
    if pixels > budget.max_pixels {
        return Err(format!(
            "the image is {width} × {height} = {pixels} pixels; the load budget allows at most {} pixels",
            budget.max_pixels
        ));
    }
    let bytes = pixels.saturating_mul(decoder_bytes_per_pixel + FLOAT_COPIES_BYTES_PER_PIXEL);
    if bytes > budget.max_decode_bytes {
        return Err(format!(
            "decoding the {width} × {height} image takes about {} MiB; the load budget allows {} MiB",
            bytes >> 20,
            budget.max_decode_bytes >> 20
        ));
    }
    Ok(())
}

/// Checks an OpenEXR file's headers (read with the `exr` crate's metadata reader, which reads
/// no pixels) against the budget before `image` decodes it: the data and display windows of
/// every part, their channels, tiles and levels, and the compression. Only the compressions
/// whose decoders in exr 1.74 allocate no more than the window's pixels are read: none, RLE
/// and ZIP (the ones raylab writes, and most tools' default); the others are refused (see
/// docs/architecture.md, "Decisions").
fn check_exr_header(bytes: &[u8], budget: &LoadBudget) -> Result<(), String> {
    use exr::compression::Compression;
    use exr::meta::BlockDescription;
    use exr::meta::attribute::LevelMode;
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false)
        .map_err(|e| format!("not a readable OpenEXR header: {e}"))?;
    let parts = meta.headers.len();
    let mut total_pixels = 0u64;
    let mut total_bytes = 0u64;
    for (i, header) in meta.headers.iter().enumerate() {
        let part = if parts > 1 {
            format!("part {i}: ")
        } else {
            String::new()
        };
        if header.deep {
            return Err(format!(
                "{part}deep OpenEXR data is not an image raylab reads"
            ));
        }
        match header.compression {
            Compression::Uncompressed
            | Compression::RLE
            | Compression::ZIP1
            | Compression::ZIP16 => {}
            other => {
                return Err(format!(
                    "{part}the file uses {other}, which raylab does not read (its decoder can \
                     exhaust memory or panic on a malformed file); save it with ZIP, RLE or no \
                     compression"
                ));
            }
        }
        let window = header.layer_size;
        let display = header.shared_attributes.display_window.size;
        let mut levels = 1;
        if let BlockDescription::Tiles(tiles) = &header.blocks {
            let tile = tiles.tile_size;
            if (tile.0 as u64).saturating_mul(tile.1 as u64) > budget.max_pixels {
                return Err(format!(
                    "{part}the tiles are {} × {} pixels; the load budget allows at most {} pixels",
                    tile.0, tile.1, budget.max_pixels
                ));
            }
            levels = match tiles.level_mode {
                LevelMode::Singular => 1,
                // The smaller levels of a mip map add up to a third of the image, those of a
                // rip map to three times it.
                LevelMode::MipMap => 2,
                LevelMode::RipMap => 4,
            };
        }
        for (w, h) in [(window.0, window.1), (display.0, display.1)] {
            check_size(w as u64, h as u64, 16, budget).map_err(|e| format!("{part}{e}"))?;
        }
        let pixels = (window.0 as u64).saturating_mul(window.1 as u64);
        let channels = header.channels.list.len() as u64;
        total_pixels = total_pixels.saturating_add(pixels.saturating_mul(levels));
        total_bytes = total_bytes.saturating_add(
            pixels
                .saturating_mul(levels)
                .saturating_mul(channels.saturating_mul(4)),
        );
    }
    if total_pixels > budget.max_pixels {
        return Err(format!(
            "the {parts} parts of the file hold {total_pixels} pixels; the load budget allows at most {}",
            budget.max_pixels
        ));
    }
    if total_bytes > budget.max_decode_bytes {
        return Err(format!(
            "the channels of the file take {} MiB; the load budget allows {} MiB",
            total_bytes >> 20,
            budget.max_decode_bytes >> 20
        ));
    }
    Ok(())
}

fn create_parent(path: &Path) -> Result<(), Error> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))
        }
        _ => Ok(()),
    }
}

/// Writes the film as an 8-bit sRGB PNG after tone mapping.
pub fn write_png(film: &Film, path: &Path, tonemap: ToneMap) -> Result<(), Error> {
    write_srgb8_png(&film.to_srgb8(tonemap), film.width, film.height, path)
}

/// Writes 8-bit sRGB pixels (`width × height × 3` bytes, row by row) as a PNG file.
pub fn write_srgb8_png(bytes: &[u8], width: u32, height: u32, path: &Path) -> Result<(), Error> {
    create_parent(path)?;
    image::save_buffer_with_format(
        path,
        bytes,
        width,
        height,
        image::ExtendedColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| Error::ImageOutput {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })
}

/// Writes the film's linear radiance, unmodified, as a 32-bit float OpenEXR file.
pub fn write_exr(film: &Film, path: &Path) -> Result<(), Error> {
    create_parent(path)?;
    let data: Vec<f32> = film.pixels.iter().flat_map(|p| p.to_array()).collect();
    let buffer = image::Rgb32FImage::from_raw(film.width, film.height, data).ok_or_else(|| {
        Error::ImageOutput {
            path: path.to_path_buf(),
            reason: "pixel count does not match the size".into(),
        }
    })?;
    buffer
        .save_with_format(path, image::ImageFormat::OpenExr)
        .map_err(|e| Error::ImageOutput {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })
}

/// Reads a float image (OpenEXR, or any format `image` decodes) into a film, under the
/// [`LoadBudget::current`] budget.
pub fn read_exr(path: &Path) -> Result<Film, Error> {
    let rgb = decode_image(path, &LoadBudget::current())
        .map_err(|reason| Error::Texture {
            path: path.to_path_buf(),
            reason,
        })?
        .rgb;
    let (width, height) = rgb.dimensions();
    Ok(Film {
        width,
        height,
        pixels: rgb.pixels().map(|p| Vec3::from(p.0)).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exr_round_trip_is_exact() {
        let mut film = Film::new(3, 2);
        film.set(0, 0, Vec3::new(0.1, 1e-7, 12345.678));
        film.set(2, 1, Vec3::new(std::f32::consts::PI, 0.0, 1.0 / 3.0));
        let dir = std::env::temp_dir().join(format!("raylab-exr-{}", std::process::id()));
        let path = dir.join("t.exr");
        write_exr(&film, &path).unwrap();
        let back = read_exr(&path).unwrap();
        assert_eq!(back, film);
        write_png(&film, &dir.join("t.png"), ToneMap::default()).unwrap();
        std::fs::remove_dir_all(dir).ok();
    }
}
