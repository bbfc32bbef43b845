//! Standard output that cannot be written: every subcommand that prints, with its
//! reader gone before it writes (a closed pipe), with its reader gone after the first
//! line, and onto a full device (`/dev/full`). A closed pipe ends the process quietly
//! with 141, the status a shell gives a writer SIGPIPE killed; a full device is exit 1
//! with a message naming standard output; never a panic, and a run's files are whole
//! either way.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

mod common;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn tmp(name: &str) -> PathBuf {
    let dir = root().join("target").join("console-tests").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The commands that print, each a short name and its arguments. A sweep directory
/// (expanded and collected) and a run's output directory are made under `dir`.
fn commands(dir: &Path) -> Vec<(&'static str, Vec<String>)> {
    let s = |v: &[&str]| v.iter().map(|a| a.to_string()).collect::<Vec<_>>();
    let p = |path: PathBuf| path.to_str().unwrap().to_string();
    common::sun_table(dir, "sun", (2.0, 30.0, 0.5));
    common::tau_sweep(dir, "sun.ron", (0.25, 1.0, 0.25));
    let sweep = p(dir.join("sweep"));
    let expand = Command::new(env!("CARGO_BIN_EXE_areo"))
        .args(["-q", "sweep", "expand", &p(dir.join("tau.sweep.ron")), "-o", &sweep])
        .output()
        .unwrap();
    assert!(expand.status.success(), "{}", String::from_utf8_lossy(&expand.stderr));
    let dem = p(root().join("crates/terrain/tests/data/gale_mola_crop_64.tif"));
    let movingai = root().join("crates/ise/tests/data/movingai");
    vec![
        ("sun rows", s(&["sun", "--from", "2012-08-06T00:00:00Z", "--to", "2012-08-07T00:00:00Z", "--step", "1min"])),
        (
            "sun csv",
            s(&[
                "sun",
                "--from",
                "2012-08-06T00:00:00Z",
                "--to",
                "2012-08-06T06:00:00Z",
                "--step",
                "1min",
                "--format",
                "csv",
            ]),
        ),
        ("sun sol", s(&["sun", "--sol", "49269", "--lat", "-4.59", "--lon", "137.44"])),
        (
            "sun day",
            s(&["sun", "--body", "moon", "--day", "2025-03-01", "--lat", "-89.5", "--lon", "45", "--format", "json"]),
        ),
        ("terrain info", s(&["terrain", "info", &dem])),
        ("terrain info json", s(&["terrain", "info", &dem, "--json"])),
        ("terrain slope", s(&["terrain", "slope", &dem, "-o", &p(dir.join("slope.tif"))])),
        (
            "terrain shadow",
            s(&[
                "terrain",
                "shadow",
                &dem,
                "--sun-azimuth",
                "90",
                "--sun-elevation",
                "10",
                "-o",
                &p(dir.join("sh.tif")),
            ]),
        ),
        ("terrain horizon", s(&["terrain", "horizon", &dem, "--sectors", "16", "-o", &p(dir.join("hz"))])),
        (
            "terrain viewshed",
            s(&["terrain", "viewshed", &dem, "--from", "8120000,-310000,2", "-o", &p(dir.join("vs.tif"))]),
        ),
        ("rover check", s(&["rover", "check", &p(root().join("crates/rover/params/lsr1.ron")), "--terrain", "flat"])),
        ("grid", s(&["grid", "--map", &p(movingai.join("arena.map")), "--scen", &p(movingai.join("arena.map.scen"))])),
        ("run", s(&["run", &p(dir.join("sun.ron")), "--out", &p(dir.join("out"))])),
        ("run json", s(&["run", &p(dir.join("sun.ron")), "--out", &p(dir.join("out-json")), "--json"])),
        ("sweep expand", s(&["sweep", "expand", &p(dir.join("tau.sweep.ron")), "-o", &p(dir.join("sweep-2"))])),
        ("sweep run", s(&["sweep", "run", &sweep, "--index", "0", "--force"])),
        ("sweep collect", s(&["sweep", "collect", &sweep])),
        ("sweep slurm", s(&["sweep", "slurm", &sweep])),
        ("sweep k8s", s(&["sweep", "k8s", &sweep])),
        ("completions", s(&["completions", "bash"])),
    ]
}

fn no_panic(name: &str, out: &Output) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked") && !err.contains("RUST_BACKTRACE"), "{name}: {err}");
}

/// Runs `args` with standard output on a pipe whose reader is already closed.
fn into_closed_pipe(args: &[String]) -> Output {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    Command::new(env!("CARGO_BIN_EXE_areo")).args(args).stdout(writer).stderr(Stdio::piped()).output().unwrap()
}

#[test]
fn a_closed_pipe_ends_every_printing_command_quietly_with_141() {
    let dir = tmp("closed");
    for (name, args) in commands(&dir) {
        let out = into_closed_pipe(&args);
        no_panic(name, &out);
        assert_eq!(out.status.code(), Some(141), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        assert!(out.stderr.is_empty(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
    }
    // The run wrote its files before it printed: they are whole.
    for run in ["out", "out-json"] {
        let facts = std::fs::read_to_string(dir.join(run).join("sun/facts.json")).unwrap();
        assert!(serde_json::from_str::<serde_json::Value>(&facts).is_ok(), "{run}: {facts}");
        assert!(dir.join(run).join("sun/sun.csv").exists(), "{run}");
    }
}

#[test]
fn a_reader_that_leaves_after_the_first_line_ends_the_command_quietly_with_141() {
    // A day of minutes (1441 rows) is far more than a pipe holds.
    let mut child = Command::new(env!("CARGO_BIN_EXE_areo"))
        .args(["sun", "--from", "2012-08-06T00:00:00Z", "--to", "2012-08-07T00:00:00Z", "--step", "1min"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut first).unwrap();
    assert!(first.contains("2012-08-06T00:00:00"), "{first}");
    let out = child.wait_with_output().unwrap();
    no_panic("sun", &out);
    assert_eq!(out.status.code(), Some(141));
    assert!(out.stderr.is_empty(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn a_full_device_is_exit_1_naming_standard_output() {
    let dir = tmp("full");
    for (name, args) in commands(&dir) {
        let full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_areo")).args(&args).stdout(full).output().unwrap();
        no_panic(name, &out);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{name}: {err}");
        assert!(err.contains("(standard output)") && err.contains("No space left on device"), "{name}: {err}");
    }
    let facts = std::fs::read_to_string(dir.join("out/sun/facts.json")).unwrap();
    assert!(serde_json::from_str::<serde_json::Value>(&facts).is_ok(), "{facts}");
}

#[test]
fn the_sun_table_keeps_the_memory_budget_and_says_so_before_it_computes() {
    let dir = tmp("sun-budget");
    // 400 000 instants: about 0.34 GiB of rows to print.
    let mut text = String::new();
    for k in 0..400_000u32 {
        text += &format!("2012-08-{:02}T{:02}:{:02}:{:02}Z\n", 6 + k / 86_400, k / 3600 % 24, k / 60 % 60, k % 60);
    }
    let times = dir.join("times.txt");
    std::fs::write(&times, text).unwrap();
    let out = Command::new("sh")
        .args(["-c", "ulimit -v 1000000; exec \"$0\" --max-memory-gb 0.25 sun --times-file \"$1\""])
        .args([env!("CARGO_BIN_EXE_areo"), times.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("a Sun table of 400000 instants needs about 0.34 GiB") && err.contains("0.25 GiB allowed"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
    // Within a budget that holds it, it prints every row.
    let out = Command::new(env!("CARGO_BIN_EXE_areo"))
        .args(["--max-memory-gb", "0.5", "sun", "--times-file", times.to_str().unwrap(), "--format", "csv"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(String::from_utf8_lossy(&out.stdout).lines().count(), 400_001);
}
