//! areo plans what a planetary rover should do — where to drive, when to charge, when
//! to sleep through the night, how to move its wheels and arm — grounded in physics
//! and in the rover's energy.
//!
//! This root crate is the glue the `areo` binary and `cargo xtask` share: the
//! [`scenario`] format (RON jobs with positioned errors), [`run()`] (a scenario's job
//! through the library crates into an [`Outcome`] of named facts and files), the
//! [`outcome::Expected`] facts the regression runner checks, and re-exports of the
//! library crates:
//!
//! - [`terrain`]: DEMs, slope, line of sight and shadows;
//! - [`ephemeris`]: Mars time, the Sun and the Earth from Mars, solar flux;
//! - [`rover`]: LSR-1 physics and coarse resource models;
//! - [`ise`]: the incremental search engine;
//! - [`actions`]: the GA action planner;
//! - [`mission`]: the TEMPEST planner.

mod error;
mod progress;

mod actions_job;
mod run;
mod tempest;

pub mod movingai;
pub mod outcome;
pub mod plots;
pub mod render;
pub mod rover_check;
pub mod scenario;
pub mod sun_report;
pub mod terrain_tools;

pub use areo_actions as actions;
pub use areo_ephemeris as ephemeris;
pub use areo_ise as ise;
pub use areo_mission as mission;
pub use areo_rover as rover;
pub use areo_terrain as terrain;

pub use crate::{
    error::{Error, Result},
    outcome::{Fact, Outcome},
    progress::{NoProgress, Progress},
    run::{RunOptions, run},
};
