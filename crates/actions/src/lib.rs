//! areo-actions: physics-based action planning by a genetic algorithm.
//!
//! Plans sequences of action modules (drive, turn, arc, arm, grasp, …; Table 1 of
//! Farritor, Hacot & Dubowsky 1998) for the LSR-1 rover, scoring each candidate by
//! executing it on areo-rover's quasi-static model with partial credit up to its first
//! failure.
//!
//! Main types: [`Task`] (start, target, samples, rocks, what the task needs),
//! [`Inventory`] (the modules a task can need, with every filter's reason, and the
//! design space of eq. 1), [`Executor`] (runs a plan until the task is complete or a
//! constraint is violated: slip, contact, saturation, stability floor, a rock hitting
//! the body, leaving the map), [`fitness()`] (eq. 17) and [`evolve`] (the GA:
//! crossover at the failure point, mutation, tournament selection, elitism, seeded and
//! identical for any thread count), [`friction_replay`] (one found plan executed at
//! each of a list of friction coefficients, the paper's study), [`friction_scan`]
//! (the task planned afresh at each) and [`climb_margins`] (the stability margin along a
//! straight climb with the arm stowed and reached forward); [`commands`] exports an
//! executed plan as the commands a rover would run (arc, distance, steering angles,
//! arm joints, duration, energy).
//!
//! ```no_run
//! # use areo_actions::*;
//! # fn demo(dem: &areo_terrain::Dem, task: &Task) -> Result<()> {
//! let params = areo_rover::RoverParams::lsr1();
//! let evaluator = areo_rover::evaluation::Evaluator::new(&params);
//! let executor = Executor::new(dem, &evaluator, task, ExecConfig::default());
//! let room = Surroundings::new((dem.cols() as f64 * dem.dx(), dem.rows() as f64 * dem.dy()), &params);
//! let inventory = Inventory::for_task(task, &room, &Overrides::default());
//! let scale = Scale { start_distance_m: task.start_distance_m(), samples_wanted: 1,
//!     reference_time_s: task.start_distance_m() / 0.03, battery_wh: 48.0, s_floor: 0.2 };
//! let report = evolve(&executor, &inventory, &Weights::default(), &scale, &GaConfig::default())?;
//! println!("best fitness {:.2}, solved in generation {:?}", report.best.fitness, report.first_solved);
//! # Ok(()) }
//! ```
//!
//! Architecture invariant: areo-actions depends only on areo-rover and areo-terrain;
//! every random process takes an explicit seed.

mod climb;
mod command;
mod error;
mod executor;
mod fitness;
mod friction;
mod ga;
mod inventory;
mod task;

pub use crate::{
    climb::{
        ArmCase, ClimbPose, ClimbProfile, SensitivityRow, StepClimb, arm_reached_forward, climb_margins,
        climb_sensitivity, least_mu, step_climb,
    },
    command::{Command, commands, steering},
    error::{Error, Result},
    executor::{Checkpoint, ExecConfig, ExecFailure, Execution, Executor, TraceStep, WheelLimit},
    fitness::{Scale, Weights, fitness, stability_penalty},
    friction::{FrictionReplay, FrictionScan, ReplayPoint, ScanPoint, friction_replay, friction_scan},
    ga::{CrossoverPoint, GaConfig, GaReport, Generation, Individual, evolve},
    inventory::{Inventory, Overrides, Removal, Surroundings, design_space_log10},
    task::{Rock, Sample, Task},
};
