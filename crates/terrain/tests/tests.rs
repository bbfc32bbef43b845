//! areo-terrain integration tests: the real MOLA files, reader/writer round trips, and
//! corrupt input.

#![allow(clippy::print_stderr)] // tests report what they measured

mod horizon_error;
mod hostile;
mod readers;
mod shadow_methods;
mod threads;
