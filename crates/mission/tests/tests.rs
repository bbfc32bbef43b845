//! areo-mission integration tests.

mod common;
mod planning;
