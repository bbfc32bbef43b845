use std::path::PathBuf;

/// Everything that can go wrong in areo-terrain.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// An input file could not be read (missing, unreadable, not UTF-8 where text is
    /// needed): bad input.
    #[error("{path}: cannot read: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// An output file could not be written (a full disk, no permission): a failure while
    /// running.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A file is not a valid DEM of its format.
    #[error("{path}: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
    /// A file's format cannot be told from its name.
    #[error("{path}: {message}")]
    UnknownFormat {
        /// The file.
        path: PathBuf,
        /// What is wrong and which formats are read.
        message: String,
    },
    /// Grid dimensions or cell sizes that cannot describe a DEM.
    #[error("invalid grid: {0}")]
    BadGrid(String),
    /// A terrain description with a value out of range.
    #[error("terrain description: `{field}` = {value} is out of range: allowed {allowed}")]
    BadSynth {
        /// The field, e.g. `craters[1].radius_m`.
        field: String,
        /// The value given.
        value: f64,
        /// The allowed range in words.
        allowed: &'static str,
    },
}

/// `Result` with this crate's [`enum@Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// The file the error is about, if it is about one.
    pub fn path(&self) -> Option<&std::path::Path> {
        match self {
            Error::Read { path, .. }
            | Error::Io { path, .. }
            | Error::Format { path, .. }
            | Error::UnknownFormat { path, .. } => Some(path),
            Error::BadGrid(_) | Error::BadSynth { .. } => None,
        }
    }

    pub(crate) fn format(path: &std::path::Path, message: impl Into<String>) -> Error {
        Error::Format { path: path.to_path_buf(), message: message.into() }
    }
}
