use std::path::PathBuf;

/// Everything that can go wrong outside student code. Every message names the file, line or
/// value at fault and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// A malformed OBJ or MTL file.
    #[error("{path}:{line}: {reason}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number (0 when the fault is not tied to a line).
        line: usize,
        /// What was found and what was expected.
        reason: String,
    },
    /// A malformed scene file.
    #[error("{path}: {reason}")]
    SceneFile {
        /// The file.
        path: PathBuf,
        /// What was found and what was expected (with line and column when known).
        reason: String,
    },
    /// A texture (or a light probe) that cannot be read or decoded.
    #[error("{path}: cannot read {}: {reason}", .named_by.as_deref().unwrap_or("the texture"))]
    Texture {
        /// The image file.
        path: PathBuf,
        /// What names the file, with its place: "the texture of materials.floor at scene.toml,
        /// line 8, column 1" (`None`: the file was loaded directly).
        named_by: Option<String>,
        /// Why it cannot be read: the operating system's or the decoder's reason, in words.
        reason: String,
    },
    /// An image that cannot be read or decoded (a reference snapshot, say).
    #[error("{path}: cannot read the image: {reason}")]
    Image {
        /// The image file.
        path: PathBuf,
        /// Why it cannot be read: the operating system's or the decoder's reason, in words.
        reason: String,
    },
    /// A scene that is syntactically fine but cannot be rendered.
    #[error("scene '{scene}': {reason}")]
    Scene {
        /// The scene's name.
        scene: String,
        /// What is wrong and what was expected.
        reason: String,
    },
    /// A bad option or argument value: `what` names the value ("--width 0", "lab 99"), so
    /// that the message reads "invalid --width 0: …". A step that cannot be done is
    /// [`Error::Failed`].
    #[error("invalid {what}: {reason}")]
    Invalid {
        /// Which option or value.
        what: String,
        /// What was expected.
        reason: String,
    },
    /// A step that could not be done (a build, a command the step runs), and why.
    #[error("{what}: {reason}")]
    Failed {
        /// The step.
        what: String,
        /// Why it could not be done.
        reason: String,
    },
    /// A component panicked while rendering.
    #[error(transparent)]
    Panic(#[from] PanicError),
    /// An image could not be encoded or written.
    #[error("{path}: cannot write image: {reason}")]
    ImageOutput {
        /// The output file.
        path: PathBuf,
        /// The encoder's complaint.
        reason: String,
    },
}

impl Error {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}

/// A panic inside a component (student code, typically), turned into an error so that one
/// broken exercise does not bring down a whole run.
#[derive(Debug, thiserror::Error)]
#[error("{context} panicked: {message}")]
pub struct PanicError {
    /// What was running.
    pub context: String,
    /// The panic message (for an unfinished stub, "not yet implemented: Exercise …").
    pub message: String,
}
