//! areo-rover integration tests.

mod params;
