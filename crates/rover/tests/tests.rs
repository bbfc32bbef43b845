//! areo-rover integration tests.

mod params;
mod physics;
