use std::path::PathBuf;

/// Everything that can go wrong running areo, with the file and position it concerns.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The file is not valid RON for its format (bad syntax, an unknown or missing
    /// field, a value of the wrong type).
    #[error("{path}:{line}:{col}: {message}")]
    Syntax {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        col: usize,
        /// What the parser expected.
        message: String,
    },
    /// A value is out of its allowed range.
    #[error("{path}:{line}:{col}: field `{field}`: {message}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// 1-based line of the field.
        line: usize,
        /// 1-based column of the field.
        col: usize,
        /// Dotted path of the field, e.g. `job.site.lat_deg`.
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A grid benchmark file (Moving AI `.map` or `.scen`) is malformed.
    #[error("{path}: {message}")]
    Grid {
        /// The file.
        path: PathBuf,
        /// What is wrong, with the line where known.
        message: String,
    },
    /// A DEM could not be read, written or built.
    #[error(transparent)]
    Terrain(#[from] areo_terrain::Error),
    /// An ephemeris computation refused its input.
    #[error(transparent)]
    Ephemeris(#[from] areo_ephemeris::Error),
    /// A rover parameter file could not be read or is invalid.
    #[error(transparent)]
    Rover(#[from] areo_rover::Error),
    /// A command-line value is out of range.
    #[error("{0}")]
    Usage(String),
    /// A scenario value is inconsistent with the rest (a goal off the map, …).
    #[error("{path}: field `{field}`: {message}")]
    Scenario {
        /// The scenario file.
        path: PathBuf,
        /// Dotted path of the field.
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A planner input is out of range or the planner failed.
    #[error(transparent)]
    Mission(#[from] areo_mission::Error),
    /// The mission's goals cannot be reached: the binding constraint. Outputs written
    /// so far are kept.
    #[error("{0}")]
    Unreachable(String),
}

impl Error {
    /// The process exit code for this error: 2 for bad input, 3 for an unreachable
    /// goal, 1 otherwise.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Syntax { .. } | Error::Invalid { .. } | Error::Grid { .. } | Error::Ephemeris(_) => 2,
            Error::Terrain(areo_terrain::Error::Io { .. }) => 1,
            Error::Terrain(_) => 2,
            Error::Io { .. } => 1,
            Error::Rover(areo_rover::Error::Io { .. }) => 1,
            Error::Rover(_) | Error::Usage(_) | Error::Scenario { .. } => 2,
            Error::Mission(areo_mission::Error::Unreachable { .. }) | Error::Unreachable(_) => 3,
            Error::Mission(_) => 2,
        }
    }
}

/// `Result` with this crate's [`enum@Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
