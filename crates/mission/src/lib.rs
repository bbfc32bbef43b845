//! areo-mission: the TEMPEST planner.
//!
//! Composes areo-terrain (DEM, slope, shadows), areo-ephemeris (the Sun), areo-rover
//! (coarse resource models) and areo-ise (the search engine) into long-range planning
//! in position, time and battery energy, with multi-goal chaining, plan extension,
//! re-planning and execution simulation (Tompkins, Stentz & Wettergreen 2004).
//!
//! Architecture invariant: areo-mission is the only crate that knows all the others;
//! nothing below it depends on it.
//!
//! Status: the crate is created by the workspace foundation; the planner lands with the
//! TEMPEST planner issue.
