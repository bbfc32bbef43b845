//! Hostile input end to end: names that would become paths, duplicates,
//! outputs over inputs, missing referenced files, budgets, stale outputs, and the exit
//! code of each (0 success, 1 failure while running, 2 bad input, 3 unreachable).

use std::path::PathBuf;
use std::process::{Command, Output};

mod common;

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
    let out = run_variant(&dir, "friction-scan.ron", "name: \"", "name: \"../../../escaped");
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("field `job.runs[0].name`") && err.contains("letters, digits"), "{err}");
    assert!(err.contains("friction-scan.ron:"), "{err}");
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
    // Every job validates its ground the same way: the terrain-shadow job refuses a
    // map with no heights and heights beyond ±1e7 m as TEMPEST does.
    let huge = dir.join("huge.asc");
    std::fs::write(&huge, "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 3.4028235e38\n-3.4028235e38 2\n")
        .unwrap();
    for (map, says) in [("empty.asc", "every cell is missing"), ("huge.asc", "within ±1e7 m")] {
        let scenario = dir.join("shadow.ron");
        std::fs::write(
            &scenario,
            format!(
                "Scenario(version: 1, description: \"x\", job: TerrainShadow(terrain: File(\"{map}\"), \
                 site: (lat_deg: -4.5, lon_east_deg: 137.4), utc: \"2012-08-06T23:00:00Z\"))"
            ),
        )
        .unwrap();
        let o = areo(&["-q", "run", scenario.to_str().unwrap(), "-o", dir.join("out").to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{map}: {}", stderr(&o));
        assert!(stderr(&o).contains(says) && stderr(&o).contains("job.terrain"), "{map}: {}", stderr(&o));
    }
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
    // A file-size limit of zero makes every write fail as a full disk would (EFBIG,
    // with the signal it would raise ignored); areo no longer follows a planted link at
    // its staging name, which is how this was once simulated with /dev/full.
    let dir = tmp("full-disk");
    let dem = dir.join("dem.asc");
    std::fs::write(&dem, "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5 6\n").unwrap();
    let out = Command::new("bash")
        .arg("-c")
        .arg("trap '' XFSZ; ulimit -f 0; exec \"$0\" terrain slope \"$1\" -o \"$2\"")
        .arg(env!("CARGO_BIN_EXE_areo"))
        .arg(&dem)
        .arg(dir.join("slope.tif"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("slope.tif") && err.to_lowercase().contains("file too large"), "{err}");
    assert!(!dir.join("slope.tif").exists(), "no file under the real name");
}

// ---- Round 2: files that are not what they seem, sweeps and scripts,
// budgets on every command. Each test is one class; each case exits 2 (or the class's
// documented code) within its time, never 101, never hangs.

/// A detached PDS3 label whose LINES × line bytes overflows 64 bits, and one with an
/// unclosed quote a megabyte long: refused (exit 2) at once.
#[test]
fn pds3_labels_that_overflow_or_never_close_are_refused_quickly() {
    let dir = tmp("pds3-hostile");
    let img = dir.join("big.img");
    std::fs::write(&img, [0u8; 64]).unwrap();
    std::fs::write(
        dir.join("big.lbl"),
        "PDS_VERSION_ID = PDS3\nRECORD_BYTES = 1\n^IMAGE = (\"big.img\", 1)\nOBJECT = IMAGE\nLINES = 4000000000\n\
         LINE_SAMPLES = 1\nSAMPLE_TYPE = PC_REAL\nSAMPLE_BITS = 64\nLINE_PREFIX_BYTES = 1099511627776\n\
         LINE_SUFFIX_BYTES = 1099511627776\nEND_OBJECT = IMAGE\nEND\n",
    )
    .unwrap();
    let o = areo(&["terrain", "info", img.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("more than 2^64") || stderr(&o).contains("truncated"), "{}", stderr(&o));

    let quoted = dir.join("quote.lbl");
    let mut text = String::from("PDS_VERSION_ID = PDS3\nNOTE = \"never closed\n");
    for _ in 0..40_000 {
        text.push_str("more text on another line of the unclosed quote\n");
    }
    std::fs::write(&quoted, text).unwrap();
    let clock = std::time::Instant::now();
    let o = areo(&["terrain", "info", quoted.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    // Linear in the label: well under a second (it took 33 s when quadratic).
    assert!(clock.elapsed().as_secs_f64() < 10.0, "{:?}", clock.elapsed());
}

/// FIFOs and devices as inputs: a scenario's rover file, a DEM, a list of instants, a
/// sweep's base — refused by what they are, without blocking or reading forever.
#[cfg(unix)]
#[test]
fn fifos_and_devices_are_refused_as_inputs() {
    let dir = tmp("special");
    let fifo = dir.join("pipe.tif");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    for (args, what) in [
        (vec!["terrain", "info", fifo.to_str().unwrap()], "a FIFO"),
        (vec!["terrain", "info", "/dev/zero"], "a character device"),
        (vec!["sun", "--times-file", "/dev/zero"], "a character device"),
    ] {
        let o = areo(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(what), "{args:?}: {}", stderr(&o));
    }
    let path = write_variant(&dir, "devon-island.ron", "rover: \"rovers/hyperion-devon.ron\"", "rover: \"/dev/zero\"");
    let o = areo(&["-q", "run", path.to_str().unwrap(), "-o", dir.join("out").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("character device"), "{}", stderr(&o));
}

/// Brackets nested 50 000 deep in a scenario: refused at the first one past the limit,
/// located, at once.
#[test]
fn deep_nesting_is_refused_where_it_passes_the_limit() {
    let dir = tmp("nesting");
    let path = dir.join("deep.ron");
    let text = format!(
        "Scenario(version: 1, description: \"x\", job: SunTable(site: {}1{}))",
        "[".repeat(50_000),
        "]".repeat(50_000)
    );
    std::fs::write(&path, text).unwrap();
    let clock = std::time::Instant::now();
    let o = areo(&["run", path.to_str().unwrap(), "-o", dir.join("out").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("deep.ron:1:") && stderr(&o).contains("nested deeper than 64"), "{}", stderr(&o));
    assert!(clock.elapsed().as_secs_f64() < 10.0);
}

/// Counts past their range are refused before anything is named or allocated:
/// `--sectors` of 2^64 − 1 and 10^8, a sweep range whose count is infinite, a grid
/// optimum of `inf`.
#[test]
fn huge_counts_are_refused_before_allocating() {
    let dir = tmp("counts");
    let dem = dir.join("ok.asc");
    std::fs::write(&dem, "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5 6\n").unwrap();
    for n in ["18446744073709551615", "100000000", "15"] {
        let o = areo(&[
            "terrain",
            "horizon",
            dem.to_str().unwrap(),
            "--sectors",
            n,
            "-o",
            dir.join("h.tif").to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{n}: {}", stderr(&o));
    }
    std::fs::write(dir.join("base.ron"), std::fs::read_to_string(root().join("scenarios/gale-sol-sun.ron")).unwrap())
        .unwrap();
    let sweep = dir.join("tiny.sweep.ron");
    std::fs::write(
        &sweep,
        "Sweep(version: 1, base: \"base.ron\", axes: [(name: \"t\", path: \"job.tau\", range: (0.1, 0.9, 1e-320))])",
    )
    .unwrap();
    let o = areo(&["sweep", "expand", sweep.to_str().unwrap(), "-o", dir.join("s").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("at most"), "{}", stderr(&o));
    std::fs::write(dir.join("m.map"), "type octile\nheight 2\nwidth 2\nmap\n..\n..\n").unwrap();
    std::fs::write(dir.join("m.scen"), "version 1\n0\tm.map\t2\t2\t0\t0\t1\t1\tinf\n").unwrap();
    let o =
        areo(&["grid", "--map", dir.join("m.map").to_str().unwrap(), "--scen", dir.join("m.scen").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

/// Outputs never replace inputs through a link, and a planted link at a staging name
/// is not followed.
#[cfg(unix)]
#[test]
fn links_never_turn_an_output_into_an_input() {
    let dir = tmp("links");
    let real = dir.join("real.tif");
    let ok = dir.join("ok.asc");
    std::fs::write(&ok, "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5 6\n").unwrap();
    assert!(areo(&["terrain", "slope", ok.to_str().unwrap(), "-o", real.to_str().unwrap()]).status.success());
    let link = dir.join("in.tif");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    let before = std::fs::read(&real).unwrap();
    let o = areo(&["terrain", "slope", link.to_str().unwrap(), "-o", real.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("overwrite the input"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&real).unwrap(), before, "the DEM behind the link is untouched");
}

/// A manifest whose task id is a path, and a manifest that disagrees with sweep.json:
/// errors, nothing written outside the sweep; expanding another sweep into a used
/// directory is refused without --force.
#[test]
fn sweep_directories_are_checked_before_use() {
    let dir = tmp("sweep-dir");
    std::fs::write(dir.join("base.ron"), std::fs::read_to_string(root().join("scenarios/gale-sol-sun.ron")).unwrap())
        .unwrap();
    let a = dir.join("a.sweep.ron");
    std::fs::write(
        &a,
        "Sweep(version: 1, base: \"base.ron\", axes: [(name: \"t\", path: \"job.tau\", values: [0.5, 0.9])])",
    )
    .unwrap();
    let out = dir.join("s");
    let o = areo(&["sweep", "expand", a.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Another sweep into the same directory.
    let b = dir.join("b.sweep.ron");
    std::fs::write(
        &b,
        "Sweep(version: 1, base: \"base.ron\", axes: [(name: \"t\", path: \"job.tau\", values: [0.1])])",
    )
    .unwrap();
    let o = areo(&["sweep", "expand", b.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("another sweep"), "{}", stderr(&o));
    assert!(areo(&["sweep", "expand", b.to_str().unwrap(), "-o", out.to_str().unwrap(), "--force"]).status.success());
    // A task id that is a path.
    let manifest = out.join("manifest.jsonl");
    let text = std::fs::read_to_string(&manifest).unwrap();
    std::fs::write(&manifest, text.replace("\"id\":\"0\"", "\"id\":\"../../x\"")).unwrap();
    let o = areo(&["sweep", "run", out.to_str().unwrap(), "--index", "0"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("task id"), "{}", stderr(&o));
    assert!(!dir.join("x.txt").exists() && !root().join("target/x.txt").exists());
    // An empty manifest while sweep.json says 1 task.
    std::fs::write(&manifest, "").unwrap();
    let o = areo(&["sweep", "collect", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("sweep.json says 1"), "{}", stderr(&o));
}

/// A GeoTIFF whose keys say a central meridian of infinity, or a semi-major axis of
/// 1e-300 m: refused with the key named.
#[test]
fn geotiff_keys_out_of_range_are_refused_by_name() {
    let dir = tmp("geokeys");
    let ok = dir.join("ok.asc");
    std::fs::write(&ok, "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5 6\n").unwrap();
    let good = dir.join("good.tif");
    assert!(areo(&["terrain", "slope", ok.to_str().unwrap(), "-o", good.to_str().unwrap()]).status.success());
    let bytes = std::fs::read(&good).unwrap();
    // The GeoDoubleParams hold the semi-major axis first: find it (3396190 or the
    // default body's radius) and plant a bad value.
    let radius = f64::from_bits(u64::from_le_bytes(
        bytes
            .windows(8)
            .map(|w| <[u8; 8]>::try_from(w).unwrap())
            .find(|w| {
                let v = f64::from_le_bytes(*w);
                (1e6..1e7).contains(&v)
            })
            .unwrap(),
    ));
    let at = bytes.windows(8).position(|w| w == radius.to_le_bytes()).unwrap();
    let mut bad = bytes.clone();
    bad[at..at + 8].copy_from_slice(&1e-300f64.to_le_bytes());
    let path = dir.join("tiny-body.tif");
    std::fs::write(&path, bad).unwrap();
    let o = areo(&["terrain", "info", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("GeogSemiMajorAxisGeoKey"), "{}", stderr(&o));
}

/// Control characters in a description reach the terminal escaped; a leap second and
/// a day past the ephemeris are refused.
#[test]
fn terminal_output_is_escaped_and_times_out_of_range_refused() {
    let dir = tmp("escape");
    let path = write_variant(&dir, "gale-sol-sun.ron", "description: \"", "description: \"\\u{1b}[31mred\\u{0}");
    let o = areo(&["-q", "run", path.to_str().unwrap(), "-o", dir.join("out").to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(!text.contains('\u{1b}') && !text.contains('\u{0}') && text.contains("\\u{1b}[31mred"), "{text:?}");
    // A goal named with bidirectional overrides, invisible characters and separators:
    // the summary shows them escaped, `--json` as JSON escapes that read back as the name.
    let name = "ea\u{202E}ts\u{2066}\u{200B}\u{2028}x";
    let small = root().join("tests/tempest/small.ron");
    let set = format!("job.goals[0].name={}", serde_json::to_string(name).unwrap());
    let out = dir.join("out");
    let args = ["-q", "run", small.to_str().unwrap(), "-o", out.to_str().unwrap(), "--set", &set];
    let o = areo(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("reached ea\\u{202e}ts\\u{2066}\\u{200b}\\u{2028}x"), "{text}");
    let raw = |t: &str| t.chars().any(|c| matches!(c, '\u{202E}' | '\u{2066}' | '\u{200B}' | '\u{2028}' | '\u{9B}'));
    assert!(!raw(&text));
    let o = areo(&[&args[..], &["--json"]].concat());
    let json = String::from_utf8_lossy(&o.stdout);
    assert!(!raw(&json), "{json}");
    let facts: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(facts["summary"].as_array().unwrap().iter().any(|l| l.as_str().unwrap().contains(name)), "{facts}");
    // An error naming a refused name shows it escaped too.
    let set = format!("job.goals[0].name={}", serde_json::to_string("\u{1b}]0;title\u{7}\u{9b}").unwrap());
    let o = areo(&["-q", "run", small.to_str().unwrap(), "-o", dir.join("out").to_str().unwrap(), "--set", &set]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!stderr(&o).contains(['\u{1b}', '\u{7}', '\u{9b}']), "{:?}", stderr(&o));
    let o = areo(&["sun", "--time", "2016-12-31T23:59:60Z"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = areo(&["sun", "--body", "moon", "--day", "2600-12-31", "--lat", "0", "--lon", "0"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

/// Twelve runs into one `--out` at once all end in place (exit 0), leaving one set of
/// outputs and no staging or set-aside directories; an `OUT/NAME` that is a file is
/// refused, not moved aside.
#[test]
fn concurrent_runs_into_one_out_all_land_and_a_file_in_the_way_is_refused() {
    let dir = tmp("concurrent");
    let path = write_variant(&dir, "gale-sol-sun.ron", "description: \"", "description: \"concurrent: ");
    let out = dir.join("out");
    let children: Vec<_> = (0..12)
        .map(|_| {
            Command::new(env!("CARGO_BIN_EXE_areo"))
                .args(["-q", "run", path.to_str().unwrap(), "-o", out.to_str().unwrap()])
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    for child in children {
        let o = child.wait_with_output().unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    }
    let names: Vec<String> =
        std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert_eq!(names, ["gale-sol-sun"], "nothing left beside the outputs");
    assert!(out.join("gale-sol-sun/facts.json").exists());

    let blocked = dir.join("blocked");
    std::fs::create_dir_all(&blocked).unwrap();
    std::fs::write(blocked.join("gale-sol-sun"), "a file in the way").unwrap();
    let o = areo(&["-q", "run", path.to_str().unwrap(), "-o", blocked.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("not an output directory"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(blocked.join("gale-sol-sun")).unwrap(), "a file in the way");
}

/// The smaller exit-code cases: a map's site at the pole is a located range error, a
/// viewshed on one cell is exit 2, a sweep plot of overflowing values and a facts.json
/// that is not text agree between `run` and `collect`, and a thread count past the cores
/// is capped with a warning.
#[test]
fn small_cases_exit_as_documented() {
    let dir = tmp("small-cases");
    let o = run_variant(&dir, "crater-morning-shadows.ron", "lat_deg: -4.5895", "lat_deg: -90");
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("job.site.lat_deg") && stderr(&o).contains("pole"), "{}", stderr(&o));

    let one = dir.join("one.asc");
    std::fs::write(&one, "ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n5\n").unwrap();
    let o = areo(&[
        "terrain",
        "viewshed",
        one.to_str().unwrap(),
        "--from",
        "0.5,0.5,2",
        "-o",
        dir.join("v.tif").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));

    // A sweep with a label axis of ±1.7e308, two tasks run; then one task's facts.json
    // replaced by bytes that are not text.
    std::fs::write(dir.join("base.ron"), std::fs::read_to_string(root().join("scenarios/gale-sol-sun.ron")).unwrap())
        .unwrap();
    let sweep = dir.join("huge.sweep.ron");
    std::fs::write(
        &sweep,
        "Sweep(version: 1, base: \"base.ron\", combine: Zip, axes: [(name: \"t\", path: \"job.tau\", values: [0.5, 0.9]), (name: \"x\", values: [-1.7e308, 1.7e308])])",
    )
    .unwrap();
    let s = dir.join("s");
    assert!(areo(&["sweep", "expand", sweep.to_str().unwrap(), "-o", s.to_str().unwrap()]).status.success());
    for i in ["0", "1"] {
        let o = Command::new(env!("CARGO_BIN_EXE_areo"))
            .args(["-v", "sweep", "run", s.to_str().unwrap(), "--index", i])
            .env("SLURM_CPUS_PER_TASK", "100000")
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(stderr(&o).contains("more than this machine's"), "the cap is said: {}", stderr(&o));
    }
    let o = areo(&["sweep", "collect", s.to_str().unwrap(), "--plot", "rows", "--against", "x"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("cannot be plotted"), "{}", stderr(&o));
    let facts = s.join("out/1/facts.json");
    std::fs::write(&facts, [0xff, 0xfe, 0x00]).unwrap();
    let collected = areo(&["sweep", "collect", s.to_str().unwrap()]);
    assert!(
        String::from_utf8_lossy(&collected.stdout).contains("1 finished"),
        "{}",
        String::from_utf8_lossy(&collected.stdout)
    );
    // run agrees: the task is not finished, so it runs again (and is then finished).
    let o = areo(&["sweep", "run", s.to_str().unwrap(), "--index", "1"]);
    assert!(
        o.status.success() && String::from_utf8_lossy(&o.stdout).contains("task 1 (1):"),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    assert!(!String::from_utf8_lossy(&o.stdout).contains("skipped"));
}

/// devon-island planned by the approximate search over its former classes, with a
/// battery too low to move (a search that floods the map), with `budget` flags, its
/// outputs under a temporary directory named `name`. (On its shipped tick the exact
/// search plans from there in about a second: the rover waits in the midnight sun.)
fn devon_island_from_an_empty_battery(name: &str, budget: &[&str]) -> Output {
    let dir = tmp(name);
    let classes = "approximate: true, resolution: (time_s: 1800, energy_wh: 50), goal_times: 12, segment_starts: 8,";
    let scenario = write_variant(&dir, "devon-island.ron", "tick_s: 300,", classes);
    let mut args = vec!["-q", "run", scenario.to_str().unwrap(), "--out", dir.to_str().unwrap()];
    args.extend(["--set", "job.start_battery_above_floor_wh=0.001"]);
    args.extend(budget);
    areo(&args)
}

/// The work budget holds during the run, not only in the estimate before it: on
/// devon-island with a battery too low to move (fuzz seed 7's finding: 4.8 M expansions
/// against an estimate of 2.4 M, minutes of search) the searches stop
/// where the budget ends, and the run says so — an exit code of its own (4, neither bad
/// input's nor a verdict's), the file, the flag — instead of running on or calling the
/// goal unreachable.
#[test]
fn a_search_that_outgrows_its_estimate_stops_at_the_work_budget() {
    let run = |max_work: &str| devon_island_from_an_empty_battery("work-spent", &["--max-work", max_work]);
    // What is certain before the run is refused before it starts: the 10 000 cells × 64
    // sectors of horizon rays. The searches are not guessed at (a guess of 2.4 M
    // expansions refused budgets this one spends to the end); they get what the
    // sweeps leave, 100 steps an expansion, and stop there.
    let sweeps = 10_000 * 64;
    let out = run(&(sweeps - 1).to_string());
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("needs about 6.40e5 steps"), "refused for its sweeps: {err}");
    let out = run(&(sweeps + 100 * 100_000).to_string());
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(4), "{err}");
    // The work counts whole expansions and the comparisons of long Pareto fronts, a
    // hundred to one: the last expansion may carry it one past the limit.
    let work = err.split("stopped after the work of ").nth(1).and_then(|r| r.split(' ').next());
    let work = work.and_then(|n| n.parse::<u64>().ok()).unwrap_or_else(|| panic!("{err}"));
    assert!((100_000..=100_001).contains(&work), "{err}");
    let out = run("2.4064e8");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(4), "{err}");
    assert!(err.contains("devon-island.ron") && err.contains("--max-work"), "{err}");
    assert!(err.contains("stopped after the work of 2400000 label expansions"), "{err}");
    assert!(!err.contains("unreachable"), "stopping is not a proof that no plan exists: {err}");
    // The facts it has are written: stopped, by what, the work done.
    let facts = root().join("target/hostile-tests/work-spent/devon-island/facts.json");
    let facts = std::fs::read_to_string(&facts).unwrap_or_else(|e| panic!("{}: {e}", facts.display()));
    assert!(facts.contains(r#""status": "stopped""#) && facts.contains(r#""stopped_by": "work""#), "{facts}");
    // Some work was counted (its value is the searches' expansions, the comparisons aside).
    let expansions = facts.split(r#""no_plan_expansions": "#).nth(1).and_then(|r| r.split([',', '\n']).next());
    assert!(expansions.and_then(|n| n.trim().parse::<u64>().ok()).is_some_and(|n| n > 100_000), "{facts}");
}

/// The same flooding search under a memory budget its estimate fits in (10 000 cells,
/// a few MB of worlds and graphs by the estimate): the graphs outgrow it within seconds,
/// and the searches stop where the budget leaves the graphs no more room — exit code 4,
/// the file, the flag — instead of growing until the machine kills the run.
#[test]
fn a_search_that_outgrows_its_memory_estimate_stops_at_the_memory_budget() {
    let out = devon_island_from_an_empty_battery("memory-spent", &["--max-memory-gb", "0.1"]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(4), "{err}");
    assert!(err.contains("devon-island.ron") && err.contains("--max-memory-gb"), "{err}");
    assert!(err.contains("stopped when their graphs held 0.1"), "{err}");
    assert!(!err.contains("unreachable"), "stopping is not a proof that no plan exists: {err}");
    let facts = root().join("target/hostile-tests/memory-spent/devon-island/facts.json");
    let facts = std::fs::read_to_string(&facts).unwrap_or_else(|e| panic!("{}: {e}", facts.display()));
    assert!(facts.contains(r#""status": "stopped""#) && facts.contains(r#""stopped_by": "memory""#), "{facts}");
    assert!(facts.contains(r#""peak_memory_mb""#), "{facts}");
}

#[test]
fn a_start_on_any_of_the_maps_four_edges_is_on_it_and_a_step_beyond_any_is_off() {
    let dir = tmp("edges");
    // A 20 × 20 map of 50 m cells: 0..=1000 m each way, its edges included.
    let scenario = |start: &str| {
        format!(
            r#"Scenario(version: 1, description: "edges", job: Tempest(body: Mars,
            terrain: Synth(cols: 20, rows: 20, cell_m: 50.0, seed: 4, noise: (amplitude_m: 1.0, wavelength_m: 400.0, octaves: 1), features: []),
            site: (lat_deg: -4.6, lon_east_deg: 137.4), start_utc: "2012-08-06T20:00:00Z", horizon_h: 12,
            start: ({start}), start_battery_above_floor_wh: 600, goals: [(name: "g", x_m: 500, y_m: 500)]))"#
        )
    };
    let path = dir.join("edges.ron");
    for (start, on) in [
        ("x_m: 0, y_m: 500", true),
        ("x_m: 1000, y_m: 500", true),
        ("x_m: 500, y_m: 0", true),
        ("x_m: 500, y_m: 1000", true),
        ("x_m: -0.5, y_m: 500", false),
        ("x_m: 1000.5, y_m: 500", false),
        ("x_m: 500, y_m: -0.5", false),
        ("x_m: 500, y_m: 1000.5", false),
    ] {
        std::fs::write(&path, scenario(start)).unwrap();
        let out = areo(&["-q", "run", path.to_str().unwrap(), "--out", dir.join("out").to_str().unwrap()]);
        let err = stderr(&out);
        if on {
            assert!(out.status.success(), "{start}: {err}");
        } else {
            assert_eq!(out.status.code(), Some(2), "{start}: {err}");
            assert!(err.contains("off the map: allowed 0..=1000 m east, 0..=1000 m north"), "{start}: {err}");
        }
    }
}

/// `sh -c` running areo with `args` under a CPU-time limit of `cpu_s` seconds and an
/// address-space limit of `kb` KiB: a case that is slow or huge fails by the limit.
fn limited(cpu_s: u32, kb: u64, args: &[&str]) -> Output {
    Command::new("sh")
        .args(["-c", &format!("ulimit -t {cpu_s} -v {kb}; exec \"$@\""), "sh", env!("CARGO_BIN_EXE_areo")])
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn the_last_rounds_hostile_files_are_refused_quickly_with_their_place() {
    let dir = tmp("last-round");
    // A list of 200 000 horizon sectors: refused at the list's opening before parsing,
    // in a fraction of the memory its parse would take.
    let sectors = "0,".repeat(200_000);
    let big = dir.join("big.ron");
    std::fs::write(
        &big,
        format!(
            "Scenario(version: 1, description: \"t\", job: SunTable(site: (lat_deg: -4.5895, lon_east_deg: 137.4417),\n    start_utc: \"2012-08-06T00:00:00Z\", duration_h: 2, step_min: 30, tau: 0.5,\n    horizon_deg: [{sectors}]))"
        ),
    )
    .unwrap();
    let out = limited(10, 600_000, &["-q", "run", big.to_str().unwrap(), "--out", dir.join("out").to_str().unwrap()]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("big.ron:3:18: a list of more than 100000 items"), "{err}");
    // A rover file nested far past any real one.
    let deep = dir.join("deep.ron");
    std::fs::write(&deep, format!("{}{}", "(".repeat(200_000), ")".repeat(200_000))).unwrap();
    let out = limited(10, 600_000, &["rover", "check", deep.to_str().unwrap()]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("deep.ron:1:65: brackets nested deeper than 64"), "{err}");
    // Heights at f32::MAX: an undeclared no-data value, refused naming the file and cell.
    let max = dir.join("max.asc");
    std::fs::write(&max, "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 10\n1 2 3\n4 3.4e38 6\n").unwrap();
    let out = areo(&["terrain", "info", max.to_str().unwrap()]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("max.asc") && err.contains("height 3.4e38 m at column 1, row 1"), "{err}");
    // A viewshed on one cell names the DEM.
    let one = dir.join("one.asc");
    std::fs::write(&one, "ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 10\n1\n").unwrap();
    let out = areo(&[
        "terrain",
        "viewshed",
        one.to_str().unwrap(),
        "--from",
        "5,5,2",
        "-o",
        dir.join("vs.tif").to_str().unwrap(),
    ]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("one.asc") && err.contains("at least 2 x 2 cells"), "{err}");
}

#[test]
fn a_damaged_task_result_is_failed_not_missing() {
    let dir = tmp("damaged");
    common::sun_table(&dir, "sun", (2.0, 30.0, 0.5));
    common::tau_sweep(&dir, "sun.ron", (0.25, 0.5, 0.25));
    let sweep = dir.join("sweep");
    let s = sweep.to_str().unwrap();
    assert!(areo(&["-q", "sweep", "expand", dir.join("tau.sweep.ron").to_str().unwrap(), "-o", s]).status.success());
    assert!(areo(&["-q", "sweep", "run", s, "--index", "0"]).status.success());
    std::fs::write(sweep.join("out/tau-0.25/facts.json"), "{\"tau\": 0.2").unwrap();
    let out = areo(&["sweep", "collect", s]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("0 finished, 1 missing, 1 failed"), "{text}");
    assert!(text.contains("failed  tau-0.25:") && text.contains("a damaged result"), "{text}");
    assert!(text.contains("missing tau-0.5"), "{text}");
}
