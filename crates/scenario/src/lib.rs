//! areo's jobs, between the library crates and the `areo` binary.
//!
//! A scenario file goes in; a typed report, named facts and files come out. This crate
//! owns:
//!
//! - [`format`](mod@format): the RON scenario format (v1), its range checks and the line:column of
//!   every error ([`format::load`], [`format::parse`]);
//! - [`run()`]: one scenario's job ([`jobs`]: Sun table, terrain shadow, TEMPEST,
//!   GA actions) through the library crates into an [`Outcome`];
//! - [`report`]: the jobs' reports as plain serialisable data, and the facts read off
//!   their fields;
//! - [`budget`]: a job's memory and work estimated before it starts, and refused
//!   when over the limit;
//! - [`outcome`]: named [`Fact`]s and the [`outcome::Expected`] checks of
//!   `cargo xtask scenarios`;
//! - [`output`]: the writers (atomic files, CSV, GeoJSON, plots, PNG);
//! - [`sweep`]: studies as sweep files expanded into array tasks (Slurm, Kubernetes),
//!   run by index and collected into one table;
//! - the computations behind the binary's other commands: [`sun`] (the Sun as rows),
//!   [`terrain`] (DEM rasters), [`grid`] (Moving AI benchmarks), [`rover_check`].
//!
//! It prints nothing and parses no flags: the `areo` binary does that, and reports
//! progress through the [`Progress`] trait it implements.

mod error;
mod progress;

pub mod budget;
pub mod format;
pub mod grid;
pub mod jobs;
pub mod outcome;
pub mod output;
pub mod report;
pub mod rover_check;
pub mod sun;
pub mod sweep;
pub mod terrain;

/// The body a job plans on (re-exported so the binary needs no other areo crate).
pub use areo_ephemeris::Body;

pub use crate::{
    error::{Error, Result},
    jobs::{RunOptions, run, run_into},
    outcome::{Fact, Failure, Outcome},
    progress::{NoProgress, Progress},
    report::Report,
};

/// Reads a text file a user gave (scenario, rover, sweep, list of instants, grid map,
/// or one of areo's own records): a regular file within areo-terrain's text limit.
pub(crate) fn read_text(path: &std::path::Path) -> std::io::Result<String> {
    areo_terrain::input::read_text(path, areo_terrain::input::TEXT_LIMIT)
}
