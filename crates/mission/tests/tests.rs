//! areo-mission integration tests.

mod chaining;
mod common;
mod planning;
mod simulation;
