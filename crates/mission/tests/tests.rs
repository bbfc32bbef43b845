//! areo-mission integration tests.

mod chaining;
mod common;
mod pareto;
mod planning;
mod sensing;
mod simulation;
