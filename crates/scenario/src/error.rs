use std::path::PathBuf;

use crate::outcome::Failure;

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
    /// The run finished but did not achieve its aim (unreachable goals, a benchmark's
    /// known optimum missed). Outputs written so far are kept.
    #[error("{0}")]
    Failed(Failure),
    /// A job needs more memory or work than it is allowed (see `budget`).
    #[error("{}", crate::budget::refusal(estimate, limit))]
    Budget {
        /// What the job would need.
        estimate: crate::budget::Estimate,
        /// What it is allowed.
        limit: crate::budget::Budget,
    },
    /// A planning call of the job reached the work budget before it had an answer
    /// (the searches stop there; see `areo_mission::PlannerConfig::max_expansions`).
    #[error(
        "{}: the TEMPEST searches stopped after the work of {expansions} label expansions (long Pareto fronts' comparisons included), as much as the work budget allows one planning call (raise it with --max-work): no plan, and no proof that none exists",
        path.display()
    )]
    WorkSpent {
        /// The scenario.
        path: PathBuf,
        /// Work the call did, in expansions (`areo_mission::ExpansionMeter::work`).
        expansions: u64,
    },
    /// A TEMPEST planning call's search graphs reached what the memory budget leaves
    /// them beside the worlds (see `areo_mission::PlannerConfig::max_search_bytes`).
    #[error(
        "{}: the TEMPEST searches stopped when their graphs held {:.2} GiB, all the memory budget leaves them beside the worlds ({:.2} GiB; raise it with --max-memory-gb, or search at wider time classes, `job.planner.resolution.time_s`): no plan, and no proof that none exists",
        path.display(),
        *bytes as f64 / (1u64 << 30) as f64,
        *limit as f64 / (1u64 << 30) as f64
    )]
    MemorySpent {
        /// The scenario.
        path: PathBuf,
        /// Bytes the graphs held.
        bytes: u64,
        /// What the budget left them, bytes.
        limit: u64,
    },
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
    /// A command-line value (or an environment variable standing for one) is out of
    /// range or inconsistent with the others.
    #[error("{what}: {message}")]
    Usage {
        /// The flag or variable with its value, e.g. `--mu -1`.
        what: String,
        /// What is wrong and what is allowed.
        message: String,
    },
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
    /// The GA action planner refused its input.
    #[error(transparent)]
    Actions(#[from] areo_actions::Error),
}

impl Error {
    /// The process exit code for this error: 2 for bad input, 3 for an unreachable
    /// goal, 4 for searches stopped by the work or memory budget before they had an
    /// answer (neither a plan nor a proof: raise the budget), 1 otherwise. The only
    /// place exit codes are decided.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Syntax { .. } | Error::Invalid { .. } | Error::Grid { .. } | Error::Ephemeris(_) => 2,
            // Refused before it starts: the job as written asks for more than allowed.
            Error::Read { .. } | Error::Budget { .. } => 2,
            Error::WorkSpent { .. } | Error::MemorySpent { .. } | Error::Failed(Failure::Stopped { .. }) => 4,
            Error::Mission(areo_mission::Error::WorkLimit { .. } | areo_mission::Error::MemoryLimit { .. }) => 4,
            // A referenced file that cannot be read or used is bad input, whatever the
            // cause; only an output that cannot be written is a failure while running.
            Error::Referenced { source, .. } => match source.exit_code() {
                1 => 2,
                code => code,
            },
            Error::Terrain(areo_terrain::Error::Io { .. }) => 1,
            Error::Terrain(_) => 2,
            Error::Io { .. } | Error::Failed(Failure::Mismatched { .. }) => 1,
            // areo-rover only reads (its parameter files).
            Error::Rover(_) | Error::Usage { .. } | Error::Scenario { .. } | Error::Actions(_) => 2,
            Error::Mission(areo_mission::Error::Unreachable { .. })
            | Error::Failed(Failure::Unreachable { .. } | Failure::NoPath { .. }) => 3,
            Error::Mission(_) => 2,
        }
    }

    /// A command-line value that is out of range: `what` names the flag and its value.
    pub fn usage(what: impl Into<String>, message: impl Into<String>) -> Error {
        Error::Usage { what: what.into(), message: message.into() }
    }

    /// This error as the failure to use the file that `field` of scenario `path` names.
    pub(crate) fn referenced_by(self, path: &std::path::Path, field: &str) -> Error {
        Error::Referenced { path: path.to_path_buf(), field: field.to_string(), source: Box::new(self) }
    }
}

/// `Result` with this crate's [`enum@Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::budget::{Budget, Estimate};

    #[test]
    fn typed_failures_reach_their_exit_codes_and_read_as_before() {
        let unreachable = Error::Failed(Failure::Unreachable {
            binding: areo_mission::Binding::Battery,
            message: "the battery".into(),
            after_actions: Some(7),
        });
        assert_eq!(unreachable.exit_code(), 3);
        assert_eq!(unreachable.to_string(), "goal unreachable after 7 actions: binding constraint: the battery");
        assert_eq!(Error::Failed(Failure::NoPath { unreachable: 1, scenarios: 4 }).exit_code(), 3);
        let mismatched = Error::Failed(Failure::Mismatched { mismatched: 2, scenarios: 4 });
        assert_eq!((mismatched.exit_code(), mismatched.to_string().as_str()), (1, "2 of 4 scenarios mismatched"));
        let usage = Error::usage("--mu -1", "must be positive and finite");
        assert_eq!((usage.exit_code(), usage.to_string().as_str()), (2, "--mu -1: must be positive and finite"));

        let estimate =
            Estimate { what: "the job".into(), memory_bytes: 3 << 30, work_steps: 10, work_unit: "cell-sector rays" };
        let memory = Budget { memory_bytes: 1 << 30, work_steps: 100 }.check(&estimate).unwrap_err();
        assert_eq!(memory.exit_code(), 2);
        // Stopped while searching: its own code, neither bad input nor a verdict.
        let spent = Error::WorkSpent { path: "job.ron".into(), expansions: 10 };
        assert_eq!(spent.exit_code(), 4);
        let held = Error::MemorySpent { path: "job.ron".into(), bytes: 2, limit: 1 };
        assert_eq!(held.exit_code(), 4);
        assert_eq!(Error::Mission(areo_mission::Error::WorkLimit { expansions: 3, limit: 2 }).exit_code(), 4);
        assert_eq!(Error::Failed(Failure::Stopped { message: "stopped".into() }).exit_code(), 4);
        assert_eq!(
            memory.to_string(),
            "the job needs about 3.00 GiB of memory, more than the 1.00 GiB allowed (raise it with --max-memory-gb)"
        );
        let work = Budget { memory_bytes: 4 << 30, work_steps: 5 }.check(&estimate).unwrap_err();
        assert!(matches!(&work, Error::Budget { limit, .. } if limit.work_steps == 5));
        assert!(work.to_string().contains("1.00e1 steps of work (cell-sector rays), more than the 5.00e0 allowed"));
        assert!(Budget { memory_bytes: 4 << 30, work_steps: 10 }.check(&estimate).is_ok());
    }
}
