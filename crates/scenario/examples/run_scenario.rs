//! Runs a scenario file as `areo run` does, with nothing printed along the way, and
//! lists its facts — `cargo run --release -p areo-scenario --example run_scenario --
//! scenarios/uncertain-ridge.ron` (the default) from the repository's root.

#![allow(clippy::print_stdout)] // an example prints what it shows

use std::path::PathBuf;

use areo_scenario::{NoProgress, RunOptions};

fn main() -> Result<(), areo_scenario::Error> {
    let path = std::env::args().nth(1).map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/uncertain-ridge.ron"),
        PathBuf::from,
    );
    let file = areo_scenario::format::load(&path)?;
    let options =
        RunOptions { out_dir: None, progress: &NoProgress, budget: areo_scenario::budget::Budget::for_this_machine() };
    let outcome = areo_scenario::run(&file, options)?;
    for line in &outcome.summary {
        println!("{line}");
    }
    for (name, fact) in &outcome.facts {
        println!("{name} = {fact}");
    }
    Ok(())
}
