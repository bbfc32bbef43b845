//! The memory figures a TEMPEST run reports: the worlds' bytes (`world_mb`) and the
//! process peak (`peak_memory_mb`), both in MB of 10⁶ bytes.

use std::path::{Path, PathBuf};

use areo_scenario::budget::Budget;
use areo_scenario::outcome::Outcome;
use areo_scenario::{NoProgress, RunOptions, format::load_set, run};

fn small() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/tempest/small.ron")
}

fn plan(sets: &[&str]) -> Outcome {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let file = load_set(&small(), &sets).unwrap_or_else(|e| panic!("{sets:?}: {e}"));
    run(&file, RunOptions { out_dir: None, progress: &NoProgress, budget: Budget::for_this_machine() })
        .unwrap_or_else(|e| panic!("{sets:?}: {e}"))
}

fn number(o: &Outcome, name: &str) -> f64 {
    o.facts.get(name).and_then(|f| f.as_number()).unwrap_or_else(|| panic!("{name}: {:?}", o.facts.get(name)))
}

/// VmHWM of this process, bytes.
fn high_water_bytes() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let line = status.lines().find(|l| l.starts_with("VmHWM:")).unwrap();
    line.split_whitespace().nth(1).unwrap().parse::<f64>().unwrap() * 1024.0
}

/// A map that is its own truth (`truth: Map`) is one world, held once: it was counted
/// twice, so a run on a real DEM reported worlds larger than its process peak.
#[test]
fn a_map_that_is_its_own_truth_is_counted_once() {
    let own = plan(&["job.truth=Map"]);
    let twin = plan(&["job.truth=AddFeatures([])"]);
    let (own_mb, twin_mb) = (number(&own, "world_mb"), number(&twin, "world_mb"));
    // The map's own grids: heights, slopes, flags, 16 sectors of horizon.
    let cells = number(&own, "cells");
    let grids_mb = cells * (18.0 + 16.0 * number(&own, "horizon_bytes_per_angle")) / 1e6;
    assert!(own_mb >= grids_mb, "{own_mb} MB for grids of {grids_mb} MB");
    // A truth that adds no landform is still a second world, which shares the map's
    // horizon map and holds the rest again: more than the map alone, less than twice it
    // (which is what counting the map twice gave).
    assert!(
        own_mb < twin_mb && twin_mb < 2.0 * own_mb,
        "truth Map {own_mb} MB, an identical truth of its own {twin_mb} MB"
    );
}

/// VmHWM is in KiB; the fact is in MB like every other memory figure (it was MiB).
#[test]
fn the_process_peak_is_in_megabytes() {
    // Raise the high-water mark well above what the small run needs, so the run leaves
    // it where it is and the fact must equal it.
    let mut ballast = vec![1u8; 300_000_000];
    for i in (0..ballast.len()).step_by(4096) {
        ballast[i] = (i % 251) as u8;
    }
    assert!(ballast.iter().step_by(4096).map(|&b| b as u64).sum::<u64>() > 0);
    drop(ballast);
    let before = high_water_bytes();
    let o = plan(&[]);
    let after = high_water_bytes();
    let mb = number(&o, "peak_memory_mb");
    assert!(before / 1e6 <= mb + 1e-6 && mb <= after / 1e6 + 1e-6, "{mb} MB reported, VmHWM {before}..{after} bytes");
}
