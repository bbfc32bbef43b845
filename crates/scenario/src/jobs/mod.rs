//! One module per job: each computes a typed report from its part of the scenario,
//! turns it into facts and summary lines ([`Outcome`]) and writes its files. [`run`]
//! dispatches on the scenario's job.

pub mod actions;
pub mod sun_table;
pub mod tempest;
pub mod terrain_shadow;

use std::path::Path;

use crate::error::{Error, Result};
use crate::format::{Job, ScenarioFile};
use crate::outcome::Outcome;
use crate::output::{json_for, write_file};
use crate::progress::Progress;

/// How to run a job.
#[derive(Clone, Copy)]
pub struct RunOptions<'a> {
    /// Where to write output files (`None`: write nothing).
    pub out_dir: Option<&'a Path>,
    /// Where to report progress.
    pub progress: &'a dyn Progress,
}

impl std::fmt::Debug for RunOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RunOptions").field("out_dir", &self.out_dir).finish_non_exhaustive()
    }
}

/// Runs the scenario's job; writes its files into `opts.out_dir` if given.
pub fn run(file: &ScenarioFile, opts: RunOptions<'_>) -> Result<Outcome> {
    if let Some(dir) = opts.out_dir {
        std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.to_path_buf(), source })?;
    }
    let mut outcome = match &file.scenario.job {
        Job::SunTable(job) => sun_table::run(job, opts)?,
        Job::TerrainShadow(job) => terrain_shadow::run(job, file, opts)?,
        Job::Tempest(job) => tempest::run(job, file, opts)?,
        Job::Actions(job) => actions::run(job, file, opts)?,
    };
    if let Some(dir) = opts.out_dir {
        let path = dir.join("facts.json");
        let json = json_for(&path, &outcome.facts, true)?;
        write_file(&path, json.as_bytes())?;
        outcome.files.push(path);
    }
    Ok(outcome)
}
