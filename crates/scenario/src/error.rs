use std::path::PathBuf;

/// Everything that can go wrong running areo, with the file and position it concerns.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// An input file could not be read (missing, unreadable, not UTF-8): bad input.
    #[error("{path}: cannot read: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A file that a scenario field names (a DEM, a rover file) could not be used.
    #[error("{path}: field `{field}`: {source}")]
    Referenced {
        /// The scenario file.
        path: PathBuf,
        /// Dotted path of the field that names the file.
        field: String,
        /// What went wrong with the file.
        source: Box<Error>,
    },
    /// The run finished but its answer is wrong (a benchmark's known optimum missed).
    #[error("{0}")]
    Failed(String),
    /// A job needs more memory or work than it is allowed (see `budget`).
    #[error("{0}")]
    Budget(String),
    /// An output file could not be written (a full disk, no permission): a failure
    /// while running.
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
            Error::Read { .. } | Error::Budget(_) => 2,
            // A referenced file that cannot be read or used is bad input, whatever the
            // cause; only an output that cannot be written is a failure while running.
            Error::Referenced { source, .. } => match source.exit_code() {
                1 => 2,
                code => code,
            },
            Error::Terrain(areo_terrain::Error::Io { .. }) => 1,
            Error::Terrain(_) => 2,
            Error::Io { .. } | Error::Failed(_) => 1,
            // areo-rover only reads (its parameter files).
            Error::Rover(_) | Error::Usage(_) | Error::Scenario { .. } => 2,
            Error::Mission(areo_mission::Error::Unreachable { .. }) | Error::Unreachable(_) => 3,
            Error::Mission(_) => 2,
        }
    }

    /// This error as the failure to use the file that `field` of scenario `path` names.
    pub fn referenced_by(self, path: &std::path::Path, field: &str) -> Error {
        Error::Referenced { path: path.to_path_buf(), field: field.to_string(), source: Box::new(self) }
    }
}

/// `Result` with this crate's [`enum@Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
