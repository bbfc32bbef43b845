//! Sweeps: a sweep file expanded into validated task scenarios, each task run by index
//! into its own output directory (skipped when finished, replaced as a set when
//! forced), and the tasks collected into one table — which must hold exactly the facts
//! of running the same scenarios directly.

use std::path::{Path, PathBuf};

use areo_scenario::budget::Budget;
use areo_scenario::sweep::{self, TaskRun};
use areo_scenario::{Error, NoProgress};

const UTCS: [&str; 4] =
    ["2012-08-06T20:00:00Z", "2012-08-06T21:00:00Z", "2012-08-06T23:00:00Z", "2012-08-07T01:30:00Z"];

/// A terrain-shadow scenario over synthesised ground at Gale, with its instant and
/// `flat` written out.
fn base(utc: &str, flat: bool) -> String {
    format!(
        r#"Scenario(
    version: 1,
    description: "sweep test",
    job: TerrainShadow(
        terrain: Synth(cols: 40, rows: 30, cell_m: 10.0, seed: 3,
            noise: (amplitude_m: 2.0, wavelength_m: 120.0, octaves: 2),
            features: [Hill(x_m: 200, y_m: 150, radius_m: 80, slope_deg: 25)]),
        site: (lat_deg: -4.5895, lon_east_deg: 137.4417),
        utc: "{utc}",
        flat: {flat},
    ),
)
"#
    )
}

fn scratch(tag: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("sweep-tests").join(tag);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write_sweep(dir: &Path, axes: &str, extra: &str) -> PathBuf {
    std::fs::write(dir.join("shadow.ron"), base(UTCS[0], false)).unwrap();
    let path = dir.join("shadows.sweep.ron");
    std::fs::write(&path, format!("Sweep(version: 1, base: \"shadow.ron\", {extra} axes: [{axes}])")).unwrap();
    path
}

const AXES: &str = r#"(name: "utc", path: "job.utc", values: ["2012-08-06T20:00:00Z", "2012-08-06T21:00:00Z", "2012-08-06T23:00:00Z", "2012-08-07T01:30:00Z"]),
    (name: "flat", path: "job.flat", values: [false, true])"#;

#[test]
fn eight_tasks_expand_run_and_collect_to_the_facts_of_direct_runs() {
    let dir = scratch("eight");
    let file = write_sweep(&dir, AXES, r#"name: "{index}-{utc}-flat-{flat}","#);
    let out = dir.join("run");
    let tasks = sweep::expand(&file, &out).unwrap();
    assert_eq!(tasks.len(), 8);
    // Product order: the last axis fastest.
    // Manifest values are JSON values: the string's text, a boolean.
    assert_eq!(tasks[3].values["utc"], UTCS[1]);
    assert_eq!(tasks[3].values["flat"], true);
    assert_eq!(tasks[3].id, "3-2012-08-06T21_00_00Z-flat-true");
    let manifest = std::fs::read_to_string(out.join("manifest.jsonl")).unwrap();
    assert_eq!(manifest.lines().count(), 8);
    assert_eq!(sweep::tasks(&out).unwrap(), tasks);

    for t in &tasks {
        match sweep::run_task(&out, t.index, false, &NoProgress, Budget::for_this_machine()).unwrap() {
            TaskRun::Ran(ran, outcome) => {
                assert_eq!(ran.id, t.id);
                assert!(outcome.failure.is_none());
            }
            TaskRun::Skipped(_) => panic!("task {} had not run", t.index),
        }
    }
    // Finished tasks are skipped; --force runs one again, replacing its outputs.
    assert!(matches!(
        sweep::run_task(&out, 5, false, &NoProgress, Budget::for_this_machine()).unwrap(),
        TaskRun::Skipped(_)
    ));
    assert!(matches!(
        sweep::run_task(&out, 5, true, &NoProgress, Budget::for_this_machine()).unwrap(),
        TaskRun::Ran(..)
    ));
    // Nothing half-written is left beside the outputs.
    let leftovers: Vec<_> = std::fs::read_dir(out.join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    let c = sweep::collect(&out, Some(("lit_fraction", "flat"))).unwrap();
    assert_eq!((c.finished, c.missing.len(), c.failed.len()), (8, 0, 0));
    assert!(c.files.iter().any(|f| f.ends_with("lit_fraction_vs_flat.png")));
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(&header[..5], &["index", "id", "utc", "flat", "status"]);
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for (t, line) in tasks.iter().zip(lines) {
        let row: Vec<&str> = line.split(',').collect();
        assert_eq!(row[col("status")], "done");
        // The same scenario run directly, without the sweep: the same facts.
        let utc = t.values["utc"].as_str().unwrap();
        let flat = t.values["flat"] == true;
        let text = base(utc, flat);
        let scenario = areo_scenario::format::parse(&dir.join("direct.ron"), &text).unwrap();
        let file =
            areo_scenario::format::ScenarioFile { path: dir.join("direct.ron"), name: "direct".into(), scenario, text };
        let direct = areo_scenario::run(
            &file,
            areo_scenario::RunOptions { out_dir: None, progress: &NoProgress, budget: Budget::for_this_machine() },
        )
        .unwrap();
        assert!(!direct.facts.is_empty());
        for (name, fact) in &direct.facts {
            let cell = row[col(name)];
            match fact {
                // JSON keeps every bit of an f64.
                areo_scenario::Fact::Number(v) => {
                    assert_eq!(cell.parse::<f64>().unwrap(), *v, "task {} {name}", t.index)
                }
                areo_scenario::Fact::Count(n) => assert_eq!(cell, n.to_string(), "task {} {name}", t.index),
                areo_scenario::Fact::Flag(b) => assert_eq!(cell, b.to_string(), "task {} {name}", t.index),
                areo_scenario::Fact::Text(s) => assert_eq!(cell, s, "task {} {name}", t.index),
            }
        }
    }
}

#[test]
fn a_zip_sweep_a_range_and_a_label_axis() {
    let dir = scratch("zip");
    let axes = r#"(name: "utc", path: "job.utc", values: ["2012-08-06T20:00:00Z", "2012-08-06T21:00:00Z", "2012-08-06T23:00:00Z"]),
        (name: "hour", values: [20, 21, 23]),
        (name: "lat", path: "job.site.lat_deg", range: (-6.0, -5.0, 0.5))"#;
    let file = write_sweep(&dir, axes, "combine: Zip,");
    let tasks = sweep::expand(&file, &dir.join("run")).unwrap();
    assert_eq!(tasks.len(), 3);
    assert_eq!(tasks.iter().map(|t| t.id.as_str()).collect::<Vec<_>>(), ["0", "1", "2"]);
    assert_eq!(tasks[2].values["lat"], -5);
    assert_eq!(tasks[1].values["lat"], -5.5);
    let text = std::fs::read_to_string(dir.join("run").join(&tasks[1].scenario)).unwrap();
    assert!(text.contains("lat_deg: -5.5,") && text.contains("utc: \"2012-08-06T21:00:00Z\""), "{text}");
    // Raw RON text for what RON values cannot carry (here a tuple-free bool as text).
    let file = write_sweep(&dir, r#"(name: "flat", path: "job.flat", raw: ["true"])"#, "");
    let tasks = sweep::expand(&file, &dir.join("raw")).unwrap();
    assert!(std::fs::read_to_string(dir.join("raw").join(&tasks[0].scenario)).unwrap().contains("flat: true,"));
    let file = write_sweep(&dir, r#"(name: "flat", path: "job.flat", raw: ["true"], values: [false])"#, "");
    assert!(sweep::expand(&file, &dir.join("both")).unwrap_err().to_string().contains("exactly one of"));
}

#[test]
fn bad_sweeps_are_located_errors_and_write_nothing() {
    let dir = scratch("bad");
    // A field the base does not write.
    let file = write_sweep(&dir, r#"(name: "tau", path: "job.tau", values: [0.5])"#, "");
    let e = sweep::expand(&file, &dir.join("run")).unwrap_err().to_string();
    assert!(e.contains("axes[0].path") && e.contains("not written"), "{e}");
    assert!(!dir.join("run").exists());
    // A value the scenario format refuses: named with the task's values and the field.
    let file = write_sweep(&dir, r#"(name: "lat", path: "job.site.lat_deg", values: [-4.5, 95.0])"#, "");
    let e = sweep::expand(&file, &dir.join("run")).unwrap_err().to_string();
    assert!(
        e.contains("task 1 (lat = 95.0)") && e.contains("job.site.lat_deg") && e.contains("-89.999..=89.999"),
        "{e}"
    );
    assert!(!dir.join("run").exists());
    // Zipped axes of different lengths; ids that collide.
    let file = write_sweep(&dir, AXES, "combine: Zip,");
    assert!(sweep::expand(&file, &dir.join("run")).unwrap_err().to_string().contains("zipped axes must match"));
    let file = write_sweep(&dir, AXES, r#"name: "same","#);
    assert!(sweep::expand(&file, &dir.join("run")).unwrap_err().to_string().contains("two tasks"));
    // An unknown field in the sweep file itself is a syntax error at its place.
    std::fs::write(dir.join("typo.sweep.ron"), "Sweep(version: 1, base: \"shadow.ron\", axis: [])").unwrap();
    assert!(matches!(sweep::expand(&dir.join("typo.sweep.ron"), &dir.join("run")), Err(Error::Syntax { line: 1, .. })));
}

#[test]
fn a_failed_task_is_recorded_collected_and_cleared_when_it_succeeds() {
    let dir = scratch("failed");
    let file = write_sweep(&dir, r#"(name: "flat", path: "job.flat", values: [false, true])"#, "");
    let out = dir.join("run");
    let tasks = sweep::expand(&file, &out).unwrap();
    sweep::run_task(&out, 0, false, &NoProgress, Budget::for_this_machine()).unwrap();
    // Task 1's scenario lost (a scratch disk wiped): it fails, and says why.
    let path = out.join(&tasks[1].scenario);
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert!(sweep::run_task(&out, 1, false, &NoProgress, Budget::for_this_machine()).is_err());
    let c = sweep::collect(&out, None).unwrap();
    assert_eq!((c.finished, c.failed.len()), (1, 1));
    assert!(c.failed[0].1.contains("cannot read"), "{:?}", c.failed);
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert!(csv.lines().nth(2).unwrap().contains(",failed,"), "{csv}");
    std::fs::write(&path, text).unwrap();
    sweep::run_task(&out, 1, false, &NoProgress, Budget::for_this_machine()).unwrap();
    let c = sweep::collect(&out, None).unwrap();
    assert_eq!((c.finished, c.failed.len(), c.missing.len()), (2, 0, 0));
    assert!(sweep::run_task(&out, 7, false, &NoProgress, Budget::for_this_machine()).is_err());
}

#[test]
fn launch_recipes_name_every_task() {
    let dir = scratch("recipes");
    let file = write_sweep(&dir, AXES, "");
    let out = dir.join("run");
    sweep::expand(&file, &out).unwrap();
    let script = sweep::slurm_script(&out, Path::new("/opt/areo/bin/areo"), 4, 2).unwrap();
    assert!(script.contains("#SBATCH --array=0-7%4") && script.contains("#SBATCH --cpus-per-task=2"), "{script}");
    assert!(script.contains("exec '/opt/areo/bin/areo' -v sweep run '"), "{script}");
    let job = sweep::k8s_job(&out, "ghcr.io/x/areo:1", "sweeps", 3).unwrap();
    for needle in [
        "completions: 8",
        "parallelism: 3",
        "completionMode: Indexed",
        "image: \"ghcr.io/x/areo:1\"",
        "claimName: \"sweeps\"",
    ] {
        assert!(job.contains(needle), "{needle}: {job}");
    }
}

/// Hostile names cannot inject: a sweep file named with a newline and a command, in a
/// directory with a space and a quote. The Slurm script keeps its lines (comments,
/// directives, `set`, `exec`), and bash reads the exec line as exactly the five words
/// meant; the Kubernetes job holds the values as quoted scalars.
#[test]
fn launch_recipes_quote_hostile_names() {
    let dir = scratch("hostile").join("it's a dir");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("shadow.ron"), base(UTCS[0], false)).unwrap();
    let evil = dir.join("x\ntouch pwned; $(touch pwned2).sweep.ron");
    std::fs::write(&evil, format!("Sweep(version: 1, base: \"shadow.ron\", axes: [{AXES}])")).unwrap();
    let out = dir.join("run 1");
    sweep::expand(&evil, &out).unwrap();
    let areo = dir.join("bin").join("are'o");
    let script = sweep::slurm_script(&out, &areo, 4, 2).unwrap();
    for line in script.lines() {
        assert!(
            line.starts_with('#') || line.starts_with("set ") || line.starts_with("exec "),
            "an injected line: {line:?}\n{script}"
        );
    }
    let exec = script.lines().find(|l| l.starts_with("exec ")).unwrap();
    let words = std::process::Command::new("bash")
        .arg("-c")
        .arg(exec.replacen("exec ", "printf '%s\\n' ", 1))
        .output()
        .unwrap();
    let words = String::from_utf8(words.stdout).unwrap();
    let canonical = out.canonicalize().unwrap();
    let expected = format!("{}\n-v\nsweep\nrun\n{}\n", areo.display(), canonical.display());
    assert_eq!(words, expected);
    let job = sweep::k8s_job(&out, "img\"\nevil: 1", "claim", 3).unwrap();
    assert_eq!(job.lines().count(), sweep::k8s_job(&out, "img", "claim", 3).unwrap().lines().count());
    assert!(job.contains("image: \"img\\\"\\nevil: 1\""), "{job}");
    assert!(!dir.join("pwned").exists() && !dir.join("pwned2").exists());
}

/// The shipped sweeps expand, every task validated.
#[test]
fn the_shipped_sweeps_expand() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/sweeps");
    let dir = scratch("shipped");
    let mut n = 0;
    for entry in std::fs::read_dir(&root).unwrap() {
        let path = entry.unwrap().path();
        if path.to_string_lossy().ends_with(".sweep.ron") {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            let tasks = sweep::expand(&path, &dir.join(&name)).unwrap();
            assert!(!tasks.is_empty(), "{name}");
            n += 1;
        }
    }
    assert!(n >= 2);
}
