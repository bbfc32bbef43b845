//! areo-mission: the TEMPEST planner (Tompkins, Stentz & Wettergreen 2004).
//!
//! Composes areo-terrain (DEM, slope, horizon maps), areo-ephemeris (the Sun), areo-rover
//! (the coarse resource models) and areo-ise (the search engine) into long-range
//! planning in position, time and battery energy.
//!
//! Main types: [`World`] (terrain, Sun table, light and shadow), [`ActionModel`]
//! (TEMPEST's Drive / Charge / Hibernate actions and local constraints for one rover),
//! [`TempestDomain`] (the ISE domain: labels of time and required energy, the L + B
//! objective or duration, windows, dominance), [`Mission`] (single- and multi-goal
//! planning by chained segments, plan extension and re-planning) and [`MissionPlan`]
//! (the waypoints). [`simulate`] runs a plan on true terrain the rover only learns by
//! sensing, re-planning after every action ([`SimReport`]). [`contact`] schedules
//! Communicate sessions and measures Earth contact and safe havens along a plan, and
//! [`metrics`] measures a plan or a run on the world (the Sun's azimuth span, sunward drives,
//! zig-zags, night and shadowed drives) — both by sampling, independently of the
//! planner's constraints. [`uncertainty`] makes chance-constrained plans (the model
//! worsened to a confidence level) and executes a plan open-loop on sampled factors
//! (Monte Carlo).
//!
//! ```no_run
//! # use areo_mission::*;
//! # fn demo(world: &World) -> Result<()> {
//! let model = ActionModel::new(areo_rover::resources::ResourceModel::hyperion(), ActionConfig::default());
//! let start = Start { cell: world.cell(2, 2), t_min: 0.0, t_max: 600.0, energy_wh: 800.0 };
//! let (_mission, plan) = Mission::plan(world, &model, PlannerConfig::default(), start, &[world.cell(40, 30)])?;
//! println!("{} waypoints over {:.1} h", plan.waypoints.len(), plan.duration_s() / 3600.0);
//! # Ok(()) }
//! ```
//!
//! Architecture invariant: areo-mission is the only crate that knows all the others;
//! nothing below it depends on it.

mod action_model;
mod domain;
mod effect;
mod error;
mod ground;
mod landmark;
mod plan;
mod planner;
mod simulate;
mod world;

pub mod contact;
pub mod exact;
pub mod metrics;
pub mod search_cost;
pub mod uncertainty;

pub use crate::{
    action_model::{
        Action, ActionConfig, ActionModel, Binding, Constraints, DriveGeometry, LoadLevel, NEIGHBOURS, Perturbation,
    },
    domain::{Label, Objective, PathLength, Resolution, Start, TempestDomain},
    effect::Effect,
    error::{Error, Result},
    ground::{ClassMap, TerrainClass, UNCLASSIFIED},
    plan::{MissionPlan, Waypoint},
    planner::{Classes, ExpansionMeter, FrontPlan, Mission, ParetoFront, PlannerConfig, SearchMode, non_dominated},
    simulate::{
        ExecutedStep, FreshCheck, FreshPlan, Noise, PlanKind, PlanRecord, PlannedOn, Restart, SimConfig, SimProgress,
        SimReport, SimStatus, Simulation, simulate,
    },
    world::{EarthSky, GridSun, World, WorldConfig, curvature_of},
};
