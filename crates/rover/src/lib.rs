//! areo-rover: rover models for the planners.
//!
//! Two levels of model: the LSR-1 rocker-bogie quasi-static physics of Farritor, Hacot
//! & Dubowsky (1998) — kinematics on terrain, force balance with power-optimal wheel
//! torques, slip, contact and saturation limits, force-angle stability, energy — used
//! by areo-actions; and TEMPEST's coarse resource models (locomotor, solar array,
//! battery, electronics loads) used by areo-mission.
//!
//! Main types: [`RoverParams`] (the LSR-1 parameter set shipped as `params/lsr1.ron`,
//! with Sojourner-class and MER-class files beside it, every value with its source or
//! assumption, loaded with range and geometry validation; [`Layout`]: the bogie in front
//! as on the LSR-1, or behind as on MER, solved as the mirror image) and [`Geometry`]
//! (the paper's loop-closure form, l1..l4, α1, α2);
//! [`kinematics::Kinematics`] (pose on any `Ground`: planar decomposition with the
//! footprint correction, plus [`kinematics::newton_pose`] as a cross-check);
//! [`forces`] (per-side quasi-static forces, power-optimal torques under friction,
//! contact and torque limits); [`stability`] (force-angle tip-over margins);
//! [`arm::ArmState`] (tool position, payload, centre of mass);
//! [`evaluation::Evaluator`] (one full pose evaluation, allocation-free);
//! [`math`] (the map and body frames, [`math::Attitude`], and the parameter types'
//! nalgebra conversions);
//! [`motion::Motion`] (the paper's Table 1 modules with duration and energy); and
//! [`resources`] (TEMPEST's locomotor, solar, battery, electronics and camera models,
//! with a Hyperion-class parameter file).
//!
//! ```
//! let lsr1 = areo_rover::RoverParams::lsr1();
//! let g = lsr1.geometry();
//! assert!((g.l3 - 0.3430).abs() < 1e-4 && (g.l4 - 0.2058).abs() < 1e-4);
//! ```
//!
//! Architecture invariant: areo-rover stands on areo-terrain's `Ground` and does no
//! I/O beyond loading its parameter files.

mod error;
mod params;

pub mod arm;
pub mod evaluation;
pub mod forces;
pub mod kinematics;
pub mod math;
pub mod motion;
pub mod resources;
pub mod stability;

pub use crate::{
    error::{Error, MAX_LIST_ITEMS, MAX_NESTING, Result, refused_shape, ron_options},
    params::{
        Activities, Arm, Assumed, Axles, BatteryPack, BodyPoint, Drive, Geometry, LSR1_RON, Layout, RoverParams,
        SidePoint, Solar,
    },
};
