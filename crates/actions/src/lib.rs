//! areo-actions: physics-based action planning by a genetic algorithm.
//!
//! Plans sequences of action modules (drive, turn, arc, arm, grasp, …) for the LSR-1
//! rover, scoring each candidate by executing it on areo-rover's quasi-static model
//! with partial credit up to its first failure (Farritor, Hacot & Dubowsky 1998).
//!
//! Architecture invariant: areo-actions depends only on areo-rover and areo-terrain;
//! every random process takes an explicit seed.
//!
//! Status: the crate is created by the workspace foundation; the planner lands with
//! the action-planning issue.
