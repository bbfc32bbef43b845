//! `cargo xtask` — development tasks for the areo workspace.
//!
//! - `cargo xtask scenarios`: run every `scenarios/*.ron` through the library and check
//!   it against `scenarios/expected/NAME.ron`;
//! - `cargo xtask deps`: check that crate dependencies point down the design's crate map;
//! - `cargo xtask bench`: run the criterion benches and print the figures and ratios
//!   that `docs/benchmarks.md` records;
//! - `cargo xtask downstream`: scratch crates outside the workspace, each on one areo
//!   crate (the ephemeris alone; the terrain without default features), built, run and
//!   their dependency trees counted;
//! - `cargo xtask fuzz`: the long, seeded robustness run against the release binary
//!   (`docs/robustness.md`).
//!
//! Each check is also a `#[test]` here, so `cargo test --workspace` covers them.

#![allow(clippy::print_stdout, clippy::print_stderr)]

mod bench;
mod deps;
mod downstream;
mod fuzz;
#[cfg(test)]
mod plot_layout;
mod scenarios;

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("scenarios") => scenarios::run_all(&project_root()).map(|report| {
            print!("{}", report.table());
            report.failures() == 0
        }),
        Some("deps") => deps::check(&project_root())
            .and_then(|mut violations| {
                let prints = deps::printing_in_libraries(&project_root())?;
                violations.extend(prints.into_iter().map(|at| format!("{at}: a library writes to stdout or stderr")));
                let bodies = deps::body_constants_outside_areo_body(&project_root())?;
                violations.extend(bodies.into_iter().map(|at| format!("{at}: a body constant outside areo-body")));
                let unoptimised = deps::optimised_compile_time_crates(&project_root())?;
                violations.extend(unoptimised.into_iter().map(|name| {
                    format!("Cargo.toml: {name} runs only while compiling: give it opt-level = 0 in the dev profile")
                }));
                let history = deps::history_references(&project_root())?;
                violations.extend(
                    history.into_iter().map(|at| format!("{at}: a session or issue number (history lives in git)")),
                );
                let files = deps::long_files(&project_root(), 1000)?;
                violations.extend(files.into_iter().map(|at| format!("{at}: a source file over 1 000 lines")));
                let long = deps::long_functions(&project_root(), 80)?;
                violations.extend(long.into_iter().map(|at| format!("{at}: a function over 80 lines")));
                let writers = deps::writers_outside_reports(&project_root())?;
                violations
                    .extend(writers.into_iter().map(|at| format!("{at}: a report writer names what is not a report")));
                Ok(violations)
            })
            .map(|violations| {
                for v in &violations {
                    println!("{v}");
                }
                if violations.is_empty() {
                    println!("dependency directions: ok");
                }
                violations.is_empty()
            }),
        Some("bench") => bench::run(&project_root(), &args[1..]),
        Some("downstream") => downstream::check(&project_root()).and_then(|built| {
            for b in &built {
                let unwanted =
                    if b.unwanted.is_empty() { String::new() } else { format!("; pulls in {:?}", b.unwanted) };
                println!("{}: builds and runs; {} packages in its dependency tree{unwanted}", b.name, b.dependencies);
            }
            let warned = downstream::package_warnings(&project_root())?;
            for (name, warnings) in &warned {
                println!("{name}: cargo package warns: {}", warnings.join("; "));
            }
            if warned.is_empty() {
                println!(
                    "cargo package --list: no metadata warning in {} library crates",
                    downstream::LIBRARY_CRATES.len()
                );
            }
            Ok(built.iter().all(|b| b.unwanted.is_empty()) && warned.is_empty())
        }),
        Some("fuzz") => fuzz::Options::parse(&args[1..]).and_then(|o| fuzz::run(&project_root(), &o)),
        _ => {
            eprintln!(
                "usage: cargo xtask <scenarios|deps|downstream|bench [FILTER]|fuzz [--cases N] [--seed S] [--timeout-s T]>"
            );
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The workspace root (the parent of this crate's directory).
fn project_root() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    dir.parent().map(PathBuf::from).unwrap_or(dir)
}
