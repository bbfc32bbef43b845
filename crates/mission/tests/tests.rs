//! areo-mission integration tests.

mod bodies;
mod chaining;
mod common;
mod front;
mod pareto;
mod planning;
mod sensing;
mod simulation;
mod terrain_error;
mod uncertainty;
