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
    let mut file = areo_scenario::format::load(path).map_err(|e| Some(e.to_string()))?;
    if expected.compare_fresh
        && let areo_scenario::format::Job::Tempest(job) = &mut file.scenario.job
        && let Some(sim) = &mut job.simulate
    {
        sim.compare_fresh = true;
    }
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
    use std::path::Path;

    /// One test per shipped scenario, so that the test harness runs them in parallel;
    /// `the_list_is_every_shipped_scenario` keeps the list and the directory equal.
    macro_rules! scenario_tests {
        ($($test:ident => $name:literal),* $(,)?) => {
            const NAMES: &[&str] = &[$($name),*];
            $(
                #[test]
                fn $test() {
                    check($name);
                }
            )*
        };
    }

    scenario_tests! {
        crater_morning_shadows => "crater-morning-shadows",
        crossover_study => "crossover-study",
        devon_island => "devon-island",
        ditch_and_hill => "ditch-and-hill",
        friction_scan_20cm => "friction-scan-20cm",
        friction_scan => "friction-scan",
        gale_ground => "gale-ground",
        gale_mola_traverse => "gale-mola-traverse",
        gale_sol_sun => "gale-sol-sun",
        lita_scale => "lita-scale",
        lunar_south_pole => "lunar-south-pole",
        lunar_south_pole_10m => "lunar-south-pole-10m",
        mer_task1 => "mer-task1",
        steep_face => "steep-face",
        sojourner_task1 => "sojourner-task1",
        steep_hill => "steep-hill",
        sun_synchronous_traverse => "sun-synchronous-traverse",
        task1_bogie_behind => "task1-bogie-behind",
        task1_paper_budget => "task1-paper-budget",
        task2_scarp => "task2-scarp",
        task2_scarp_long_bogie => "task2-scarp-long-bogie",
        task2_scarp_cg31 => "task2-scarp-cg31",
        pareto_front => "pareto-front",
        uncertain_dawn => "uncertain-dawn",
        uncertain_ridge => "uncertain-ridge",
        valley_detour => "valley-detour",
    }

    /// Runs one shipped scenario against its expected facts, as `cargo xtask
    /// scenarios` does.
    fn check(name: &str) {
        let root = crate::project_root();
        let dir = root.join("scenarios");
        let (path, expected) = (dir.join(format!("{name}.ron")), dir.join("expected").join(format!("{name}.ron")));
        let out = root.join("target").join("xtask-scenarios").join(name);
        match super::run_one(&path, &expected, &out) {
            Ok((checked, mismatches)) => {
                assert!(checked > 0, "{name}: no facts checked");
                assert!(mismatches.is_empty(), "{name}: {mismatches:#?}");
                // Every plot it drew: no legend over a label or (off the map) the data,
                // no label over another.
                let hidden = crate::plot_layout::problems(&out);
                assert!(hidden.is_empty(), "{name}: {hidden:#?}");
            }
            Err(None) => panic!("{name}: no expected file {}", expected.display()),
            Err(Some(e)) => panic!("{name}: {e}"),
        }
    }

    #[test]
    fn the_list_is_every_shipped_scenario() {
        let dir = crate::project_root().join("scenarios");
        let mut found: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "ron"))
            .map(|p| Path::new(&p).file_stem().unwrap().to_string_lossy().into_owned())
            .collect();
        found.sort();
        let mut listed: Vec<String> = NAMES.iter().map(|s| s.to_string()).collect();
        listed.sort();
        assert_eq!(found, listed, "scenarios/ and the per-scenario tests differ");
    }
}
