//! One module per job: each computes its public plain-data [`Report`] from its part of
//! the scenario, and [`run`] dispatches on the scenario's job. Every job's facts are read
//! off its report's fields, and its summary, files and plots are written from the
//! report alone (`output::reports`).

pub mod actions;
pub(crate) mod sun_table;
pub(crate) mod tempest;
pub(crate) mod terrain_shadow;

use std::path::Path;

use crate::budget::Budget;
use crate::error::{Error, Result};
use crate::format::{Job, ScenarioFile};
use crate::outcome::Outcome;
use crate::output::{json_for, write_file};
use crate::progress::Progress;
use crate::report::Report;

/// How to run a job.
#[derive(Clone, Copy)]
pub struct RunOptions<'a> {
    /// Where to write output files (`None`: write nothing).
    pub out_dir: Option<&'a Path>,
    /// Where to report progress.
    pub progress: &'a dyn Progress,
    /// The memory and work the job may take; checked before it starts.
    pub budget: Budget,
}

impl std::fmt::Debug for RunOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RunOptions")
            .field("out_dir", &self.out_dir)
            .field("budget", &self.budget)
            .finish_non_exhaustive()
    }
}

/// Runs the scenario's job; writes its files into `opts.out_dir` if given.
pub fn run(file: &ScenarioFile, opts: RunOptions<'_>) -> Result<Outcome> {
    if let Some(estimate) = crate::budget::estimate(&file.scenario) {
        opts.budget.check(&estimate)?;
    }
    if let Some(dir) = opts.out_dir {
        std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.to_path_buf(), source })?;
    }
    let mut outcome = match &file.scenario.job {
        Job::SunTable(job) => reported(Report::SunTable(sun_table::compute(job, opts.progress)?), None, opts)?,
        Job::TerrainShadow(job) => {
            reported(Report::TerrainShadow(terrain_shadow::compute(job, file, opts)?), None, opts)?
        }
        Job::Tempest(job) => {
            let (report, failure) = tempest::run(job, file, opts)?;
            reported(report, failure, opts)?
        }
        Job::Actions(job) => reported(actions::run(job, file, opts)?, None, opts)?,
    };
    if let Some(dir) = opts.out_dir {
        let path = dir.join("facts.json");
        let json = json_for(&path, &outcome.facts, true)?;
        write_file(&path, json.as_bytes())?;
        outcome.files.push(path);
    }
    Ok(outcome)
}

/// The outcome of a job that returned `report` (and failed as `failure` says): its facts
/// and summary read off it, its files written from it.
fn reported(report: Report, failure: Option<crate::outcome::Failure>, opts: RunOptions<'_>) -> Result<Outcome> {
    let files = match opts.out_dir {
        Some(dir) => crate::output::reports::write(dir, &report)?,
        None => Vec::new(),
    };
    Ok(Outcome {
        facts: report.facts(),
        summary: crate::output::reports::summary(&report),
        files,
        failure,
        report: Some(Box::new(report)),
    })
}

/// Runs the scenario into `out_root/NAME/` (NAME the scenario's file stem), replacing
/// that directory's previous contents as a set: the job writes into a staging directory
/// beside it, renamed into place only when the job has finished (an unreachable goal
/// included), so no stale file of an earlier run survives beside the new ones and a
/// failed run leaves the previous outputs as they were (the swap is one atomic step
/// where the kernel can exchange two names; `docs/robustness.md` says what survives
/// which fault). Refuses an output directory that holds the scenario file itself, and a
/// scenario whose file name is not UTF-8.
pub fn run_into(file: &ScenarioFile, out_root: &Path, progress: &dyn Progress, budget: Budget) -> Result<Outcome> {
    let name = &file.name;
    if file.path.file_stem().is_some_and(|s| s.to_str().is_none()) {
        return Err(Error::usage(
            file.path.display().to_string(),
            "the scenario's file name gives the output directory and is not UTF-8: rename the file",
        ));
    }
    if name.is_empty() || name.starts_with('.') || name.contains(['/', '\\']) {
        return Err(Error::usage(
            file.path.display().to_string(),
            format!("the scenario's file name gives the output directory; {name:?} cannot be one"),
        ));
    }
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| Error::Io { path, source }
    };
    std::fs::create_dir_all(out_root).map_err(io(out_root))?;
    let dir = out_root.join(name);
    if let (Ok(scenario), Ok(target)) = (file.path.canonicalize(), dir.canonicalize())
        && scenario.starts_with(&target)
    {
        return Err(Error::usage(
            format!("--out {}", out_root.display()),
            format!("the outputs go to {}, which holds the scenario {} itself", dir.display(), file.path.display()),
        ));
    }
    if let Ok(meta) = std::fs::symlink_metadata(&dir)
        && !meta.is_dir()
    {
        return Err(Error::usage(
            format!("--out {}", out_root.display()),
            format!("{} is a file or a link, not an output directory: move it or choose another --out", dir.display()),
        ));
    }
    crate::output::staging::clear_stale(&dir);
    let staging = crate::output::staging::staging_path(&dir, "partial");
    let outcome = run(file, RunOptions { out_dir: Some(&staging), progress, budget });
    let mut outcome = match outcome {
        Ok(o) => o,
        Err(e) => {
            // Best effort: a half-written staging directory is of no use.
            let _ = std::fs::remove_dir_all(&staging);
            // Name the file the user asked for, not its staging name.
            return Err(match e {
                Error::Io { path, source } => match path.strip_prefix(&staging) {
                    Ok(rest) => Error::Io { path: dir.join(rest), source },
                    Err(_) => Error::Io { path, source },
                },
                other => other,
            });
        }
    };
    crate::output::staging::pause_for_tests(&staging);
    crate::output::staging::put_in_place(&staging, &dir).map_err(io(&dir)).inspect_err(|_| {
        // Best effort: the finished outputs could not be put in place.
        let _ = std::fs::remove_dir_all(&staging);
    })?;
    for f in &mut outcome.files {
        if let Ok(rest) = f.strip_prefix(&staging) {
            *f = dir.join(rest);
        }
    }
    Ok(outcome)
}
