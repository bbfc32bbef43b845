//! A full pose evaluation allocates nothing: the action planner runs millions of them.
//! Its own test binary, because it installs dhat's counting allocator for the process,
//! and without libtest's harness: dhat counts every thread's allocations, and the
//! harness's own thread allocates while a test runs (seen under load as 4 blocks).

use areo_rover::RoverParams;
use areo_rover::arm::ArmState;
use areo_rover::evaluation::{Conditions, Evaluator, Place};
use areo_terrain::synth::{Feature, TerrainSpec};

#[global_allocator]
static ALLOC: dhat::Alloc = dhat::Alloc;

fn main() {
    pose_evaluation_does_not_allocate();
}

fn pose_evaluation_does_not_allocate() {
    let dem = TerrainSpec {
        cols: 200,
        rows: 200,
        cell_m: 0.02,
        base_m: 0.0,
        seed: 1,
        noise: None,
        features: vec![
            Feature::Hill { x_m: 2.5, y_m: 2.0, radius_m: 1.2, slope_deg: 15.0 },
            Feature::Rock { x_m: 1.6, y_m: 1.75, height_m: 0.08, width_m: 0.2 },
        ],
    }
    .build()
    .unwrap();
    let params = RoverParams::lsr1();
    let ev = Evaluator::new(&params);
    let arm = ArmState::stowed(&params);
    let cond = Conditions { mu: 0.8, direction: 1.0 };
    let places: Vec<Place> = (0..40).map(|i| Place { x: 1.0 + 0.02 * i as f64, y: 2.0, heading: 1.5 }).collect();
    let profiler = dhat::Profiler::builder().testing().build();
    let mut warm = None;
    let mut evaluated = 0;
    for p in &places {
        // Cold and warm, successes and failures alike.
        let _ = ev.evaluate(&dem, *p, &arm, &cond, None);
        if let Ok(e) = ev.evaluate(&dem, *p, &arm, &cond, warm.as_ref()) {
            warm = Some(e.pose);
            evaluated += 1;
        }
    }
    let stats = dhat::HeapStats::get();
    drop(profiler);
    assert!(evaluated > 30, "the path is admissible: {evaluated}");
    assert_eq!(stats.total_blocks, 0, "{} bytes allocated in {} blocks", stats.total_bytes, stats.total_blocks);
}
