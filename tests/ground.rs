//! The ground end to end: a terrain-class map read onto the map (a class at half speed
//! doubles the drive time, its drives and cells counted per class, its layer and its
//! columns written), the rover's roll limit refusing a drive across a slope it allows
//! straight up, and class maps that cannot be used refused by name.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

mod layers;
use layers::{ascii_grid, csv, root, run, scratch, stderr};

const COLS: usize = 30;
const ROWS: usize = 20;
/// Drives east at 0.3 m/s take 180 s: whole minutes, like the planner's default tick,
/// so that no drive waits for the next tick (at 0.5 × and 1.5 × speed too).
const CELL: f64 = 54.0;

/// An ESRI ASCII grid on the map's 30 × 20 cells: `value(col, row)` (row 0 north).
fn grid(dir: &Path, name: &str, value: impl Fn(usize, usize) -> String) -> String {
    ascii_grid(dir, name, (COLS, ROWS, CELL), value)
}

/// The centre of cell (col, row), map metres.
fn at((c, r): (usize, usize)) -> (f64, f64) {
    ((c as f64 + 0.5) * CELL, (ROWS as f64 - r as f64 - 0.5) * CELL)
}

/// A scenario on `terrain` (RON) from `start` to `goal` (cells) with the rover file
/// `rover` and `extra` fields.
fn scenario(
    dir: &Path,
    terrain: &str,
    rover: &str,
    start: (usize, usize),
    goal: (usize, usize),
    extra: &str,
) -> PathBuf {
    let (s, g) = (at(start), at(goal));
    let path = dir.join("ground.ron");
    std::fs::write(
        &path,
        format!(
            r#"Scenario(version: 1, description: "ground", job: Tempest(body: Mars, terrain: {terrain},
            site: (lat_deg: -4.6, lon_east_deg: 137.4), start_utc: "2012-08-06T22:00:00Z", horizon_h: 30,
            rover: "{rover}", start: (x_m: {}, y_m: {}), start_battery_above_floor_wh: 800,
            goals: [(name: "goal", x_m: {}, y_m: {})],
            {extra}))"#,
            s.0, s.1, g.0, g.1
        ),
    )
    .unwrap();
    path
}

const FLAT: &str = "Synth(cols: 30, rows: 20, cell_m: 54, seed: 1, noise: (amplitude_m: 0.0, wavelength_m: 400.0, octaves: 1), features: [])";

/// The shipped mock solar rover with a bigger battery and `locomotor` lines added.
fn rover(dir: &Path, locomotor: &str) -> String {
    let text = std::fs::read_to_string(root().join("scenarios/rovers/mock-solar-rover.ron")).unwrap();
    let text = text.replacen("locomotor: (", &format!("locomotor: ({locomotor}"), 1);
    let text = text.replacen("capacity_wh: 1000.0", "capacity_wh: 5000.0", 1);
    assert!(text.contains("capacity_wh: 5000.0"));
    std::fs::write(dir.join("rover.ron"), text).unwrap();
    "rover.ron".into()
}

fn facts(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("ground/facts.json")).unwrap()).unwrap()
}

/// The plan's drives: (col, row, duration s).
fn drives(plan: &[HashMap<String, String>]) -> Vec<(String, String, f64)> {
    plan.iter()
        .filter(|w| w["action"].starts_with("drive"))
        .map(|w| (w["col"].clone(), w["row"].clone(), w["duration_s"].parse().unwrap()))
        .collect()
}

#[test]
fn a_class_at_half_speed_doubles_every_drive_and_is_counted_and_drawn() {
    let dir = scratch("ground-tests", "half-speed");
    let rover = rover(&dir, "");
    let (start, goal) = ((2, 10), (27, 10));
    let plain = scenario(&dir, FLAT, &rover, start, goal, "");
    let out_plain = dir.join("plain");
    let o = run(&plain, &out_plain);
    assert!(o.status.success(), "{}", stderr(&o));
    let sand = grid(&dir, "sand.asc", |_, _| "7".into());
    let classes = format!(
        "terrain_classes: (file: \"{sand}\", classes: [(id: 7, name: \"sand\", speed_factor: 0.5, power_factor: 1.8)])"
    );
    let path = scenario(&dir, FLAT, &rover, start, goal, &classes);
    let out = dir.join("sand");
    let o = run(&path, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let (a, b) = (csv(&out_plain.join("ground/plan.csv")), csv(&out.join("ground/plan.csv")));
    let (da, db) = (drives(&a), drives(&b));
    assert_eq!(da.len(), 25);
    assert_eq!(
        da.iter().map(|d| (&d.0, &d.1)).collect::<Vec<_>>(),
        db.iter().map(|d| (&d.0, &d.1)).collect::<Vec<_>>()
    );
    for (x, y) in da.iter().zip(&db) {
        assert!((x.2 - 180.0).abs() < 0.05 && (y.2 - 360.0).abs() < 0.05, "{x:?} vs {y:?}");
    }
    assert!(b.iter().all(|w| w["class"] == "sand"));
    assert!(
        b.iter()
            .filter(|w| w["action"].starts_with("drive"))
            .all(|w| w["pitch_deg"] == "0.000" && w["roll_deg"] == "0.000")
    );
    assert!(b.iter().filter(|w| !w["action"].starts_with("drive")).all(|w| w["pitch_deg"].is_empty()));
    let f = facts(&out);
    assert_eq!(f["terrain_classes.classes.sand.cells"], 600);
    assert_eq!(f["terrain_classes.unclassified_cells"], 0);
    let total: f64 = db.iter().map(|d| d.2).sum();
    let counted = f["terrain_classes.classes.sand.plan_drive_time_s"].as_f64().unwrap();
    assert!((counted - total).abs() < 0.1 * db.len() as f64, "{counted} vs {total}");
    let drawn: f64 = b
        .iter()
        .filter(|w| w["action"].starts_with("drive"))
        .map(|w| w["energy_drawn_wh"].parse::<f64>().unwrap())
        .sum();
    let counted = f["terrain_classes.classes.sand.plan_drive_energy_wh"].as_f64().unwrap();
    assert!((counted - drawn).abs() < 1e-3 * db.len() as f64, "{counted} vs {drawn}");
    assert!(out.join("ground/classes.tif").exists());
    let summary = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(summary.contains("terrain classes sand.asc: sand 600 cells"), "{summary}");
    let html = std::fs::read_to_string(out.join("ground/view.html")).unwrap();
    assert!(html.contains("\"classes\":{\"names\":[\"sand\"]"), "the viewer has the classes");
}

#[test]
fn a_half_classified_map_costs_each_drive_by_both_its_cells() {
    // The west half sand at 0.5, the east half bedrock at 1.5: a drive inside each
    // takes 2 and 2/3 times the plain one, and the drive across the border 4/3 times.
    let dir = scratch("ground-tests", "border");
    let rover = rover(&dir, "");
    let file = grid(&dir, "halves.asc", |c, _| if c < 15 { "1".into() } else { "2".into() });
    let classes = format!(
        "terrain_classes: (file: \"{file}\", classes: [(id: 1, name: \"sand\", speed_factor: 0.5), (id: 2, name: \"bedrock\", speed_factor: 1.5)])"
    );
    let path = scenario(&dir, FLAT, &rover, (2, 10), (27, 10), &classes);
    let out = dir.join("out");
    let o = run(&path, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let plan = csv(&out.join("ground/plan.csv"));
    let plain = CELL / 0.3;
    for (c, _, d) in drives(&plan) {
        let c: usize = c.parse().unwrap();
        let want = match c {
            c if c < 14 => 2.0,
            14 => 0.5 * 2.0 + 0.5 / 1.5,
            _ => 1.0 / 1.5,
        } * plain;
        assert!((d - want).abs() <= 0.06, "drive from column {c}: {d} s, want {want}");
    }
    // Executed: each drive's class where it starts, its time split the same way.
    let path =
        scenario(&dir, FLAT, &rover, (2, 10), (27, 10), &format!("{classes}, simulate: (sense_radius_cells: 1)"));
    let run_out = dir.join("run");
    let o = run(&path, &run_out);
    assert!(o.status.success(), "{}", stderr(&o));
    let executed = csv(&run_out.join("ground/executed.csv"));
    let mut on_sand = 0.0;
    for s in executed.iter().filter(|s| s["action"].starts_with("drive")) {
        let c: usize = s["col"].parse().unwrap();
        assert_eq!(s["class"], if c < 15 { "sand" } else { "bedrock" }, "{s:?}");
        let d: f64 = s["duration_s"].parse().unwrap();
        on_sand += match c {
            c if c < 14 => d,
            14 => d * 0.5 * 2.0 / (0.5 * 2.0 + 0.5 / 1.5),
            _ => 0.0,
        };
    }
    let counted = facts(&run_out)["terrain_classes.classes.sand.run_drive_time_s"].as_f64().unwrap();
    assert!((counted - on_sand).abs() < 1.0, "{counted} vs {on_sand}");
    let f = facts(&out);
    assert_eq!(f["terrain_classes.classes.sand.cells"], 300);
    assert_eq!(f["terrain_classes.classes.bedrock.cells"], 300);
    let sand = f["terrain_classes.classes.sand.plan_drive_time_s"].as_f64().unwrap();
    let bedrock = f["terrain_classes.classes.bedrock.plan_drive_time_s"].as_f64().unwrap();
    // 12.5 cells' worth on sand at twice the time, 12.5 on bedrock at 2/3.
    assert!((sand - 12.5 * 2.0 * plain).abs() < 1.0 && (bedrock - 12.5 / 1.5 * plain).abs() < 1.0, "{sand} {bedrock}");
}

/// A plane rising 15° toward the east, as an ESRI ASCII DEM.
fn ramp(dir: &Path) -> String {
    let rise = CELL * 15f64.to_radians().tan();
    grid(dir, "ramp.asc", |c, _| format!("{:.4}", c as f64 * rise))
}

#[test]
fn a_drive_across_a_slope_steeper_than_max_roll_is_refused_while_straight_up_passes() {
    let dir = scratch("ground-tests", "roll");
    let terrain = format!("File(\"{}\")", ramp(&dir));
    // North across the 15° slope: roll 15° straight, 10.5° on the diagonals.
    let tight = rover(&dir, "max_roll_deg: 10.0, ");
    let north = scenario(&dir, &terrain, &tight, (10, 17), (10, 3), "");
    let out = dir.join("north");
    let o = run(&north, &out);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("roll above the rover's max_roll_deg"), "{}", stderr(&o));
    assert_eq!(facts(&out)["unreachable_proven"], true);
    // Straight up the slope: pitch 15°, roll 0, under the slope limit of 20°.
    let east = scenario(&dir, &terrain, &tight, (3, 10), (20, 10), "");
    let out = dir.join("east");
    let o = run(&east, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let plan = csv(&out.join("ground/plan.csv"));
    let pitches: Vec<f64> =
        plan.iter().filter(|w| w["action"].starts_with("drive")).map(|w| w["pitch_deg"].parse().unwrap()).collect();
    assert_eq!(pitches.len(), 17);
    assert!(pitches.iter().all(|p| (p - 15.0).abs() < 0.01), "{pitches:?}");
    // A 12° limit lets the diagonals through: north by zig-zag, every roll within it.
    let loose = rover(&dir, "max_roll_deg: 12.0, ");
    let north = scenario(&dir, &terrain, &loose, (10, 17), (10, 3), "");
    let out = dir.join("zigzag");
    let o = run(&north, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let plan = csv(&out.join("ground/plan.csv"));
    let rolls: Vec<f64> =
        plan.iter().filter(|w| w["action"].starts_with("drive")).map(|w| w["roll_deg"].parse().unwrap()).collect();
    assert!(rolls.len() >= 14 && rolls.iter().all(|r| r.abs() <= 12.0 && r.abs() > 10.0), "{rolls:?}");
    assert!(plan.iter().all(|w| w["action"] != "drive N" && w["action"] != "drive S"));
}

#[test]
fn class_maps_that_cannot_be_used_are_refused_by_name() {
    let dir = scratch("ground-tests", "hostile");
    let plain = rover(&dir, "");
    let good = grid(&dir, "good.asc", |c, _| if c < 15 { "1".into() } else { "2".into() });
    grid(&dir, "unknown.asc", |c, r| if (c, r) == (20, 5) { "9".into() } else { "1".into() });
    grid(&dir, "holes.asc", |c, r| if (c, r) == (3, 3) { "-9999".into() } else { "1".into() });
    grid(&dir, "fraction.asc", |c, _| if c == 0 { "1.5".into() } else { "1".into() });
    // A fraction f32 would round away: refused as written, not read as class 2.
    grid(&dir, "tiny.asc", |c, r| if (c, r) == (7, 4) { "2.000000001".into() } else { "1".into() });
    std::fs::write(
        dir.join("far.asc"),
        std::fs::read_to_string(dir.join("good.asc")).unwrap().replace("xllcorner 0", "xllcorner 90000"),
    )
    .unwrap();
    std::fs::copy(root().join("crates/terrain/tests/data/gale_mola_crop_64.tif"), dir.join("gale.tif")).unwrap();
    let two = "classes: [(id: 1, name: \"sand\", speed_factor: 0.5), (id: 2, name: \"bedrock\")]";
    let field = "job.terrain_classes";
    for (file, classes, want) in [
        (
            "unknown.asc",
            two,
            "values that are no listed class id under the map: 9 (1 cells); the classes list ids 1, 2",
        ),
        ("holes.asc", two, "1 cells of the map fall on cells of the class map with no value"),
        ("fraction.asc", two, "1.5 under the map cell at"),
        ("tiny.asc", two, "2.000000001 under the map cell at"),
        ("far.asc", two, "does not overlap the map"),
        ("gale.tif", two, "the raster's CRS"),
        ("missing.asc", two, "missing.asc"),
        (good.as_str(), "classes: [(id: 1, name: \"sand\"), (id: 1, name: \"rock\")]", "id 1 is listed twice"),
        (good.as_str(), "classes: [(id: 300, name: \"sand\"), (id: 2, name: \"rock\")]", "300: allowed 0..=254"),
        (good.as_str(), "classes: [(id: 1, name: \"sand\", speed_factor: 0), (id: 2, name: \"rock\")]", "speed_factor"),
        (
            good.as_str(),
            "classes: [(id: 1, name: \"sand\", max_slope_deg: 95), (id: 2, name: \"rock\")]",
            "max_slope_deg",
        ),
        (good.as_str(), "classes: []", "is empty"),
    ] {
        let extra = format!("terrain_classes: (file: \"{file}\", {classes})");
        let path = scenario(&dir, FLAT, &plain, (2, 10), (27, 10), &extra);
        let o = run(&path, &dir.join("out"));
        assert_eq!(o.status.code(), Some(2), "{file} {classes}: {}", stderr(&o));
        assert!(stderr(&o).contains(want) && stderr(&o).contains(field), "{file} {classes}: {}", stderr(&o));
    }
    // A rover file's roll limit out of range names its field.
    let bad = rover(&dir, "max_roll_deg: 120.0, ");
    let path = scenario(&dir, FLAT, &bad, (2, 10), (27, 10), "");
    let o = run(&path, &dir.join("out"));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("locomotor.max_roll_deg") && stderr(&o).contains("allowed 0..90"), "{}", stderr(&o));
}

/// The shipped gale-ground scenario without its no-go mask, with `rover` (a shipped
/// rover file): the initial plan's drives, as (action, pitch, roll).
fn gale_without_mask(dir: &Path, rover: &str) -> (Vec<(String, f64, f64)>, serde_json::Value) {
    let text = std::fs::read_to_string(root().join("scenarios/gale-ground.ron")).unwrap();
    let text: String = text.lines().filter(|l| !l.trim_start().starts_with("no_go:")).collect::<Vec<_>>().join("\n");
    let scenarios = root().join("scenarios");
    let text = text
        .replace("\"data/", &format!("\"{}/data/", scenarios.display()))
        .replace("\"rovers/mock-solar-rover-tilt-limits.ron\"", &format!("\"{}/rovers/{rover}\"", scenarios.display()));
    let path = dir.join("ground.ron");
    std::fs::write(&path, text).unwrap();
    let out = dir.join(rover);
    let o = run(&path, &out);
    assert!(o.status.success(), "{rover}: {}", stderr(&o));
    let plan = csv(&out.join("ground/plan.csv"));
    let drives = plan
        .iter()
        .filter(|w| w["action"].starts_with("drive"))
        .map(|w| (w["action"].clone(), w["pitch_deg"].parse().unwrap(), w["roll_deg"].parse().unwrap()))
        .collect();
    (drives, facts(&out))
}

#[test]
fn on_the_gale_crop_the_roll_limit_turns_the_route_off_the_cross_slopes() {
    // On MOLA's Gale crater, west and north-west from the eastern slopes: the rover
    // without tilt limits crosses slopes at over 12° of roll; the one limited to 12°
    // keeps every drive within it, and pays for it.
    let dir = scratch("ground-tests", "gale-roll");
    let (free, free_facts) = gale_without_mask(&dir, "mock-solar-rover.ron");
    let (limited, limited_facts) = gale_without_mask(&dir, "mock-solar-rover-tilt-limits.ron");
    let worst = |d: &[(String, f64, f64)]| d.iter().map(|x| x.2.abs()).fold(0.0, f64::max);
    assert!(worst(&free) > 12.0, "{free:?}");
    assert!(worst(&limited) <= 12.0 && worst(&limited) > 9.0, "{limited:?}");
    assert_ne!(free, limited);
    // The limit costs battery: the limited plan's lowest predicted charge is lower.
    let low = |f: &serde_json::Value| f["initial_plan_min_battery_wh"].as_f64().unwrap();
    assert!(low(&limited_facts) < low(&free_facts) - 50.0, "{} vs {}", low(&limited_facts), low(&free_facts));
    assert!(limited_facts["initial_plan_max_roll_deg"].as_f64().unwrap() <= 12.0);
}

/// The GA job up a 22° hill whose flank is the class `classes` (RON), from its foot to
/// a target on the flank: the facts.
fn sandy_hill(dir: &Path, name: &str, classes: &str) -> serde_json::Value {
    let path = dir.join(format!("{name}.ron"));
    std::fs::write(
        &path,
        format!(
            r#"Scenario(version: 1, description: "a sandy hill", job: Actions(
            terrain: Synth(cols: 100, rows: 150, cell_m: 0.02, base_m: 0.0, seed: 1, features: [
                Hill(x_m: 1.0, y_m: 2.6, radius_m: 1.0, slope_deg: 22),
            ]),
            task: (start: (1.0, 0.7, 0.0), target: (1.0, 2.0), target_radius_m: 0.15),
            ga: (population: 12, generations: 4, initial_length: (15, 30), seed: 7),
            runs: [(name: "small", inventory: [101, 105, 106, 107, 108])],
            {classes}))"#
        ),
    )
    .unwrap();
    let out = dir.join("out");
    let o = run(&path, &out);
    assert!(o.status.success(), "{name}: {}", stderr(&o));
    serde_json::from_str(&std::fs::read_to_string(out.join(name).join("facts.json")).unwrap()).unwrap()
}

#[test]
fn a_feature_of_a_slippery_class_stops_the_climb_its_friction_cannot_hold() {
    // Holding on 22° needs μ ≥ tan 22° = 0.404. The motion's μ (0.65) climbs to the
    // target; sand of μ 0.3 on the hill's flank slips; sand of μ 0.45 holds, using a
    // larger share of what it has.
    let dir = scratch("ground-tests", "sandy-hill");
    let plain = sandy_hill(&dir, "plain", "");
    let slippery = sandy_hill(&dir, "slippery", "feature_classes: [(feature: 0, class: \"sand\", mu: 0.3)],");
    let firm = sandy_hill(&dir, "firm", "feature_classes: [(feature: 0, class: \"sand\", mu: 0.45)],");
    assert_eq!(plain["runs.small.complete"], true);
    assert_eq!(slippery["runs.small.complete"], false);
    assert!(slippery["runs.small.executed.stopped_at"].as_str().unwrap().contains("slip"), "{slippery}");
    assert_eq!(firm["runs.small.complete"], true);
    // Every cell centre within the hill's 1 m base radius on the 2 × 3 m map.
    assert_eq!(slippery["feature_classes.sand.cells"], 5876);
    let share = |f: &serde_json::Value| f["runs.small.peak_friction_ratio"].as_f64().unwrap();
    assert!(share(&firm) > share(&plain) && share(&firm) <= 1.0 + 1e-9, "{} {}", share(&firm), share(&plain));
    // A class on a feature the terrain does not have, or on a map file, is refused.
    let path = dir.join("bad.ron");
    let text = std::fs::read_to_string(dir.join("firm.ron")).unwrap().replace("feature: 0", "feature: 3");
    std::fs::write(&path, text).unwrap();
    let o = run(&path, &dir.join("out"));
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("job.feature_classes[0].feature") && stderr(&o).contains("the terrain has 1 features"),
        "{}",
        stderr(&o)
    );
}
