//! areo-rover integration tests.

mod bogie_behind;
mod params;
mod physics;
