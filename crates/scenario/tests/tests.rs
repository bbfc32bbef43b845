//! areo-scenario integration tests, in one binary so that the long ones (a fresh search
//! beside every compared re-plan, the kept TEMPEST states at finer settings) share the
//! cores. `memory.rs` is its own binary: it reads the process's peak memory.

mod fresh_replans;
mod names;
mod plan_region;
mod report_files;
mod resolution_states;
mod robustness;
mod settings;
mod sweep;
mod task1;
mod waits;
