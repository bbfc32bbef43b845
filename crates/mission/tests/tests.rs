//! areo-mission integration tests.

mod battery_inside;
mod bodies;
mod chaining;
mod common;
mod exact;
mod fine_ticks;
mod front;
mod grid_north;
mod ground;
mod late_windows;
mod pareto;
mod planning;
mod repair;
mod sensing;
mod simulation;
mod terrain_error;
mod tick;
mod uncertainty;
mod waits;
