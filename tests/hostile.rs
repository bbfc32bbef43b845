//! Hostile input end to end (issue 25): names that would become paths, duplicates,
//! outputs over inputs, missing referenced files, budgets, stale outputs, and the exit
//! code of each (0 success, 1 failure while running, 2 bad input, 3 unreachable).

use std::path::PathBuf;
use std::process::{Command, Output};

fn areo(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_areo")).args(args).output().expect("run areo")
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn tmp(tag: &str) -> PathBuf {
    let dir = root().join("target").join("hostile-tests").join(tag);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A shipped scenario with `from` replaced by `to`, written into `dir` (with the shipped
/// rover files beside it), run into `dir/out`.
fn run_variant(dir: &std::path::Path, scenario: &str, from: &str, to: &str) -> Output {
    let path = write_variant(dir, scenario, from, to);
    areo(&["-q", "run", path.to_str().unwrap(), "--out", dir.join("out").to_str().unwrap()])
}

/// The variant's file (and the rover files beside it), not run.
fn write_variant(dir: &std::path::Path, scenario: &str, from: &str, to: &str) -> PathBuf {
    let text = std::fs::read_to_string(root().join("scenarios").join(scenario)).unwrap();
    assert!(text.contains(from), "{scenario} contains {from:?}");
    let path = dir.join(scenario);
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    let rovers = dir.join("rovers");
    std::fs::create_dir_all(&rovers).unwrap();
    for f in std::fs::read_dir(root().join("scenarios/rovers")).unwrap() {
        let f = f.unwrap().path();
        std::fs::copy(&f, rovers.join(f.file_name().unwrap())).unwrap();
    }
    path
}

#[test]
fn a_name_that_would_be_a_path_is_refused_where_it_is_written() {
    let dir = tmp("names");
    let out = run_variant(&dir, "friction-sweep.ron", "name: \"", "name: \"../../../escaped");
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("field `job.runs[0].name`") && err.contains("letters, digits"), "{err}");
    assert!(err.contains("friction-sweep.ron:"), "{err}");
    assert!(!dir.join("escaped").exists() && !root().join("escaped").exists());
}

#[test]
fn duplicate_goal_names_are_refused() {
    let dir = tmp("duplicates");
    let out = run_variant(&dir, "valley-detour.ron", "name: \"goal2\"", "name: \"goal1\"");
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("field `job.goals[1].name`") && err.contains("used twice"), "{err}");
}

#[test]
fn a_missing_rover_file_is_bad_input_naming_the_field() {
    let dir = tmp("missing-rover");
    let out = run_variant(&dir, "steep-hill.ron", "rovers/lsr1-instrument-arm.ron", "rovers/none.ron");
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("field `job.rover`") && err.contains("rovers/none.ron"), "{err}");
}

#[test]
fn a_rover_value_out_of_range_is_placed_at_its_line_and_column() {
    let dir = tmp("rover-range");
    write_variant(&dir, "steep-hill.ron", "rovers/lsr1-instrument-arm.ron", "rovers/lsr1-instrument-arm.ron");
    let rover = dir.join("rovers/lsr1-instrument-arm.ron");
    let text = std::fs::read_to_string(&rover).unwrap();
    let at = text.find("mass_kg:").expect("the rover file gives its mass");
    let line = text[..at].lines().count() + usize::from(text[..at].ends_with('\n'));
    let value_end = at + text[at..].find([',', '\n']).unwrap();
    std::fs::write(&rover, format!("{}mass_kg: 1e308{}", &text[..at], &text[value_end..])).unwrap();
    let out =
        areo(&["-q", "run", dir.join("steep-hill.ron").to_str().unwrap(), "--out", dir.join("o").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains(&format!("lsr1-instrument-arm.ron:{line}:")), "line {line}: {err}");
    assert!(err.contains("mass_kg") && err.contains("1e308") && err.contains("10000"), "{err}");
    assert!(err.contains("field `job.rover`"), "{err}");
}

#[test]
fn a_rerun_replaces_the_outputs_as_a_set() {
    let dir = tmp("rerun");
    let scenario = root().join("scenarios/gale-sol-sun.ron");
    let out_dir = dir.join("out");
    let run = || areo(&["-q", "run", scenario.to_str().unwrap(), "--out", out_dir.to_str().unwrap()]);
    assert!(run().status.success());
    let stale = out_dir.join("gale-sol-sun/from-an-older-run.csv");
    std::fs::write(&stale, "old\n").unwrap();
    let out = run();
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!stale.exists(), "a file of an earlier run does not survive beside the new ones");
    assert!(out_dir.join("gale-sol-sun/sun.csv").exists());
    // Nothing is left in --out but the scenario's directory (no staging, no old copy).
    let left: Vec<_> = std::fs::read_dir(&out_dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left, vec![std::ffi::OsString::from("gale-sol-sun")]);
    // The summary names the files where they now are.
    assert!(String::from_utf8_lossy(&out.stdout).contains("gale-sol-sun/sun.csv"));
    assert!(!String::from_utf8_lossy(&out.stdout).contains("partial"));
}

#[test]
fn a_job_over_its_memory_budget_is_refused_with_the_estimate() {
    let scenario = root().join("scenarios/crater-morning-shadows.ron");
    let dir = tmp("budget");
    let out = areo(&["run", scenario.to_str().unwrap(), "--out", dir.to_str().unwrap(), "--max-memory-gb", "0.0001"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("GiB") && err.contains("--max-memory-gb") && err.contains("cells"), "{err}");
    assert!(!dir.join("crater-morning-shadows").exists(), "refused before anything is written");
    let out = areo(&["run", scenario.to_str().unwrap(), "--max-memory-gb", "-1"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn terrain_outputs_never_replace_the_input_or_become_the_preview() {
    let dir = tmp("terrain-out");
    let dem = dir.join("dem.asc");
    std::fs::write(&dem, "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5 6\n").unwrap();
    // -o the input itself (an .asc: refused as not a GeoTIFF name), a .tif whose
    // preview would be the input, and a PNG name.
    let cases = [(dir.join("dem.asc"), "GeoTIFF"), (dir.join("x.png"), "GeoTIFF"), (dir.join("./dem.tif"), "")];
    for (out, _) in &cases[..2] {
        let o = areo(&["terrain", "slope", dem.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(stderr(&o).contains("GeoTIFF"), "{}", stderr(&o));
    }
    assert_eq!(std::fs::read_to_string(&dem).unwrap().lines().count(), 7, "the input is untouched");
    let png_input = dir.join("map.png");
    std::fs::write(&png_input, b"not really").unwrap();
    let o = areo(&["terrain", "slope", dem.to_str().unwrap(), "-o", dir.join("map.tif").to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A GeoTIFF input and -o the same file: refused, the DEM kept.
    let tif = dir.join("map.tif");
    let before = std::fs::read(&tif).unwrap();
    let o = areo(&["terrain", "slope", tif.to_str().unwrap(), "-o", dir.join("./map.tif").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("overwrite the input"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&tif).unwrap(), before);
}

#[test]
fn an_all_missing_dem_says_so_and_bad_viewshed_heights_are_refused() {
    let dir = tmp("nodata");
    let dem = dir.join("empty.asc");
    std::fs::write(
        &dem,
        "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n-9999 -9999\n-9999 -9999\n",
    )
    .unwrap();
    let o = areo(&["terrain", "info", dem.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("every cell is missing") && !text.contains("3.4"), "{text}");
    let ok = dir.join("ok.asc");
    std::fs::write(&ok, "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5 6\n").unwrap();
    for from in ["1,1,0", "1,1,-2", "99,1,2"] {
        let o = areo(&[
            "terrain",
            "viewshed",
            ok.to_str().unwrap(),
            "--from",
            from,
            "-o",
            dir.join("v.tif").to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{from}: {}", stderr(&o));
    }
}

#[test]
fn a_header_declaring_billions_of_cells_is_refused_before_allocating() {
    let dir = tmp("huge-header");
    let dem = dir.join("huge.asc");
    std::fs::write(&dem, "ncols 63245\nnrows 63245\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n").unwrap();
    let o = areo(&["terrain", "info", dem.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("can hold at most"), "{}", stderr(&o));
}

#[test]
fn grid_exits_3_when_a_goal_is_unreachable_and_refuses_other_map_types() {
    let dir = tmp("grid");
    let map = dir.join("wall.map");
    std::fs::write(&map, "type octile\nheight 3\nwidth 3\nmap\n.@.\n.@.\n.@.\n").unwrap();
    let scen = dir.join("wall.map.scen");
    std::fs::write(&scen, "version 1\n0\twall.map\t3\t3\t0\t0\t2\t0\t2\n").unwrap();
    let o = areo(&["grid", "--map", map.to_str().unwrap(), "--scen", scen.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("no path"), "{}", stderr(&o));
    let hex = dir.join("hex.map");
    std::fs::write(&hex, "type hex\nheight 3\nwidth 3\nmap\n...\n...\n...\n").unwrap();
    let o = areo(&["grid", "--map", hex.to_str().unwrap(), "--scen", scen.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("octile"), "{}", stderr(&o));
}

#[test]
fn a_sol_outside_the_ephemeris_is_refused_at_once() {
    let o = areo(&["sun", "--sol=-1000000000", "--lat", "0", "--lon", "0"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("-97000..=258000"), "{}", stderr(&o));
}

#[test]
fn a_goal_off_the_map_is_placed_at_its_line_and_indexed() {
    let dir = tmp("goal-off-map");
    let out = run_variant(&dir, "valley-detour.ron", "(name: \"goal2\", x_m: 250,", "(name: \"goal2\", x_m: 99999,");
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    let text = std::fs::read_to_string(dir.join("valley-detour.ron")).unwrap();
    let line = text.lines().position(|l| l.contains("x_m: 99999")).unwrap() + 1;
    assert!(err.contains(&format!("valley-detour.ron:{line}:")), "line {line}: {err}");
    assert!(err.contains("field `job.goals[1]`") && err.contains("off the map"), "{err}");
}

#[test]
fn a_full_disk_is_a_failure_while_running_not_bad_input() {
    // The output's temporary name points at /dev/full: every write fails with ENOSPC.
    if !std::path::Path::new("/dev/full").exists() {
        panic!("/dev/full is needed to simulate a full disk");
    }
    let dir = tmp("full-disk");
    let dem = dir.join("dem.asc");
    std::fs::write(&dem, "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5 6\n").unwrap();
    std::os::unix::fs::symlink("/dev/full", dir.join("slope.tif.partial")).unwrap();
    let out = areo(&["terrain", "slope", dem.to_str().unwrap(), "-o", dir.join("slope.tif").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("slope.tif") && err.to_lowercase().contains("no space"), "{err}");
    assert!(!dir.join("slope.tif").exists(), "no file under the real name");
}
