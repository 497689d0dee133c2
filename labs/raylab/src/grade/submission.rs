//! What is taken from a submission (`labs/labNN/src/**`), and what else it changed.
//!
//! A submission is hostile. Nothing here follows a symbolic link or opens anything but a
//! regular file, and every walk is bounded in entries, depth and bytes. What is refused becomes
//! a line of text, never an `Err`, so one submission cannot stop the grading of the others: an
//! `Err` is a failure on the grading side (the tree, the handout).

use course::LabId;
use std::collections::BTreeMap;
use std::ffi::OsStr;
use std::fs::{self, DirEntry, FileType, OpenOptions};
use std::io::{ErrorKind, Read, Write};
use std::ops::Bound;
use std::os::unix::fs::{FileTypeExt, OpenOptionsExt, PermissionsExt};
use std::path::{Path, PathBuf};

use raylab_core::Error;

use crate::handout::io;

/// Directories never compared or copied: build output and version control.
const SKIPPED: &[&str] = &[".git", "target", "out"];

/// Files a build rewrites on its own, left out of the comparison.
const REGENERATED: &[&str] = &["Cargo.lock"];

/// The largest file taken from a submission (1 MiB).
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// The largest file of a submission compared by content with the handout's (8 MiB: the
/// handout's own files, such as lab 12's sky, are larger than a student's source file).
const MAX_COMPARED_BYTES: u64 = 8 << 20;

/// The most entries (files, directories, refused entries) looked at in one lab's `src/`.
const MAX_LAB_ENTRIES: usize = 256;

/// The most bytes taken from one lab's `src/` (8 MiB).
const MAX_LAB_BYTES: u64 = 8 << 20;

/// The deepest entry taken from one lab's `src/`, in path components below it.
const MAX_LAB_DEPTH: usize = 8;

/// The most entries of a submission looked at by [`changed_files`].
const MAX_COMPARED_ENTRIES: usize = 20_000;

/// The deepest entry of a submission looked at by [`changed_files`].
const MAX_COMPARED_DEPTH: usize = 32;

/// What happened to one lab's code on its way into the grading tree.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LabIntake {
    /// A note when the submission has no real `labs/labNN/src/` directory and the lab is graded
    /// as the handout's stubs.
    pub missing: Option<String>,
    /// One line per entry of the submission's `labs/labNN/src/` that was not copied, and why.
    pub rejected: Vec<String>,
}

/// Why an entry of a submission was not read.
#[derive(Debug)]
pub enum Refusal {
    /// A symbolic link.
    Link,
    /// Not a regular file, a directory or a link: what it is ("a FIFO", …).
    Special(&'static str),
    /// A regular file over [`MAX_FILE_BYTES`]: its size, or `None` when it grew past the limit
    /// while being read.
    TooLarge(Option<u64>),
    /// The operating system refused to open or read it.
    Unreadable(std::io::Error),
}

impl Refusal {
    /// The refusal as the end of a rejection line: `a FIFO (not read)`.
    pub fn rejection(&self) -> String {
        match self {
            Refusal::Link => "a symbolic link (not followed)".into(),
            Refusal::Special(kind) => format!("{kind} (not read)"),
            Refusal::TooLarge(Some(size)) => {
                format!("{}, over the 1 MiB limit for one file", bytes(*size))
            }
            Refusal::TooLarge(None) => {
                "grew while being read, over the 1 MiB limit for one file".into()
            }
            Refusal::Unreadable(err) => format!("cannot be read: {err}"),
        }
    }

    /// The refusal as the note of a `changed_files` line: `a FIFO, not read`.
    fn note(&self) -> String {
        match self {
            Refusal::Link => "a symbolic link, not read".into(),
            Refusal::Special(kind) => format!("{kind}, not read"),
            Refusal::TooLarge(Some(size)) => format!("{size} bytes, not compared"),
            Refusal::TooLarge(None) => "grew while being read, not compared".into(),
            Refusal::Unreadable(err) => format!("cannot be read: {err}"),
        }
    }
}

/// What an entry is, for a line of text: "a symbolic link", "a FIFO", …
fn kind(file_type: FileType) -> &'static str {
    if file_type.is_symlink() {
        "a symbolic link"
    } else if file_type.is_dir() {
        "a directory"
    } else if file_type.is_file() {
        "a regular file"
    } else if file_type.is_fifo() {
        "a FIFO"
    } else if file_type.is_socket() {
        "a socket"
    } else if file_type.is_block_device() {
        "a block device"
    } else if file_type.is_char_device() {
        "a character device"
    } else {
        "not a regular file"
    }
}

/// A size for a line of text: exact bytes below 2 MiB (so that a file just over the 1 MiB
/// limit never reads "1.0 MiB"), MiB with one decimal above.
fn bytes(size: u64) -> String {
    if size < 2 << 20 {
        format!("{size} bytes")
    } else {
        format!("{:.1} MiB", size as f64 / f64::from(1 << 20))
    }
}

/// `path` for a line of text: lossy UTF-8 with control characters escaped, so that a hostile
/// name cannot write escape sequences into a report or a terminal.
pub fn shown(path: &Path) -> String {
    path.to_string_lossy()
        .chars()
        .map(|c| {
            if c.is_control() {
                c.escape_default().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// Why the name of an entry is refused, if it is.
fn bad_name(name: &OsStr) -> Option<&'static str> {
    match name.to_str() {
        None => Some("a name that is not valid UTF-8 (not copied)"),
        Some(name) if name.chars().any(char::is_control) => {
            Some("a name with control characters (not copied)")
        }
        Some(_) => None,
    }
}

/// Reads the regular file at `path`, at most `limit` bytes, without following a symbolic link
/// and without blocking or over-allocating when something else was put there after it was
/// checked: the file is opened with `O_NOFOLLOW | O_NONBLOCK | O_NOCTTY`, the opened file must
/// be a regular file, and at most `limit` + 1 bytes are read.
pub fn read_regular(path: &Path, limit: u64) -> Result<Vec<u8>, Refusal> {
    let file = OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK | libc::O_NOCTTY)
        .open(path)
        .map_err(|err| match err.raw_os_error() {
            Some(libc::ELOOP) => Refusal::Link,
            _ => Refusal::Unreadable(err),
        })?;
    let metadata = file.metadata().map_err(Refusal::Unreadable)?;
    if !metadata.file_type().is_file() {
        return Err(Refusal::Special(kind(metadata.file_type())));
    }
    if metadata.len() > limit {
        return Err(Refusal::TooLarge(Some(metadata.len())));
    }
    // The size is at most `limit`, so this reserves no more than the limit.
    let mut contents = Vec::with_capacity(metadata.len() as usize);
    file.take(limit + 1)
        .read_to_end(&mut contents)
        .map_err(Refusal::Unreadable)?;
    if contents.len() as u64 > limit {
        return Err(Refusal::TooLarge(None));
    }
    Ok(contents)
}

/// The entries of `dir`, at most `budget` of them (`more` tells whether there were others),
/// sorted by name; an error when `dir` cannot be listed.
fn entries(dir: &Path, budget: usize) -> std::io::Result<(Vec<DirEntry>, bool)> {
    let mut entries = Vec::new();
    let mut more = false;
    for entry in fs::read_dir(dir)? {
        let entry = entry?;
        if SKIPPED.iter().any(|s| entry.file_name() == *s) {
            continue;
        }
        if entries.len() == budget {
            more = true;
            break;
        }
        entries.push(entry);
    }
    entries.sort_by_key(DirEntry::file_name);
    Ok((entries, more))
}

/// The files taken from one lab's `src/`, and a rejection line for each entry refused.
#[derive(Default)]
struct Taken {
    /// The files, by path relative to `src/`.
    files: Vec<(PathBuf, Vec<u8>)>,
    /// Entries looked at so far.
    entries: usize,
    /// Bytes taken so far.
    bytes: u64,
    /// One line per refusal.
    rejected: Vec<String>,
}

impl Taken {
    /// Takes the files of `src` (shown in lines as `shown_as`), within the lab's limits.
    fn from(src: &Path, shown_as: &Path) -> Taken {
        let mut taken = Taken::default();
        taken.walk(src, shown_as, Path::new(""), 1);
        taken
    }

    /// Takes the entries of the directory `root/relative`, which are `depth` levels below
    /// `root`. Returns false once the entry limit stopped the walk.
    fn walk(&mut self, root: &Path, shown_as: &Path, relative: &Path, depth: usize) -> bool {
        let dir = root.join(relative);
        let shown_dir = shown(&shown_as.join(relative));
        let (entries, more) = match entries(&dir, MAX_LAB_ENTRIES - self.entries) {
            Ok(listed) => listed,
            Err(err) => {
                self.rejected
                    .push(format!("{shown_dir}: cannot be listed: {err}"));
                return true;
            }
        };
        self.entries += entries.len();
        for entry in entries {
            let path = relative.join(entry.file_name());
            let shown_path = shown(&shown_as.join(&path));
            if let Some(reason) = bad_name(&entry.file_name()) {
                self.rejected.push(format!("{shown_path}: {reason}"));
                continue;
            }
            let file_type = match entry.file_type() {
                Ok(file_type) => file_type,
                Err(err) => {
                    self.rejected
                        .push(format!("{shown_path}: cannot be read: {err}"));
                    continue;
                }
            };
            if file_type.is_dir() {
                if depth >= MAX_LAB_DEPTH {
                    self.rejected.push(format!(
                        "{shown_path}: a directory whose contents are more than {MAX_LAB_DEPTH} levels deep (not copied)"
                    ));
                } else if !self.walk(root, shown_as, &path, depth + 1) {
                    return false;
                }
            } else if file_type.is_file() {
                if let Err(reason) = self.take_file(&root.join(&path), &path) {
                    self.rejected.push(format!("{shown_path}: {reason}"));
                }
            } else if file_type.is_symlink() {
                let reason = Refusal::Link.rejection();
                self.rejected.push(format!("{shown_path}: {reason}"));
            } else {
                let reason = Refusal::Special(kind(file_type)).rejection();
                self.rejected.push(format!("{shown_path}: {reason}"));
            }
        }
        if more {
            self.rejected.push(format!(
                "{}: more than {MAX_LAB_ENTRIES} entries, the rest is not copied",
                shown(shown_as)
            ));
        }
        !more
    }

    /// Takes the regular file at `path` (`relative` to `src/`) within the limits; the end of
    /// its rejection line if it is refused.
    fn take_file(&mut self, path: &Path, relative: &Path) -> Result<(), String> {
        let over_total = |size: u64| {
            format!(
                "{}, over the 8 MiB limit for one lab's files in total (not copied)",
                bytes(size)
            )
        };
        // The size as listed, to refuse a large file without opening it.
        let listed = fs::symlink_metadata(path)
            .map_err(|err| Refusal::Unreadable(err).rejection())?
            .len();
        if listed > MAX_FILE_BYTES {
            return Err(Refusal::TooLarge(Some(listed)).rejection());
        }
        if self.bytes + listed > MAX_LAB_BYTES {
            return Err(over_total(listed));
        }
        let contents = read_regular(path, MAX_FILE_BYTES).map_err(|r| r.rejection())?;
        let size = contents.len() as u64;
        if self.bytes + size > MAX_LAB_BYTES {
            return Err(over_total(size));
        }
        self.bytes += size;
        self.files.push((relative.to_path_buf(), contents));
        Ok(())
    }
}

/// `labs/labNN/src` of lab `lab`.
fn lab_src(lab: LabId) -> PathBuf {
    PathBuf::from(format!("labs/{lab}/src"))
}

/// Checks that each of `labs`, `labs/labNN` and `labs/labNN/src` under `submission` is a real
/// directory. `Err(None)` when one does not exist, `Err(Some(line))` with a rejection line
/// when one is something else (a symbolic link, a file, …) or cannot be looked at.
fn real_dir(submission: &Path, src: &Path) -> Result<PathBuf, Option<String>> {
    let mut relative = PathBuf::new();
    for component in src.components() {
        relative.push(component);
        let path = submission.join(&relative);
        let shown_path = shown(&relative);
        match fs::symlink_metadata(&path) {
            Err(err) if err.kind() == ErrorKind::NotFound => return Err(None),
            Err(err) => return Err(Some(format!("{shown_path}: cannot be read: {err}"))),
            Ok(metadata) if metadata.file_type().is_symlink() => {
                return Err(Some(format!("{shown_path}: {}", Refusal::Link.rejection())));
            }
            Ok(metadata) if !metadata.is_dir() => {
                return Err(Some(format!(
                    "{shown_path}: {}, not a directory (not read)",
                    kind(metadata.file_type())
                )));
            }
            Ok(_) => {}
        }
    }
    Ok(submission.join(src))
}

/// Puts lab `lab`'s code into `tree` (where a submission's build takes it from), replacing
/// `tree/labs/labNN/src`: the
/// submission's `labs/labNN/src/` if it is a real directory, otherwise (or for `None`) the
/// handout's stubs.
///
/// Only regular files are copied, each at most 1 MiB, at most 256 entries, 8 MiB and 8 levels
/// per lab, with names of valid UTF-8 and no control characters; no symbolic link is followed
/// and nothing else is opened. Every refusal is a line of [`LabIntake::rejected`]. The files
/// written are plain regular files (mode 0644). An `Err` is a failure on the grading side: the
/// tree cannot be written, or the handout's stubs cannot be read.
pub fn install_lab_code(
    submission: Option<&Path>,
    handout: &Path,
    tree: &Path,
    lab: LabId,
) -> Result<LabIntake, Error> {
    let src = lab_src(lab);
    let mut intake = LabIntake::default();
    let theirs = submission.and_then(|submission| match real_dir(submission, &src) {
        Ok(dir) => Some(Taken::from(&dir, &src)),
        Err(rejected) => {
            intake.rejected.extend(rejected);
            intake.missing = Some(format!(
                "{}/ is missing: graded as the handout's stubs",
                src.display()
            ));
            None
        }
    });
    let files = match theirs {
        Some(taken) => {
            intake.rejected.extend(taken.rejected);
            taken.files
        }
        None => {
            let stubs = handout.join(&src);
            let taken = Taken::from(&stubs, &src);
            if let Some(line) = taken.rejected.into_iter().next() {
                return Err(Error::Failed {
                    what: format!("the handout's {}", stubs.display()),
                    reason: line,
                });
            }
            taken.files
        }
    };
    write_files(&tree.join(&src), &files)?;
    Ok(intake)
}

/// A lab's files as read from a submission by [`lab_sources`].
pub struct LabSources {
    /// The files, by path relative to `src/`; `None` when the submission has no real
    /// `labs/labNN/src/` directory.
    pub files: Option<Vec<(PathBuf, Vec<u8>)>>,
    /// One line per entry that was not read, and why.
    pub rejected: Vec<String>,
}

/// The files of lab `lab`'s `labs/labNN/src/` in `submission`, read as [`install_lab_code`]
/// reads them: regular files only, within the same limits.
pub fn lab_sources(submission: &Path, lab: LabId) -> LabSources {
    let src = lab_src(lab);
    match real_dir(submission, &src) {
        Ok(dir) => {
            let taken = Taken::from(&dir, &src);
            LabSources {
                files: Some(taken.files),
                rejected: taken.rejected,
            }
        }
        Err(rejected) => LabSources {
            files: None,
            rejected: rejected.into_iter().collect(),
        },
    }
}

/// Replaces the directory `dir` by one holding `files` (paths relative to it), each a plain
/// regular file of mode 0644.
fn write_files(dir: &Path, files: &[(PathBuf, Vec<u8>)]) -> Result<(), Error> {
    if fs::symlink_metadata(dir).is_ok() {
        fs::remove_dir_all(dir).map_err(io(dir))?;
    }
    fs::create_dir_all(dir).map_err(io(dir))?;
    for (relative, contents) in files {
        let path = dir.join(relative);
        if let Some(parent) = path.parent() {
            fs::create_dir_all(parent).map_err(io(parent))?;
        }
        let mut file = OpenOptions::new()
            .write(true)
            .create_new(true)
            .mode(0o644)
            .open(&path)
            .map_err(io(&path))?;
        file.write_all(contents).map_err(io(&path))?;
        // The mode given at creation is reduced by the umask; this one is not.
        file.set_permissions(fs::Permissions::from_mode(0o644))
            .map_err(io(&path))?;
    }
    Ok(())
}

/// Whether `path` (relative to the tree) is graded code: `labs/labNN/src/**`.
fn is_student_code(path: &Path) -> bool {
    let parts: Vec<_> = path.components().map(|c| c.as_os_str()).collect();
    parts.len() >= 4 && is_lab_src(&parts[..3])
}

/// Whether `path` (relative to the tree) is a lab's code directory `labs/labNN/src`, where each
/// submission puts its own code.
pub fn is_lab_sources(path: &Path) -> bool {
    let parts: Vec<_> = path.components().map(|c| c.as_os_str()).collect();
    is_lab_src(&parts)
}

/// Whether `path` (relative to the tree) is a lab's written answers file,
/// `labs/labNN/answers.md`: the student's own, collected for the report, never a change.
fn is_written_answers(path: &Path) -> bool {
    let parts: Vec<_> = path.components().map(|c| c.as_os_str()).collect();
    parts.len() == 3
        && parts[0] == "labs"
        && parts[1].to_string_lossy().starts_with("lab")
        && parts[1] != "raylab"
        && parts[2] == "answers.md"
}

/// The written answers of lab `lab` in `submission` (`labs/labNN/answers.md`), read as a
/// regular file of at most [`course::answers::FILE_LIMIT`] bytes under real directories.
/// `Ok(None)` when there is none; `Err` with a rejection line when it cannot be taken.
pub fn read_answers(submission: &Path, lab: LabId) -> Result<Option<String>, String> {
    let dir = match real_dir(submission, Path::new(&lab.folder())) {
        Ok(dir) => dir,
        Err(None) => return Ok(None),
        Err(Some(line)) => return Err(line),
    };
    let path = dir.join("answers.md");
    let shown_path = lab.answers();
    match fs::symlink_metadata(&path) {
        Err(err) if err.kind() == ErrorKind::NotFound => return Ok(None),
        Ok(meta) if meta.len() > course::answers::FILE_LIMIT => {
            return Err(format!(
                "{shown_path}: {}, over the {} limit of a written answers file (not read)",
                bytes(meta.len()),
                bytes(course::answers::FILE_LIMIT)
            ));
        }
        _ => {}
    }
    let contents = read_regular(&path, course::answers::FILE_LIMIT)
        .map_err(|refusal| format!("{shown_path}: {}", refusal.rejection()))?;
    Ok(Some(String::from_utf8_lossy(&contents).into_owned()))
}

/// The largest image taken from a lab's written answers (1 MiB).
pub const MAX_ANSWER_IMAGE_BYTES: u64 = 1 << 20;

/// The most image bytes taken from one lab's written answers (4 MiB).
pub const MAX_ANSWER_IMAGES_BYTES: u64 = 4 << 20;

/// The deepest path, in components, an image of the answers may name.
const MAX_IMAGE_PATH_DEPTH: usize = 32;

/// What an image of the answers is, by its first bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageKind {
    /// A PNG file.
    Png,
    /// A JPEG file.
    Jpeg,
}

impl ImageKind {
    /// The file name extension the grader gives it.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Png => "png",
            Self::Jpeg => "jpg",
        }
    }
}

/// An image taken from a submission: its bytes as read, once.
#[derive(Debug)]
pub struct TakenImage {
    /// The file's contents.
    pub bytes: Vec<u8>,
    /// What it is.
    pub kind: ImageKind,
}

/// The path, relative to the submission, that `target` names in lab `lab`'s answers file:
/// resolved lexically from `labs/labNN/` (`.` and `..` by their names, never by the file
/// system). Refused, with why, when it is a URL or an absolute path, has control characters,
/// or leaves the submission.
pub fn answer_image_path(lab: LabId, target: &str) -> Result<PathBuf, String> {
    if target.is_empty() {
        return Err("no path".into());
    }
    if target.contains(':') || target.starts_with('/') || target.starts_with('\\') {
        return Err("not a path inside the submission (a URL or an absolute path)".into());
    }
    if target.chars().any(char::is_control) || target.contains(['?', '#', '\\']) {
        return Err("a path with characters the grader does not take".into());
    }
    let folder = lab.to_string();
    let mut resolved: Vec<&str> = vec!["labs", &folder];
    for part in target.split('/') {
        match part {
            "" | "." => {}
            ".." => {
                if resolved.pop().is_none() {
                    return Err("a path that leaves the submission".into());
                }
            }
            name => resolved.push(name),
        }
        if resolved.len() > MAX_IMAGE_PATH_DEPTH {
            return Err(format!("a path over {MAX_IMAGE_PATH_DEPTH} levels deep"));
        }
    }
    if resolved.is_empty() || target.ends_with('/') {
        return Err("not a file".into());
    }
    Ok(resolved.iter().collect())
}

/// The image at `relative` (a path [`answer_image_path`] gave) in `submission`, at most `limit`
/// bytes: a regular file under real directories (no symbolic link followed, nothing else
/// opened), refused past the limit before it is read, and a PNG or JPEG by its signature whose
/// header gives a size of at most [`course::answers::MAX_SIDE`] on each side.
pub fn read_answer_image(
    submission: &Path,
    relative: &Path,
    limit: u64,
) -> Result<TakenImage, String> {
    let parent = relative.parent().unwrap_or(Path::new(""));
    if !parent.as_os_str().is_empty() {
        real_dir(submission, parent)
            .map_err(|line| line.unwrap_or_else(|| "not in the submission".into()))?;
    }
    let path = submission.join(relative);
    match fs::symlink_metadata(&path) {
        Err(err) if err.kind() == ErrorKind::NotFound => {
            return Err("not in the submission".into());
        }
        Ok(meta) if meta.file_type().is_file() && meta.len() > limit => {
            return Err(format!(
                "{}, over the {} limit of an image (not read)",
                bytes(meta.len()),
                bytes(limit)
            ));
        }
        _ => {}
    }
    let contents = read_regular(&path, limit).map_err(|refusal| match refusal {
        Refusal::TooLarge(_) => format!("over the {} limit of an image", bytes(limit)),
        other => other.rejection(),
    })?;
    let (kind, _) = image_header(&contents)?;
    Ok(TakenImage {
        bytes: contents,
        kind,
    })
}

/// What `bytes` are by their signature, and the size their header gives: a PNG (its `IHDR`)
/// or a JPEG (its first start-of-frame), within [`course::answers::MAX_SIDE`] on each side.
pub fn image_header(bytes: &[u8]) -> Result<(ImageKind, (u32, u32)), String> {
    const PNG: &[u8] = b"\x89PNG\r\n\x1a\n";
    let be16 = |at: usize| {
        bytes
            .get(at..at + 2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]))
    };
    let be32 = |at: usize| {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_be_bytes([b[0], b[1], b[2], b[3]]))
    };
    let (kind, size) = if bytes.starts_with(PNG) {
        match (bytes.get(12..16), be32(16), be32(20)) {
            (Some(b"IHDR"), Some(w), Some(h)) => (ImageKind::Png, (w, h)),
            _ => return Err("a PNG without its header (not taken)".into()),
        }
    } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        let mut at = 2;
        let size = loop {
            // Markers, each 0xFF (fill bytes 0xFF allowed) and a code; all but a few carry a
            // length that the scan skips.
            let Some(&0xFF) = bytes.get(at) else {
                break None;
            };
            while bytes.get(at + 1) == Some(&0xFF) {
                at += 1;
            }
            let Some(&code) = bytes.get(at + 1) else {
                break None;
            };
            match code {
                0xD8 | 0x01 | 0xD0..=0xD7 => at += 2,
                0xD9 | 0xDA => break None,
                0xC0..=0xCF if ![0xC4, 0xC8, 0xCC].contains(&code) => {
                    break be16(at + 5)
                        .zip(be16(at + 7))
                        .map(|(h, w)| (u32::from(w), u32::from(h)));
                }
                _ => match be16(at + 2) {
                    Some(length) if length >= 2 => at += 2 + usize::from(length),
                    _ => break None,
                },
            }
        };
        match size {
            Some(size) => (ImageKind::Jpeg, size),
            None => return Err("a JPEG without a frame header (not taken)".into()),
        }
    } else {
        return Err("not a PNG or JPEG file by its contents (not taken)".into());
    };
    let side = course::answers::MAX_SIDE;
    if size.0 == 0 || size.1 == 0 || size.0 > side || size.1 > side {
        return Err(format!(
            "{}×{} pixels, outside the 1 to {side} pixels of a side that the grader takes",
            size.0, size.1
        ));
    }
    Ok((kind, size))
}

/// Whether `path` (relative to the tree) is in a lab's folder of figures for its written
/// answers, `labs/labNN/figures/`: the student's own, never a change.
fn is_answer_figure(path: &Path) -> bool {
    let parts: Vec<_> = path.components().map(|c| c.as_os_str()).collect();
    parts.len() >= 4
        && parts[0] == "labs"
        && parts[1].to_string_lossy().starts_with("lab")
        && parts[1] != "raylab"
        && parts[2] == course::answers::FIGURES
}

/// Whether `parts` are `labs`, `labNN`, `src`: a lab's code directory.
fn is_lab_src(parts: &[&OsStr]) -> bool {
    parts.len() == 3
        && parts[0] == "labs"
        && parts[1].to_string_lossy().starts_with("lab")
        && parts[1] != "raylab"
        && parts[2] == "src"
}

/// An entry of a tree other than a directory that was listed, for [`changed_files`].
#[derive(Debug)]
enum Entry {
    /// A regular file of this size.
    File(u64),
    /// Something not read: what it is or why (`a FIFO, not read`).
    NotRead(String),
    /// A directory whose contents are not known: why (`cannot be listed: …`).
    NotListed(String),
}

/// The entries of a tree, leaving out [`SKIPPED`] directories and the labs' code.
#[derive(Default)]
struct Listing {
    /// Every entry but the directories listed, by path relative to the tree.
    entries: BTreeMap<PathBuf, Entry>,
    /// Entries looked at so far.
    seen: usize,
    /// Whether the entry limit stopped the walk.
    stopped: bool,
}

impl Listing {
    /// Lists the tree `root`, looking at no more than `max_entries` entries, `max_depth` levels
    /// deep.
    fn of(root: &Path, max_entries: usize, max_depth: usize) -> Listing {
        let mut listing = Listing::default();
        listing.walk(root, Path::new(""), 1, max_entries, max_depth);
        listing
    }

    /// Lists the directory `root/relative`, whose entries are `depth` levels below `root`.
    fn walk(
        &mut self,
        root: &Path,
        relative: &Path,
        depth: usize,
        max_entries: usize,
        max_depth: usize,
    ) {
        let (entries, more) = match entries(&root.join(relative), max_entries - self.seen) {
            Ok(listed) => listed,
            Err(err) => {
                let note = format!("a directory that cannot be listed: {err}");
                self.entries
                    .insert(relative.to_path_buf(), Entry::NotListed(note));
                return;
            }
        };
        self.seen += entries.len();
        for entry in entries {
            let path = relative.join(entry.file_name());
            let listed = match entry.file_type() {
                Err(err) => Entry::NotRead(format!("cannot be read: {err}")),
                Ok(file_type) if file_type.is_dir() => {
                    let parts: Vec<_> = path.components().map(|c| c.as_os_str()).collect();
                    if is_lab_src(&parts) {
                        continue;
                    }
                    if depth >= max_depth {
                        Entry::NotListed(format!(
                            "a directory whose contents are more than {max_depth} levels deep, not compared"
                        ))
                    } else {
                        self.walk(root, &path, depth + 1, max_entries, max_depth);
                        if self.stopped {
                            return;
                        }
                        continue;
                    }
                }
                Ok(file_type) if file_type.is_file() => match entry.metadata() {
                    Ok(metadata) => Entry::File(metadata.len()),
                    Err(err) => Entry::NotRead(format!("cannot be read: {err}")),
                },
                Ok(file_type) if file_type.is_symlink() => Entry::NotRead(Refusal::Link.note()),
                Ok(file_type) => Entry::NotRead(Refusal::Special(kind(file_type)).note()),
            };
            self.entries.insert(path, listed);
        }
        self.stopped |= more;
    }

    /// Whether the tree has an entry at `path` or below it.
    fn has_at_or_below(&self, path: &Path) -> bool {
        self.entries.contains_key(path)
            || self
                .entries
                .range::<Path, _>((Bound::Excluded(path), Bound::Unbounded))
                .next()
                .is_some_and(|(p, _)| p.starts_with(path))
    }

    /// Whether `path` is below a directory whose contents are not known.
    fn is_below_unlisted(&self, path: &Path) -> bool {
        path.ancestors()
            .skip(1)
            .any(|a| matches!(self.entries.get(a), Some(Entry::NotListed(_))))
    }
}

/// The note of a `modified: P` line for a regular file of `submission` and one of `handout`
/// at the same place: `Some("")` when they differ, `Some(" (…)")` when they may differ, `None`
/// when they are the same.
///
/// Files are compared by content up to [`MAX_COMPARED_BYTES`]. Files of different sizes differ;
/// two files of the same size over the limit are listed as `modified: P (N bytes, not
/// compared)`, as they may differ.
fn compare(
    submission: &Path,
    handout: &Path,
    their_size: u64,
    our_size: u64,
) -> Result<Option<String>, Error> {
    if their_size != our_size {
        return Ok(Some(String::new()));
    }
    if their_size > MAX_COMPARED_BYTES {
        return Ok(Some(format!(" ({their_size} bytes, not compared)")));
    }
    let theirs = match read_regular(submission, MAX_COMPARED_BYTES) {
        Ok(contents) => contents,
        Err(refusal) => return Ok(Some(format!(" ({})", refusal.note()))),
    };
    let ours = fs::read(handout).map_err(io(handout))?;
    Ok((theirs != ours).then(String::new))
}

/// The files outside `labs/labNN/src/` in which `submission` differs from `handout`, as
/// `modified: P`, `added: P` and `removed: P` lines. They take no part in grading.
///
/// No symbolic link is followed and nothing but a regular file is read: other entries are
/// listed as `added: P (a symbolic link, not read)`, or `modified: P (…)` where the handout has
/// something. Problems reading the submission become such lines too. At most 20 000 entries
/// are looked at (beyond, one line `… comparison stopped after 20000 entries`, and no `removed`
/// lines as those are not known), 32 levels deep (a deeper directory is listed as not
/// compared). An `Err` is a failure to read the handout.
pub fn changed_files(submission: &Path, handout: &Path) -> Result<Vec<String>, Error> {
    let theirs = Listing::of(submission, MAX_COMPARED_ENTRIES, MAX_COMPARED_DEPTH);
    let ours = Listing::of(handout, usize::MAX, usize::MAX);
    let mut our_files = BTreeMap::new();
    for (path, entry) in &ours.entries {
        match entry {
            Entry::File(size) => our_files.insert(path.as_path(), *size),
            Entry::NotRead(why) | Entry::NotListed(why) => {
                return Err(Error::Failed {
                    what: format!("the handout's {}", handout.join(path).display()),
                    reason: why.clone(),
                });
            }
        };
    }
    let ignored = |p: &Path| {
        is_student_code(p)
            || is_written_answers(p)
            || is_answer_figure(p)
            || REGENERATED.iter().any(|r| p == Path::new(r))
    };
    let mut changes = Vec::new();
    for (path, entry) in theirs.entries.iter().filter(|(p, _)| !ignored(p)) {
        // The empty path is the submission itself, when it cannot be listed.
        let shown_path = if path.as_os_str().is_empty() {
            ".".to_string()
        } else {
            shown(path)
        };
        match (entry, our_files.get(path.as_path())) {
            (Entry::File(_), None) => changes.push(format!("added: {shown_path}")),
            (Entry::File(their_size), Some(our_size)) => {
                if let Some(note) = compare(
                    &submission.join(path),
                    &handout.join(path),
                    *their_size,
                    *our_size,
                )? {
                    changes.push(format!("modified: {shown_path}{note}"));
                }
            }
            (Entry::NotRead(why) | Entry::NotListed(why), _) => {
                let verb = if ours.has_at_or_below(path) {
                    "modified"
                } else {
                    "added"
                };
                changes.push(format!("{verb}: {shown_path} ({why})"));
            }
        }
    }
    if !theirs.stopped {
        for path in our_files.keys().filter(|p| !ignored(p)) {
            if !theirs.entries.contains_key(*path) && !theirs.is_below_unlisted(path) {
                changes.push(format!("removed: {}", shown(path)));
            }
        }
    } else {
        changes.push(format!(
            "… comparison stopped after {MAX_COMPARED_ENTRIES} entries"
        ));
    }
    Ok(changes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::symlink;
    use std::process::Command;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A new empty directory under the system's temporary directory, removed on drop.
    struct Scratch(PathBuf);

    impl Scratch {
        /// Creates a directory whose name no other test (or run) uses.
        fn new(name: &str) -> Scratch {
            static COUNT: AtomicUsize = AtomicUsize::new(0);
            let dir = std::env::temp_dir().join(format!(
                "raylab-intake-{name}-{}-{}",
                std::process::id(),
                COUNT.fetch_add(1, Ordering::Relaxed)
            ));
            fs::create_dir_all(&dir).unwrap();
            Scratch(dir)
        }

        /// Writes `contents` at `relative`, creating the directories above it.
        fn write(&self, relative: &str, contents: &[u8]) -> PathBuf {
            let path = self.0.join(relative);
            fs::create_dir_all(path.parent().unwrap()).unwrap();
            fs::write(&path, contents).unwrap();
            path
        }

        /// Creates the directory `relative`.
        fn dir(&self, relative: &str) -> PathBuf {
            let path = self.0.join(relative);
            fs::create_dir_all(&path).unwrap();
            path
        }

        /// Creates a symbolic link at `relative` pointing at `target`.
        fn link(&self, target: impl AsRef<Path>, relative: &str) {
            let path = self.0.join(relative);
            fs::create_dir_all(path.parent().unwrap()).unwrap();
            symlink(target, path).unwrap();
        }

        /// Creates a FIFO at `relative`.
        fn fifo(&self, relative: &str) {
            let status = Command::new("mkfifo")
                .arg(self.0.join(relative))
                .status()
                .unwrap();
            assert!(status.success());
        }
    }

    impl Drop for Scratch {
        fn drop(&mut self) {
            let _ = fs::remove_dir_all(&self.0);
        }
    }

    /// A handout with stubs for lab 2, a submission directory and a grading tree.
    fn setup(name: &str) -> (Scratch, Scratch, Scratch) {
        let handout = Scratch::new(&format!("{name}-handout"));
        handout.write("labs/lab02/src/lib.rs", b"// stub\n");
        handout.write("labs/lab02/tests/checks.rs", b"// checks\n");
        handout.write("Cargo.toml", b"[workspace]\n");
        let submission = Scratch::new(&format!("{name}-submission"));
        submission.write("Cargo.toml", b"[workspace]\n");
        submission.write("labs/lab02/tests/checks.rs", b"// checks\n");
        let tree = Scratch::new(&format!("{name}-tree"));
        tree.write("labs/lab02/src/old.rs", b"// from the last submission\n");
        (handout, submission, tree)
    }

    /// The files under `dir`, relative to it, with their contents.
    fn tree_files(dir: &Path) -> Vec<(String, Vec<u8>)> {
        let taken = Taken::from(dir, Path::new(""));
        assert!(taken.rejected.is_empty(), "{:?}", taken.rejected);
        taken
            .files
            .into_iter()
            .map(|(p, c)| (p.display().to_string(), c))
            .collect()
    }

    /// The first bytes of a PNG of `width` × `height` pixels: its signature and `IHDR`.
    fn png_header(width: u32, height: u32) -> Vec<u8> {
        let mut bytes = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR".to_vec();
        bytes.extend_from_slice(&width.to_be_bytes());
        bytes.extend_from_slice(&height.to_be_bytes());
        bytes.extend_from_slice(&[8, 2, 0, 0, 0]);
        bytes
    }

    #[test]
    fn answer_images_are_named_by_paths_inside_the_submission() {
        let lab = LabId::of(2);
        let resolved = |target| answer_image_path(lab, target);
        assert_eq!(
            resolved("figures/rays.png"),
            Ok(PathBuf::from("labs/lab02/figures/rays.png"))
        );
        assert_eq!(
            resolved("./figures/../../../out/report/lab02/a.png"),
            Ok(PathBuf::from("out/report/lab02/a.png"))
        );
        for refused in [
            "../../../etc/passwd",
            "../../..",
            "/etc/passwd",
            "https://example.org/a.png",
            "data:image/png;base64,AAAA",
            "figures/",
            "",
            "a\u{1b}[2J.png",
            "a.png?x",
        ] {
            assert!(resolved(refused).is_err(), "{refused:?}");
        }
        let deep = "a/".repeat(40) + "x.png";
        assert!(resolved(&deep).is_err());
    }

    #[test]
    fn answer_images_are_small_regular_png_or_jpeg_files() {
        let submission = Scratch::new("answer-images");
        let png = png_header(64, 48);
        submission.write("labs/lab02/figures/ok.png", &png);
        let mut jpeg = vec![0xFF, 0xD8, 0xFF, 0xE0, 0, 4, 0, 0];
        jpeg.extend_from_slice(&[0xFF, 0xC0, 0, 11, 8, 0, 30, 0, 40, 3, 0, 0]);
        submission.write("labs/lab02/figures/ok.jpg", &jpeg);
        submission.write("labs/lab02/figures/fake.png", b"<svg onload=alert(1)>");
        submission.write("labs/lab02/figures/huge.png", &png_header(100_000, 100_000));
        submission.write("labs/lab02/figures/empty.png", &png_header(0, 10));
        submission.write(
            "labs/lab02/figures/cut.jpg",
            &[0xFF, 0xD8, 0xFF, 0xE0, 0, 200],
        );
        let mut big = png.clone();
        big.resize(2 << 20, 0);
        submission.write("labs/lab02/figures/big.png", &big);
        let secret = submission.write("secret.png", &png);
        submission.link(&secret, "labs/lab02/figures/link.png");
        submission.link(submission.0.join("labs/lab02/figures"), "labs/lab02/linked");
        submission.fifo("labs/lab02/figures/pipe.png");
        let read = |relative: &str| {
            read_answer_image(&submission.0, Path::new(relative), MAX_ANSWER_IMAGE_BYTES)
        };
        let ok = read("labs/lab02/figures/ok.png").unwrap();
        assert_eq!((ok.kind, ok.bytes), (ImageKind::Png, png.clone()));
        assert_eq!(
            read("labs/lab02/figures/ok.jpg").unwrap().kind,
            ImageKind::Jpeg
        );
        assert_eq!(image_header(&jpeg), Ok((ImageKind::Jpeg, (40, 30))));
        assert_eq!(read("secret.png").unwrap().kind, ImageKind::Png);
        let refusals = [
            ("labs/lab02/figures/fake.png", "not a PNG or JPEG"),
            ("labs/lab02/figures/huge.png", "100000×100000 pixels"),
            ("labs/lab02/figures/empty.png", "0×10 pixels"),
            (
                "labs/lab02/figures/cut.jpg",
                "a JPEG without a frame header",
            ),
            ("labs/lab02/figures/big.png", "over the 1048576 bytes limit"),
            ("labs/lab02/figures/link.png", "a symbolic link"),
            ("labs/lab02/linked/ok.png", "a symbolic link"),
            ("labs/lab02/figures/pipe.png", "a FIFO"),
            ("labs/lab02/figures/none.png", "not in the submission"),
            ("labs/lab09/figures/ok.png", "not in the submission"),
        ];
        for (relative, why) in refusals {
            let refused = read(relative).map(|i| i.kind).unwrap_err();
            assert!(refused.contains(why), "{relative}: {refused}");
        }
        // A smaller budget (what is left of the lab's 4 MiB) refuses a file within 1 MiB.
        let refused = read_answer_image(&submission.0, Path::new("labs/lab02/figures/ok.png"), 10);
        assert!(refused.unwrap_err().contains("over the 10 bytes limit"));
    }

    #[test]
    fn a_lab_s_figures_for_its_answers_are_not_changes() {
        assert!(is_answer_figure(Path::new("labs/lab01/figures/rays.png")));
        assert!(!is_answer_figure(Path::new("labs/lab01/figures")));
        assert!(!is_answer_figure(Path::new("labs/raylab/figures/a.png")));
        assert!(!is_answer_figure(Path::new("docs/figures/a.png")));
    }

    #[test]
    fn only_lab_sources_are_student_code() {
        assert!(is_student_code(Path::new("labs/lab01/src/lib.rs")));
        assert!(is_student_code(Path::new("labs/lab07/src/extra/mod.rs")));
        assert!(!is_student_code(Path::new("labs/lab01/tests/checks.rs")));
        assert!(!is_student_code(Path::new(
            "labs/lab01/golden/camera_basis.json"
        )));
        assert!(!is_student_code(Path::new("labs/raylab/src/main.rs")));
        assert!(!is_student_code(Path::new("framework/src/lib.rs")));
        assert!(!is_student_code(Path::new("labs/lab01/Cargo.toml")));
        assert!(is_written_answers(Path::new("labs/lab01/answers.md")));
        assert!(!is_written_answers(Path::new("labs/raylab/answers.md")));
        assert!(!is_written_answers(Path::new("labs/lab01/src/answers.md")));
    }

    #[test]
    fn nested_regular_files_are_copied_exactly_as_plain_files() {
        let (handout, submission, tree) = setup("nested");
        let source = submission.write("labs/lab02/src/lib.rs", b"pub mod shapes;\n");
        fs::set_permissions(&source, fs::Permissions::from_mode(0o4755)).unwrap();
        submission.write("labs/lab02/src/shapes/mod.rs", b"mod sphere;\n");
        let bytes: Vec<u8> = (0..=255).collect();
        submission.write("labs/lab02/src/shapes/sphere/data.bin", &bytes);
        submission.dir("labs/lab02/src/empty");
        let intake =
            install_lab_code(Some(&submission.0), &handout.0, &tree.0, LabId::of(2)).unwrap();
        assert_eq!(intake, LabIntake::default());
        let src = tree.0.join("labs/lab02/src");
        assert_eq!(
            tree_files(&src),
            vec![
                ("lib.rs".to_string(), b"pub mod shapes;\n".to_vec()),
                ("shapes/mod.rs".to_string(), b"mod sphere;\n".to_vec()),
                ("shapes/sphere/data.bin".to_string(), bytes),
            ]
        );
        let mode = fs::metadata(src.join("lib.rs"))
            .unwrap()
            .permissions()
            .mode();
        assert_eq!(mode & 0o7777, 0o644);
    }

    #[test]
    fn links_and_special_files_are_rejected_not_followed() {
        let (handout, submission, tree) = setup("links");
        let key = handout.write("reference/src/lab02.rs", b"// the answer key\n");
        submission.write("labs/lab02/src/lib.rs", b"mod key;\n");
        submission.link(&key, "labs/lab02/src/key.rs");
        submission.link("nowhere.rs", "labs/lab02/src/dangling.rs");
        submission.link("b", "labs/lab02/src/a");
        submission.link("a", "labs/lab02/src/b");
        submission.link(handout.0.join("reference/src"), "labs/lab02/src/keys");
        submission.fifo("labs/lab02/src/pipe");
        let intake =
            install_lab_code(Some(&submission.0), &handout.0, &tree.0, LabId::of(2)).unwrap();
        assert_eq!(intake.missing, None);
        assert_eq!(
            intake.rejected,
            vec![
                "labs/lab02/src/a: a symbolic link (not followed)",
                "labs/lab02/src/b: a symbolic link (not followed)",
                "labs/lab02/src/dangling.rs: a symbolic link (not followed)",
                "labs/lab02/src/key.rs: a symbolic link (not followed)",
                "labs/lab02/src/keys: a symbolic link (not followed)",
                "labs/lab02/src/pipe: a FIFO (not read)",
            ]
        );
        assert_eq!(
            tree_files(&tree.0.join("labs/lab02/src")),
            vec![("lib.rs".to_string(), b"mod key;\n".to_vec())]
        );
    }

    #[test]
    fn a_symlinked_src_is_missing_and_rejected() {
        let (handout, submission, tree) = setup("src-link");
        let elsewhere = handout.write("reference/src/lib.rs", b"// the answer key\n");
        submission.dir("labs/lab02");
        submission.link(elsewhere.parent().unwrap(), "labs/lab02/src");
        let intake =
            install_lab_code(Some(&submission.0), &handout.0, &tree.0, LabId::of(2)).unwrap();
        assert_eq!(
            intake.missing.as_deref(),
            Some("labs/lab02/src/ is missing: graded as the handout's stubs")
        );
        assert_eq!(
            intake.rejected,
            vec!["labs/lab02/src: a symbolic link (not followed)"]
        );
        assert_eq!(
            tree_files(&tree.0.join("labs/lab02/src")),
            vec![("lib.rs".to_string(), b"// stub\n".to_vec())]
        );

        // A link higher up is not followed either.
        let (handout, submission, tree) = setup("labs-link");
        handout.write("elsewhere/lab02/src/lib.rs", b"// the answer key\n");
        fs::remove_dir_all(submission.0.join("labs")).unwrap();
        submission.link(handout.0.join("elsewhere"), "labs");
        let intake =
            install_lab_code(Some(&submission.0), &handout.0, &tree.0, LabId::of(2)).unwrap();
        assert!(intake.missing.is_some());
        assert_eq!(
            intake.rejected,
            vec!["labs: a symbolic link (not followed)"]
        );
    }

    #[test]
    fn an_unreadable_file_is_rejected() {
        let (handout, submission, tree) = setup("unreadable");
        submission.write("labs/lab02/src/lib.rs", b"// ok\n");
        let locked = submission.write("labs/lab02/src/locked.rs", b"// locked\n");
        fs::set_permissions(&locked, fs::Permissions::from_mode(0o000)).unwrap();
        // Permissions do not stop root: then the file is copied as usual.
        let enforced = fs::File::open(&locked).is_err();
        let intake =
            install_lab_code(Some(&submission.0), &handout.0, &tree.0, LabId::of(2)).unwrap();
        let names: Vec<_> = tree_files(&tree.0.join("labs/lab02/src"))
            .into_iter()
            .map(|(p, _)| p)
            .collect();
        if enforced {
            assert_eq!(
                intake.rejected,
                vec!["labs/lab02/src/locked.rs: cannot be read: Permission denied (os error 13)"]
            );
            assert_eq!(names, ["lib.rs"]);
        } else {
            assert!(intake.rejected.is_empty());
            assert_eq!(names, ["lib.rs", "locked.rs"]);
        }
    }

    #[test]
    fn a_missing_src_installs_the_stubs_without_a_rejection() {
        let (handout, submission, tree) = setup("missing");
        let intake =
            install_lab_code(Some(&submission.0), &handout.0, &tree.0, LabId::of(2)).unwrap();
        assert!(intake.missing.is_some());
        assert!(intake.rejected.is_empty());
        assert_eq!(
            tree_files(&tree.0.join("labs/lab02/src")),
            vec![("lib.rs".to_string(), b"// stub\n".to_vec())]
        );
    }

    #[test]
    fn limits_are_enforced() {
        let (handout, submission, tree) = setup("limits");
        submission.write("labs/lab02/src/lib.rs", b"// ok\n");
        let big = submission.write("labs/lab02/src/big.rs", b"");
        fs::File::options()
            .write(true)
            .open(&big)
            .unwrap()
            .set_len(3_355_443)
            .unwrap();
        submission.write("labs/lab02/src/edge.rs", &vec![b' '; (1 << 20) + 1]);
        submission.write("labs/lab02/src/a/b/c/d/e/f/g/deep.rs", b"// level 8\n");
        submission.write("labs/lab02/src/a/b/c/d/e/f/g/h/deeper.rs", b"// level 9\n");
        submission.write("labs/lab02/src/bad\u{1b}[2Jname.rs", b"");
        let intake =
            install_lab_code(Some(&submission.0), &handout.0, &tree.0, LabId::of(2)).unwrap();
        assert_eq!(
            intake.rejected,
            vec![
                "labs/lab02/src/a/b/c/d/e/f/g/h: a directory whose contents are more than 8 levels deep (not copied)",
                "labs/lab02/src/bad\\u{1b}[2Jname.rs: a name with control characters (not copied)",
                "labs/lab02/src/big.rs: 3.2 MiB, over the 1 MiB limit for one file",
                "labs/lab02/src/edge.rs: 1048577 bytes, over the 1 MiB limit for one file",
            ]
        );
        let files = tree_files(&tree.0.join("labs/lab02/src"));
        let names: Vec<_> = files.iter().map(|(p, _)| p.as_str()).collect();
        assert_eq!(names, ["a/b/c/d/e/f/g/deep.rs", "lib.rs"]);
    }

    #[test]
    fn a_lab_is_limited_in_entries_and_bytes() {
        let (handout, submission, tree) = setup("many");
        for i in 0..300 {
            submission.write(&format!("labs/lab02/src/f{i:03}.rs"), b"//\n");
        }
        let intake =
            install_lab_code(Some(&submission.0), &handout.0, &tree.0, LabId::of(2)).unwrap();
        assert_eq!(
            intake.rejected,
            vec!["labs/lab02/src: more than 256 entries, the rest is not copied"]
        );
        assert_eq!(tree_files(&tree.0.join("labs/lab02/src")).len(), 256);

        let (handout, submission, tree) = setup("heavy");
        for i in 0..10 {
            submission.write(&format!("labs/lab02/src/f{i}.bin"), &vec![0; 1 << 20]);
        }
        let intake =
            install_lab_code(Some(&submission.0), &handout.0, &tree.0, LabId::of(2)).unwrap();
        assert_eq!(
            intake.rejected,
            vec![
                "labs/lab02/src/f8.bin: 1048576 bytes, over the 8 MiB limit for one lab's files in total (not copied)",
                "labs/lab02/src/f9.bin: 1048576 bytes, over the 8 MiB limit for one lab's files in total (not copied)",
            ]
        );
        assert_eq!(tree_files(&tree.0.join("labs/lab02/src")).len(), 8);
    }

    #[test]
    fn reading_refuses_what_is_not_a_small_regular_file() {
        let scratch = Scratch::new("read");
        let file = scratch.write("file", b"12345");
        assert_eq!(read_regular(&file, 5).unwrap(), b"12345");
        assert!(matches!(
            read_regular(&file, 4),
            Err(Refusal::TooLarge(Some(5)))
        ));
        scratch.link(&file, "link");
        assert!(matches!(
            read_regular(&scratch.0.join("link"), 5),
            Err(Refusal::Link)
        ));
        scratch.fifo("fifo");
        assert!(matches!(
            read_regular(&scratch.0.join("fifo"), 5),
            Err(Refusal::Special("a FIFO"))
        ));
        assert!(matches!(
            read_regular(&scratch.0.join("nothing"), 5),
            Err(Refusal::Unreadable(_))
        ));
    }

    #[test]
    fn changed_files_lists_what_it_does_not_read_and_terminates() {
        let (handout, submission, _tree) = setup("changed");
        handout.write("README.md", b"read me\n");
        handout.write("docs/guide.md", b"guide\n");
        handout.write("framework/src/lib.rs", b"// framework\n");
        handout.write("labs/lab02/golden/a.json", b"{}\n");
        let key = handout.write("reference/src/lab02.rs", b"// key\n");
        submission.write("Cargo.lock", b"# regenerated\n");
        submission.write("README.md", b"read me too\n");
        submission.write("labs/lab02/src/lib.rs", b"// not compared\n");
        submission.link(&key, "labs/lab02/src/key.rs");
        submission.write("target/debug/huge", b"skipped");
        submission.link(&key, "key.rs");
        submission.link("nowhere", "dangling");
        submission.link("loop-b", "loop-a");
        submission.link("loop-a", "loop-b");
        submission.link(handout.0.join("framework"), "framework");
        submission.link(&key, "labs/lab02/golden/a.json");
        submission.fifo("pipe");
        submission.write("docs/guide.md", &vec![b'x'; (1 << 20) + 10]);
        submission.write(
            "deep/a/b/c/d/e/f/g/h/i/j/k/l/m/n/o/p/q/r/s/t/u/v/w/x/y/z/0/1/2/3/4/5/6/f",
            b"",
        );
        let changes = changed_files(&submission.0, &handout.0).unwrap();
        assert_eq!(
            changes,
            vec![
                "modified: README.md",
                "added: dangling (a symbolic link, not read)",
                "added: deep/a/b/c/d/e/f/g/h/i/j/k/l/m/n/o/p/q/r/s/t/u/v/w/x/y/z/0/1/2/3/4 (a directory whose contents are more than 32 levels deep, not compared)",
                "modified: docs/guide.md",
                "modified: framework (a symbolic link, not read)",
                "added: key.rs (a symbolic link, not read)",
                "modified: labs/lab02/golden/a.json (a symbolic link, not read)",
                "added: loop-a (a symbolic link, not read)",
                "added: loop-b (a symbolic link, not read)",
                "added: pipe (a FIFO, not read)",
                "removed: framework/src/lib.rs",
                "removed: reference/src/lab02.rs",
            ]
        );
    }

    #[test]
    fn changed_files_compares_contents_and_reports_unreadable_files() {
        let (handout, submission, _tree) = setup("contents");
        handout.write("same.txt", b"same\n");
        handout.write("size.txt", b"abc\n");
        handout.write("big.bin", &vec![0; (8 << 20) + 1]);
        handout.write("probe.exr", &vec![0; (1 << 20) + 1]);
        submission.write("same.txt", b"same\n");
        submission.write("size.txt", b"abd\n");
        submission.write("big.bin", &vec![1; (8 << 20) + 1]);
        submission.write("probe.exr", &vec![0; (1 << 20) + 1]);
        let locked = submission.dir("locked");
        submission.write("locked/secret.txt", b"");
        fs::set_permissions(&locked, fs::Permissions::from_mode(0o000)).unwrap();
        // Permissions do not stop root: then the directory is listed as usual.
        let enforced = fs::read_dir(&locked).is_err();
        let changes = changed_files(&submission.0, &handout.0);
        fs::set_permissions(&locked, fs::Permissions::from_mode(0o755)).unwrap();
        // Over 1 MiB but unchanged: not listed.
        let mut expected = vec!["modified: big.bin (8388609 bytes, not compared)"];
        expected.push(if enforced {
            "added: locked (a directory that cannot be listed: Permission denied (os error 13))"
        } else {
            "added: locked/secret.txt"
        });
        expected.push("modified: size.txt");
        assert_eq!(changes.unwrap(), expected);
    }

    #[test]
    fn changed_files_stops_after_its_entry_limit() {
        let (handout, submission, _tree) = setup("stopped");
        handout.write("kept.txt", b"");
        let many = submission.dir("many");
        for i in 0..MAX_COMPARED_ENTRIES {
            fs::File::create(many.join(format!("{i}"))).unwrap();
        }
        let changes = changed_files(&submission.0, &handout.0).unwrap();
        assert_eq!(
            changes.last().map(String::as_str),
            Some("… comparison stopped after 20000 entries")
        );
        assert!(!changes.iter().any(|c| c.starts_with("removed:")));
    }
}
