//! The scenario regression runner: every shipped scenario against its expected facts.

use std::fmt::Write;
use std::path::Path;
use std::time::Instant;

use areo_scenario::outcome::{Expected, Mismatch};
use areo_scenario::{NoProgress, RunOptions};

/// One scenario's result.
pub(crate) struct Row {
    name: String,
    checked: usize,
    status: Status,
    seconds: f64,
}

enum Status {
    Pass,
    Mismatch(Vec<Mismatch>),
    NoExpectation,
    Error(String),
}

/// All rows of one run.
pub(crate) struct Report {
    rows: Vec<Row>,
}

impl Report {
    pub(crate) fn failures(&self) -> usize {
        self.rows.iter().filter(|r| !matches!(r.status, Status::Pass)).count()
    }

    pub(crate) fn table(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "{:<28} {:<8} {:>6} {:>9}", "scenario", "status", "facts", "time (s)");
        for r in &self.rows {
            let status = match &r.status {
                Status::Pass => "ok",
                Status::Mismatch(_) => "MISMATCH",
                Status::NoExpectation => "NO-EXPECT",
                Status::Error(_) => "ERROR",
            };
            let _ = writeln!(s, "{:<28} {:<8} {:>6} {:>9.2}", r.name, status, r.checked, r.seconds);
            match &r.status {
                Status::Mismatch(ms) => {
                    for m in ms {
                        let _ = writeln!(s, "    {}: expected {}, found {}", m.fact, m.expected, m.found);
                    }
                }
                Status::NoExpectation => {
                    let _ = writeln!(s, "    missing scenarios/expected/{}.ron", r.name);
                }
                Status::Error(e) => {
                    let _ = writeln!(s, "    {e}");
                }
                Status::Pass => {}
            }
        }
        let _ = writeln!(s, "{} scenarios, {} failed", self.rows.len(), self.failures());
        s
    }
}

/// Runs every `scenarios/*.ron` under `root`.
pub(crate) fn run_all(root: &Path) -> Result<Report, String> {
    let dir = root.join("scenarios");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    paths.sort();
    if paths.is_empty() {
        return Err(format!("no scenarios in {}", dir.display()));
    }
    let out_root = root.join("target").join("xtask-scenarios");
    let mut rows = Vec::new();
    for path in paths {
        let started = Instant::now();
        let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        let expected_path = dir.join("expected").join(format!("{name}.ron"));
        let (checked, status) = match run_one(&path, &expected_path, &out_root.join(&name)) {
            Ok((n, ms)) if ms.is_empty() => (n, Status::Pass),
            Ok((n, ms)) => (n, Status::Mismatch(ms)),
            Err(None) => (0, Status::NoExpectation),
            Err(Some(e)) => (0, Status::Error(e)),
        };
        rows.push(Row { name, checked, status, seconds: started.elapsed().as_secs_f64() });
    }
    Ok(Report { rows })
}

/// `Err(None)`: no expectation file; `Err(Some(e))`: the scenario failed to load or run.
fn run_one(path: &Path, expected_path: &Path, out: &Path) -> Result<(usize, Vec<Mismatch>), Option<String>> {
    if !expected_path.exists() {
        return Err(None);
    }
    let expected = Expected::load(expected_path).map_err(|e| Some(e.to_string()))?;
    let file = areo_scenario::format::load(path).map_err(|e| Some(e.to_string()))?;
    let outcome = areo_scenario::run(
        &file,
        RunOptions {
            out_dir: Some(out),
            progress: &NoProgress,
            budget: areo_scenario::budget::Budget::for_this_machine(),
        },
    )
    .map_err(|e| Some(e.to_string()))?;
    Ok((expected.facts.len(), expected.check(&outcome)))
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_shipped_scenario_meets_its_expectations() {
        let report = super::run_all(&crate::project_root()).unwrap();
        assert_eq!(report.failures(), 0, "\n{}", report.table());
    }
}
