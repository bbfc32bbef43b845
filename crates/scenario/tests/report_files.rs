//! Every file a run writes is read off its report: each of the report's tables is the
//! CSV of its name, row for row, and each of its plots the SVG and PNG of its name.

use std::path::{Path, PathBuf};

use areo_scenario::budget::Budget;
use areo_scenario::format::load_set;
use areo_scenario::{NoProgress, Report, RunOptions, run};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn out(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("areo-report-files-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Runs `scenario` with `sets` into a fresh directory; returns the report and the
/// directory.
fn run_into(scenario: &str, sets: &[&str], name: &str) -> (Report, PathBuf) {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let file = load_set(&root().join(scenario), &sets).unwrap();
    let dir = out(name);
    let opts = RunOptions { out_dir: Some(&dir), progress: &NoProgress, budget: Budget::for_this_machine() };
    let outcome = run(&file, opts).unwrap();
    (*outcome.report.unwrap(), dir)
}

/// Every table is `NAME.csv` with as many rows; every plot `NAME.svg` and `NAME.png`
/// (under `RUN/` for a run's plots when there are several runs). Returns the tables'
/// and the plots' names.
fn check_files(report: &Report, dir: &Path) -> (Vec<String>, Vec<String>) {
    let mut tables = Vec::new();
    for (name, rows) in report.tables() {
        let path = dir.join(format!("{name}.csv"));
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let rows = rows.as_array().unwrap_or_else(|| panic!("{name} is not a list of rows"));
        assert_eq!(text.lines().count(), rows.len() + 1, "{name}: the CSV's rows");
        tables.push(name);
    }
    let mut plots = Vec::new();
    let mut see = |sub: &str, plot: &areo_scenario::report::plots::Plot| {
        for ext in ["svg", "png"] {
            let path = dir.join(sub).join(format!("{}.{ext}", plot.name));
            assert!(std::fs::metadata(&path).is_ok_and(|m| m.len() > 1000), "{}", path.display());
        }
        plots.push(format!("{sub}{}", plot.name));
    };
    match report {
        Report::Tempest(r) => r.plots.iter().for_each(|p| see("", p)),
        Report::Actions(r) => {
            r.plots.iter().for_each(|p| see("", p));
            for (name, best) in &r.best_plans {
                let sub = if r.best_plans.len() == 1 { String::new() } else { format!("{name}/") };
                best.plots.iter().for_each(|p| see(&sub, p));
            }
        }
        _ => {}
    }
    (tables, plots)
}

#[test]
fn an_actions_runs_tables_and_plots_are_its_files() {
    let (report, dir) = run_into(
        "tests/actions/small.ron",
        &[
            r#"job.runs=[(name: "one", inventory: [101, 105, 106, 107, 108, 3002, 3003], seeds: (1, 2)), (name: "two", inventory: [101, 105, 106, 107, 108, 3002, 3003])]"#,
        ],
        "actions",
    );
    let (tables, plots) = check_files(&report, &dir);
    for name in ["seeds", "one/plan", "one/ga", "one/commands", "two/plan", "two/ga", "two/commands"] {
        assert!(tables.iter().any(|t| t == name), "{name} in {tables:?}");
    }
    for name in ["success_by_generation", "lookahead_one", "one/top_view", "two/side_profile", "two/fitness"] {
        assert!(plots.iter().any(|p| p == name), "{name} in {plots:?}");
    }
    // Two seeds of run one: seeds.csv holds them, and the plan table is the trace the
    // best plan's commands follow, a command per executed module.
    let Report::Actions(r) = &report else { panic!("an actions report") };
    assert_eq!(r.runs["one"].study.as_ref().map(|s| s.seed_rows.len()), Some(2));
    let best = &r.best_plans["one"];
    assert_eq!(best.plan.trace.len(), best.commands.commands.len());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_tempest_runs_tables_and_plots_are_its_files() {
    let (report, dir) = run_into(
        "scenarios/uncertain-dawn.ron",
        &["job.monte_carlo.runs=50", "job.monte_carlo.closed_loop_runs=2"],
        "tempest",
    );
    let (tables, plots) = check_files(&report, &dir);
    for name in ["plan", "monte_carlo"] {
        assert!(tables.iter().any(|t| t == name), "{name} in {tables:?}");
    }
    for name in ["route", "distance", "energy", "mc_arrival", "mc_battery", "mc_lowest_battery"] {
        assert!(plots.iter().any(|p| p == name), "{name} in {plots:?}");
    }
    // No simulation: the layers are the map the plan was made on.
    let Report::Tempest(r) = &report else { panic!("a TEMPEST report") };
    assert_eq!(r.layers.as_ref().map(|l| l.map.as_str()), Some("as planned"));
    let _ = std::fs::remove_dir_all(&dir);
}
