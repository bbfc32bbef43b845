//! Faults a shared machine deals a run — a kill at the worst moment, a file-size limit,
//! racing commands on one target, long and odd names — each ending with whole results
//! or a clear error, and nothing left behind that the next run does not clear.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

mod common;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn tmp(name: &str) -> PathBuf {
    let dir = root().join("target").join("fault-tests").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn areo(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_areo")).args(args).output().unwrap()
}

/// A Sun-table scenario named `name` in `dir` whose optical depth is `tau`.
fn sun_scenario(dir: &Path, name: &str, tau: f64) -> PathBuf {
    common::sun_table(dir, name, (12.0, 10.0, tau))
}

/// The tau a run's facts.json records, which tells one run's set from another's.
fn tau_of(set: &Path) -> f64 {
    let facts: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(set.join("facts.json")).unwrap()).unwrap();
    facts["tau"].as_f64().unwrap_or_else(|| panic!("{facts}"))
}

/// The hidden staging entries left in `dir`.
fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.') && (n.contains(".partial-") || n.contains(".old-")))
        .collect()
}

/// Kills `child` once it has written `flag` (the test hook `AREO_PAUSE_BEFORE_PLACING`:
/// its outputs finished, not yet in place), and waits for it.
fn kill_when_paused(child: &mut std::process::Child, flag: &Path) {
    let t0 = std::time::Instant::now();
    while !flag.exists() {
        assert!(t0.elapsed().as_secs() < 60, "the run never reached the moment");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
}

fn ok(out: &Output) {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn a_run_killed_before_its_outputs_are_placed_keeps_the_previous_set_and_the_next_run_clears_its_leftovers() {
    let dir = tmp("killed");
    let out = dir.join("out");
    let scenario = sun_scenario(&dir, "sun", 0.4);
    ok(&areo(&["-q", "run", scenario.to_str().unwrap(), "--out", out.to_str().unwrap()]));
    assert_eq!(tau_of(&out.join("sun")), 0.4);
    // The next run, killed when its outputs are finished but not yet in place.
    sun_scenario(&dir, "sun", 0.9);
    let flag = dir.join("paused");
    let mut child = Command::new(env!("CARGO_BIN_EXE_areo"))
        .args(["-q", "run", scenario.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .env("AREO_PAUSE_BEFORE_PLACING", &flag)
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    kill_when_paused(&mut child, &flag);
    // The previous set is in place, whole; the killed run's staging is left over.
    assert_eq!(tau_of(&out.join("sun")), 0.4);
    assert!(out.join("sun/sun.csv").exists());
    let left = leftovers(&out);
    assert_eq!(left.len(), 1, "{left:?}");
    assert!(std::fs::read_to_string(&flag).unwrap().ends_with(&left[0]));
    // The next run puts its set in place and clears the dead run's leftovers.
    ok(&areo(&["-q", "run", scenario.to_str().unwrap(), "--out", out.to_str().unwrap()]));
    assert_eq!(tau_of(&out.join("sun")), 0.9);
    assert_eq!(leftovers(&out), Vec::<String>::new());
}

#[test]
fn runs_killed_at_any_moment_leave_one_whole_set() {
    let dir = tmp("kill-anywhere");
    let out = dir.join("out");
    let scenario = sun_scenario(&dir, "sun", 0.4);
    ok(&areo(&["-q", "run", scenario.to_str().unwrap(), "--out", out.to_str().unwrap()]));
    let files = |set: &Path| {
        let mut names: Vec<String> =
            std::fs::read_dir(set).unwrap().flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        names
    };
    let whole = files(&out.join("sun"));
    for (k, tau) in [0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.2].into_iter().enumerate() {
        sun_scenario(&dir, "sun", tau);
        let mut child = Command::new(env!("CARGO_BIN_EXE_areo"))
            .args(["-q", "run", scenario.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .stdout(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(3 * k as u64));
        let _ = child.kill();
        child.wait().unwrap();
        // Whatever the moment: one set, whole, the previous or the new.
        assert_eq!(files(&out.join("sun")), whole, "killed after {} ms", 3 * k);
        let t = tau_of(&out.join("sun"));
        assert!(t <= tau, "tau {t} after a run of {tau}");
    }
    ok(&areo(&["-q", "run", scenario.to_str().unwrap(), "--out", out.to_str().unwrap()]));
    assert_eq!(leftovers(&out), Vec::<String>::new());
}

#[test]
fn a_file_size_limit_is_an_error_naming_the_file_and_a_sweep_task_records_it() {
    let dir = tmp("fsize");
    let out = dir.join("out");
    let scenario = sun_scenario(&dir, "sun", 0.4);
    ok(&areo(&["-q", "run", scenario.to_str().unwrap(), "--out", out.to_str().unwrap()]));
    // A week of minutes is far more than 8 KB of sun.csv.
    common::sun_table(&dir, "sun", (168.0, 1.0, 0.9));
    let limited = |args: &str| {
        Command::new("sh")
            .args(["-c", &format!("ulimit -f 8; exec \"$0\" {args}"), env!("CARGO_BIN_EXE_areo")])
            .current_dir(&dir)
            .output()
            .unwrap()
    };
    let run = limited("-q run sun.ron --out out");
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{err}");
    assert!(err.contains("out/sun/sun.csv: File too large"), "{err}");
    assert_eq!(tau_of(&out.join("sun")), 0.4, "the previous set stays");
    assert_eq!(leftovers(&out), Vec::<String>::new());
    // A sweep task under the same limit records why it failed.
    common::tau_sweep(&dir, "sun.ron", (0.25, 0.5, 0.25));
    ok(&areo(&[
        "-q",
        "sweep",
        "expand",
        dir.join("tau.sweep.ron").to_str().unwrap(),
        "-o",
        dir.join("sweep").to_str().unwrap(),
    ]));
    let task = limited("-q sweep run sweep --index 0");
    assert_eq!(task.status.code(), Some(1), "{}", String::from_utf8_lossy(&task.stderr));
    let failed = std::fs::read_to_string(dir.join("sweep/failed/tau-0.25.txt")).unwrap();
    assert!(failed.contains("File too large"), "{failed}");
    let collected =
        String::from_utf8_lossy(&areo(&["sweep", "collect", dir.join("sweep").to_str().unwrap()]).stdout).into_owned();
    assert!(collected.contains("0 finished, 1 missing, 1 failed"), "{collected}");
}

/// Runs `n` copies of `args` at once; returns their outputs.
fn racing(n: usize, args: &[String]) -> Vec<Output> {
    let children: Vec<_> = (0..n)
        .map(|_| {
            Command::new(env!("CARGO_BIN_EXE_areo"))
                .args(args)
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    children.into_iter().map(|c| c.wait_with_output().unwrap()).collect()
}

#[test]
fn racing_writers_of_one_target_all_succeed_and_leave_it_whole() {
    let dir = tmp("race");
    let s = |v: &[&str]| v.iter().map(|a| a.to_string()).collect::<Vec<_>>();
    // Ten slope maps of one DEM into one file.
    let dem = root().join("crates/terrain/tests/data/gale_mola_crop_64.tif");
    let slope = dir.join("same.tif");
    for o in racing(10, &s(&["-q", "terrain", "slope", dem.to_str().unwrap(), "-o", slope.to_str().unwrap()])) {
        ok(&o);
    }
    let info = String::from_utf8_lossy(&areo(&["terrain", "info", slope.to_str().unwrap()]).stdout).into_owned();
    assert!(info.contains("64 × 64 cells"), "{info}");
    assert_eq!(leftovers(&dir), Vec::<String>::new());
    // Ten runs of one scenario into one --out.
    let out = dir.join("out");
    let scenario = sun_scenario(&dir, "sun", 0.6);
    for o in racing(10, &s(&["-q", "run", scenario.to_str().unwrap(), "--out", out.to_str().unwrap()])) {
        ok(&o);
    }
    assert_eq!(tau_of(&out.join("sun")), 0.6);
    assert_eq!(leftovers(&out), Vec::<String>::new());
    // Ten collects of one sweep.
    common::tau_sweep(&dir, "sun.ron", (0.25, 1.0, 0.25));
    let sweep = dir.join("sweep");
    ok(&areo(&["-q", "sweep", "expand", dir.join("tau.sweep.ron").to_str().unwrap(), "-o", sweep.to_str().unwrap()]));
    ok(&areo(&["-q", "sweep", "run", sweep.to_str().unwrap(), "--index", "1"]));
    for o in racing(10, &s(&["sweep", "collect", sweep.to_str().unwrap()])) {
        ok(&o);
        assert!(String::from_utf8_lossy(&o.stdout).starts_with("1 finished, 3 missing, 0 failed"));
    }
    let results = std::fs::read_to_string(sweep.join("results.csv")).unwrap();
    assert_eq!(results.lines().count(), 5, "{results}");
}

#[test]
fn two_sweeps_expanded_into_one_directory_at_once_leave_one_expansion() {
    let dir = tmp("expand-race");
    sun_scenario(&dir, "sun", 0.5);
    for (name, axis) in [("a", "(0.25, 1.0, 0.25)"), ("b", "(0.1, 0.9, 0.1)")] {
        std::fs::write(
            dir.join(format!("{name}.sweep.ron")),
            format!(
                r#"Sweep(version: 1, base: "sun.ron", name: "{name}-{{tau}}", axes: [(name: "tau", path: "job.tau", range: {axis})])"#
            ),
        )
        .unwrap();
    }
    let sweep = dir.join("sweep");
    let children: Vec<_> = ["a", "b"]
        .iter()
        .map(|name| {
            Command::new(env!("CARGO_BIN_EXE_areo"))
                .args(["-q", "sweep", "expand", dir.join(format!("{name}.sweep.ron")).to_str().unwrap()])
                .args(["-o", sweep.to_str().unwrap()])
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    let outs: Vec<Output> = children.into_iter().map(|c| c.wait_with_output().unwrap()).collect();
    let won: Vec<usize> = (0..2).filter(|&i| outs[i].status.success()).collect();
    assert_eq!(won.len(), 1, "one expansion wins: {:?}", outs.iter().map(|o| o.status.code()).collect::<Vec<_>>());
    let lost = &outs[1 - won[0]];
    assert_eq!(lost.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&lost.stderr).contains("holds the expansion of another sweep"));
    // The manifest and the task files are the winner's, and only its.
    let prefix = ["a-", "b-"][won[0]];
    let manifest = std::fs::read_to_string(sweep.join("manifest.jsonl")).unwrap();
    let ids: Vec<String> = manifest
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap()["id"].as_str().unwrap().to_string())
        .collect();
    assert!(ids.iter().all(|id| id.starts_with(prefix)), "{ids:?}");
    let mut files: Vec<String> = std::fs::read_dir(sweep.join("tasks"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().trim_end_matches(".ron").to_string())
        .collect();
    files.sort();
    let mut want = ids.clone();
    want.sort();
    assert_eq!(files, want);
}

#[test]
fn a_long_run_name_fits_its_staging_and_a_name_that_is_not_utf8_is_refused() {
    let dir = tmp("names");
    // 245 bytes: legal, and the longest a `.ron` file's stem can be.
    let long = "é".repeat(100) + &"x".repeat(45);
    assert_eq!(long.len(), 245);
    let scenario = sun_scenario(&dir, &long, 0.5);
    let out = dir.join("out");
    ok(&areo(&["-q", "run", scenario.to_str().unwrap(), "--out", out.to_str().unwrap()]));
    assert_eq!(tau_of(&out.join(&long)), 0.5);
    assert_eq!(leftovers(&out), Vec::<String>::new());
    // Latin-1 "café": not UTF-8, refused rather than written as U+FFFD.
    use std::os::unix::ffi::OsStrExt;
    let latin1 = dir.join(std::ffi::OsStr::from_bytes(b"caf\xe9.ron"));
    std::fs::copy(&scenario, &latin1).unwrap();
    let refused = Command::new(env!("CARGO_BIN_EXE_areo"))
        .arg("run")
        .arg(&latin1)
        .args(["--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{err}");
    assert!(err.contains("not UTF-8"), "{err}");
    assert!(!out.join("caf\u{fffd}").exists());
}

/// `terrain horizon` puts its sector set in place as one directory: killed when the set
/// is finished but not yet placed, or at any moment, the directory holds the previous
/// set or the new one, whole — never sectors of two runs.
#[test]
fn a_horizon_map_killed_at_any_moment_leaves_one_whole_set() {
    let dir = tmp("horizon-kill");
    let (dem, out) = (root().join("crates/terrain/tests/data/gale_mola_crop_64.tif"), dir.join("h"));
    let run = |sectors: &str| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_areo"));
        c.args(["-q", "terrain", "horizon", dem.to_str().unwrap(), "--sectors", sectors, "-o", out.to_str().unwrap()]);
        c
    };
    let set = || {
        let mut names: Vec<String> =
            std::fs::read_dir(&out).unwrap().flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        names
    };
    let whole = |n: usize| (0..n).map(|s| format!("s{s:03}.tif")).collect::<Vec<_>>();
    ok(&run("16").output().unwrap());
    assert_eq!(set(), whole(16));
    let first = std::fs::read(out.join("s003.tif")).unwrap();
    let flag = dir.join("paused");
    let mut child = run("32").env("AREO_PAUSE_BEFORE_PLACING", &flag).spawn().unwrap();
    kill_when_paused(&mut child, &flag);
    assert_eq!(set(), whole(16), "the previous set, whole");
    assert_eq!(std::fs::read(out.join("s003.tif")).unwrap(), first);
    assert_eq!(leftovers(&dir).len(), 1);
    for (k, sectors) in ["32", "16", "32", "16", "32"].into_iter().enumerate() {
        let mut child = run(sectors).stdout(Stdio::null()).spawn().unwrap();
        std::thread::sleep(std::time::Duration::from_millis(5 + 15 * k as u64));
        let _ = child.kill();
        child.wait().unwrap();
        let now = set();
        assert!(now == whole(16) || now == whole(32), "kill {k}: {now:?}");
    }
    ok(&run("32").output().unwrap());
    assert_eq!(set(), whole(32));
    assert_eq!(leftovers(&dir), Vec::<String>::new(), "the dead runs' staging is cleared");
    // A GeoTIFF's name without --tile is refused, saying what the output is.
    let o = Command::new(env!("CARGO_BIN_EXE_areo"))
        .args([
            "terrain",
            "horizon",
            dem.to_str().unwrap(),
            "--sectors",
            "16",
            "-o",
            dir.join("h.tif").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("directory"), "{}", String::from_utf8_lossy(&o.stderr));
}
