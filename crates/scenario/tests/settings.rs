//! Values set from outside the file — `--set PATH=VALUE` and a sweep's axes — change
//! their own field and nothing else: text that would close the field and open another,
//! comment out what follows or switch RON extensions is refused naming the setting, and
//! a value of the wrong type names the setting and what the field takes.

use std::path::{Path, PathBuf};

use areo_scenario::Error;
use areo_scenario::format::Job;
use areo_scenario::format::{load, load_with};
use areo_scenario::sweep;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn small() -> PathBuf {
    root().join("tests/tempest/small.ron")
}

fn refused(path: &Path, set: &str) -> String {
    match load_with(path, &[set.to_string()]) {
        Ok(_) => panic!("{set} was accepted"),
        Err(e @ Error::Usage { .. }) => {
            assert_eq!(e.exit_code(), 2);
            e.to_string()
        }
        Err(e) => panic!("{set}: not a usage error: {e:?}"),
    }
}

#[test]
fn a_value_that_would_add_or_change_another_field_is_refused() {
    let path = small();
    // Each of these, spliced as text, made a valid scenario with something else changed.
    for (set, says) in [
        (
            r#"job.horizon_h=40, tau: 0.5, regions: [(name: "X", x_m: 1, y_m: 1, radius_m: 10)]"#,
            "more than one RON value",
        ),
        ("job.planner.goal_times=200), simulate: (sense_radius_cells: 9", "more than one RON value"),
        ("job.horizon_h=40 // , rest of the line", "comment"),
        ("job.horizon_h=40 /* */", "comment"),
        ("job.horizon_h=#![enable(implicit_some)] 40", "attribute"),
        ("job.start_utc=\"2012-08-06T23:00:00Z\"), x: (", "more than one RON value"),
    ] {
        let err = refused(&path, set);
        assert!(err.contains(&format!("--set {set}")) && err.contains(says), "{set}: {err}");
    }
    // A string may hold any of those characters: it is one value.
    let set = "job.goals[0].name=\"east // (a), b: [#]\"".to_string();
    let file = load_with(&path, &[set]).unwrap();
    let Job::Tempest(job) = &file.scenario.job else { panic!("a TEMPEST job") };
    assert_eq!(job.goals[0].name, "east // (a), b: [#]");
    // Nothing else moved: the file with the setting applied is the file as written,
    // but for that one value.
    let written = load(&path).unwrap();
    let (Job::Tempest(a), Job::Tempest(b)) = (&written.scenario.job, &file.scenario.job) else { unreachable!() };
    assert_eq!(format!("{:?}", a.simulate), format!("{:?}", b.simulate));
    assert_eq!(a.regions.len(), b.regions.len());
}

#[test]
fn a_value_of_the_wrong_type_names_the_setting_and_the_type() {
    let path = small();
    let err = refused(&path, "job.horizon_h=\"forty\"");
    assert!(err.contains("--set job.horizon_h=\"forty\"") && err.contains("`job.horizon_h`"), "{err}");
    assert!(err.contains("Expected float") && !err.contains("small.ron"), "says a number is expected: {err}");
    // With several settings, the one at fault is named.
    let sets = ["job.start_battery_above_floor_wh=450".to_string(), "job.horizon_sectors=[16]".to_string()];
    let err = load_with(&path, &sets).unwrap_err().to_string();
    assert!(err.contains("--set job.horizon_sectors=[16]") && !err.contains("450"), "{err}");
}

#[test]
fn a_sweep_axis_sets_its_own_field_only() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("settings-tests");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(small(), dir.join("small.ron")).unwrap();
    // The base's rover path is relative to it.
    let base = std::fs::read_to_string(small())
        .unwrap()
        .replace("../../scenarios/rovers/", &format!("{}/", root().join("scenarios/rovers").display()));
    std::fs::write(dir.join("small.ron"), base).unwrap();
    let expand = |axes: &str| {
        let path = dir.join("s.sweep.ron");
        std::fs::write(&path, format!("Sweep(version: 1, base: \"small.ron\", axes: [{axes}])")).unwrap();
        sweep::expand(&path, &dir.join("run"))
    };
    let raw = r#"(name: "h", path: "job.horizon_h", raw: ["40, simulate: None"])"#;
    let err = expand(raw).unwrap_err().to_string();
    assert!(err.contains("axes[0]") && err.contains("more than one RON value"), "{err}");
    let raw = r#"(name: "h", path: "job.horizon_h", raw: ["40 //"])"#;
    assert!(expand(raw).unwrap_err().to_string().contains("comment"));
    let nested = r#"(name: "p", path: "job.planner", raw: ["(approximate: true, goal_times: 100, resolution: (time_s: 600, energy_wh: 25))"]),
        (name: "g", path: "job.planner.goal_times", values: [50, 60])"#;
    let err = expand(nested).unwrap_err().to_string();
    assert!(err.contains("axes[1].path") && err.contains("overlaps"), "{err}");
    let fine = r#"(name: "h", path: "job.horizon_h", values: [30, 40])"#;
    assert_eq!(expand(fine).unwrap().len(), 2);
}
