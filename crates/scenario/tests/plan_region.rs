//! A TEMPEST job planned in a region of a map read a window at a time
//! (`job.plan_region`) against the same job on the whole map.

use std::path::{Path, PathBuf};

use areo_scenario::budget::Budget;
use areo_scenario::{NoProgress, RunOptions, format::load, run};
use areo_terrain::Spheroid;
use areo_terrain::synth::{Feature, Noise, TerrainSpec};

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("areo_plan_region_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// 110 × 90 cells of 50 m at Gale's latitude: noise, two hills that cast long morning
/// and evening shadows, a crater on the way.
fn write_map(path: &Path) {
    let dem = TerrainSpec {
        cols: 110,
        rows: 90,
        cell_m: 50.0,
        base_m: -4500.0,
        seed: 11,
        noise: Some(Noise { amplitude_m: 4.0, wavelength_m: 600.0, octaves: 3, persistence: 0.5 }),
        features: vec![
            Feature::Hill { x_m: 2000.0, y_m: 2600.0, radius_m: 400.0, slope_deg: 30.0 },
            Feature::Hill { x_m: 3800.0, y_m: 1700.0, radius_m: 350.0, slope_deg: 28.0 },
            Feature::Crater {
                x_m: 2900.0,
                y_m: 2200.0,
                radius_m: 300.0,
                depth_m: 40.0,
                rim_height_m: 10.0,
                ejecta_radii: 2.0,
            },
        ],
    }
    .build()
    .unwrap()
    .placed_at(Spheroid::MARS_MOLA_SPHERE, -4.5895, 137.4417)
    .unwrap();
    areo_terrain::geotiff::write(&dem, path).unwrap();
}

fn scenario(region: &str, start: (f64, f64)) -> String {
    format!(
        r#"Scenario(
    version: 1,
    description: "plan region",
    job: Tempest(
        terrain: File("map.tif"),
        site: (lat_deg: -4.5895, lon_east_deg: 137.4417),
        start_utc: "2012-08-06T20:15:00Z",
        horizon_h: 30,
        horizon_sectors: 32,
        rover: "mock-solar-rover.ron",
        start: (x_m: {}, y_m: {}),
        start_battery_above_floor_wh: 150,
        goals: [(name: "goal", x_m: 3300, y_m: 2900)],
        planner: (approximate: true, goal_energy_wh: 50, resolution: (time_s: 1200, energy_wh: 25)),
        {region}
    ),
)"#,
        start.0, start.1
    )
}

fn run_text(name: &str, text: &str) -> Result<areo_scenario::outcome::Outcome, areo_scenario::Error> {
    let d = dir();
    let path = d.join(format!("{name}.ron"));
    std::fs::write(&path, text).unwrap();
    let file = load(&path)?;
    run(&file, RunOptions { out_dir: None, progress: &NoProgress, budget: Budget::for_this_machine() })
}

fn number(o: &areo_scenario::outcome::Outcome, name: &str) -> f64 {
    match o.facts.get(name) {
        Some(f) if f.as_number().is_some() => f.as_number().unwrap_or(f64::NAN),
        other => panic!("{name}: {other:?}"),
    }
}

#[test]
fn a_region_plans_what_the_whole_map_plans() {
    let d = dir();
    write_map(&d.join("map.tif"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    std::fs::copy(root.join("scenarios/rovers/mock-solar-rover.ron"), d.join("mock-solar-rover.ron")).unwrap();
    let whole = run_text("whole", &scenario("", (1200.0, 900.0))).unwrap();
    // The region leaves out a wide margin the route has no reason to enter; its
    // horizons answer for Suns 0.5° up and higher, which is all the Sun that charges.
    let region = "plan_region: (x_m: (700, 4300), y_m: (500, 3600), lowest_sun_deg: 0.5),";
    let cut = run_text("region", &scenario(region, (1200.0, 900.0))).unwrap();
    assert!(number(&cut, "cells") < 0.6 * number(&whole, "cells"), "the region holds fewer cells");
    assert_eq!(whole.failure, None);
    assert_eq!(cut.failure, None);
    for fact in [
        "initial_plan_expansions",
        "initial_plan_hibernations",
        "initial_plan_drives",
        "initial_plan_distance_m",
        "initial_plan_duration_h",
        "initial_plan_charges",
    ] {
        assert_eq!(number(&cut, fact), number(&whole, fact), "{fact}");
    }
    assert!(number(&whole, "initial_plan_charges") > 0.0, "a plan that charges: the horizons matter");
    assert!(cut.summary.iter().any(|l| l.contains("planning region of 72 × 62 cells")), "{:?}", cut.summary);
    let (a, b) = (number(&cut, "initial_plan_min_battery_wh"), number(&whole, "initial_plan_min_battery_wh"));
    assert!((a - b).abs() <= 1e-6 * b.abs().max(1.0), "min battery {a} vs {b}");

    // A start outside the region is refused with the region's extent.
    let err = run_text("outside", &scenario(region, (300.0, 900.0))).unwrap_err().to_string();
    assert!(err.contains("job.start") && err.contains("off the planning region"), "{err}");
    // A region the wrong way round is refused by field.
    let bad = "plan_region: (x_m: (4000, 700), y_m: (500, 3600)),";
    let err = run_text("bad", &scenario(bad, (1200.0, 900.0))).unwrap_err().to_string();
    assert!(err.contains("job.plan_region.x_m") && err.contains("0 ≤ low < high"), "{err}");
}

/// The battery to hold at the last goal above what the battery holds is bad input,
/// refused by field with the limit before any search (not searched for until the work
/// budget ends); at the limit it is a question the planner answers.
#[test]
fn a_goal_battery_above_the_capacity_is_refused_by_field() {
    // A directory of its own: the other test writes its map beside its scenarios.
    let d = dir().join("capacity");
    std::fs::create_dir_all(&d).unwrap();
    write_map(&d.join("map.tif"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    std::fs::copy(root.join("scenarios/rovers/mock-solar-rover.ron"), d.join("mock-solar-rover.ron")).unwrap();
    let refusal = |name: &str, text: String| {
        let path = d.join(format!("{name}.ron"));
        std::fs::write(&path, text).unwrap();
        let file = load(&path).unwrap();
        let budget = Budget::for_this_machine();
        run(&file, RunOptions { out_dir: None, progress: &NoProgress, budget }).unwrap_err().to_string()
    };
    let text = scenario("", (1200.0, 900.0));
    let err = refusal("goal-above", text.replace("goal_energy_wh: 50", "goal_energy_wh: 5000"));
    assert!(err.contains("job.planner.goal_energy_wh") && err.contains("5000 Wh") && err.contains("at most"), "{err}");
    let err =
        refusal("start-above", text.replace("start_battery_above_floor_wh: 150", "start_battery_above_floor_wh: 5000"));
    assert!(err.contains("job.start_battery_above_floor_wh") && err.contains("at most"), "{err}");
}
