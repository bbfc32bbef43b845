//! areo-rover: rover models for the planners.
//!
//! Two levels of model: the LSR-1 rocker-bogie quasi-static physics of Farritor, Hacot
//! & Dubowsky (1998) — kinematics on terrain, force balance with power-optimal wheel
//! torques, slip, contact and saturation limits, force-angle stability, energy — used
//! by areo-actions; and TEMPEST's coarse resource models (locomotor, solar array,
//! battery, electronics loads) used by areo-mission.
//!
//! Architecture invariant: areo-rover stands on areo-terrain's `Ground` and does no
//! I/O beyond loading its parameter files.
//!
//! Status: the crate is created by the workspace foundation; the models land with the
//! rover issue.
