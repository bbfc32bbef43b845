//! One full pose evaluation (kinematics + coupled forces + stability) of LSR-1 on a
//! rough 2 cm DEM — a 20° hill, a 25 cm deep ditch with 45° walls, rocks and noise —
//! the unit of work of the action planner. Target: ≤ 5 µs on one core, i.e. ≥ 2 × 10⁵
//! evaluations per second, warm-started along a motion as the planner runs them.

use areo_rover::RoverParams;
use areo_rover::arm::ArmState;
use areo_rover::evaluation::{Conditions, Evaluator, Place};
use areo_terrain::Dem;
use areo_terrain::synth::{Feature, Noise, TerrainSpec};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn terrain() -> Dem {
    TerrainSpec {
        cols: 300,
        rows: 200,
        cell_m: 0.02,
        base_m: 0.0,
        seed: 3,
        noise: Some(Noise { amplitude_m: 0.02, wavelength_m: 0.5, octaves: 3, persistence: 0.5 }),
        features: vec![
            Feature::Hill { x_m: 4.5, y_m: 2.0, radius_m: 1.5, slope_deg: 20.0 },
            Feature::Ditch { from_m: (2.0, 0.0), to_m: (2.0, 4.0), width_m: 0.6, depth_m: 0.25, wall_deg: 45.0 },
            Feature::Rock { x_m: 1.2, y_m: 1.7, height_m: 0.08, width_m: 0.2 },
        ],
    }
    .build()
    .expect("the bench terrain is valid")
}

fn pose(c: &mut Criterion) {
    let dem = terrain();
    let params = RoverParams::lsr1();
    let ev = Evaluator::new(&params);
    let arm = ArmState::stowed(&params);
    let cond = Conditions { mu: 0.8, direction: 1.0 };
    // A 10 cm move heading east over the rock and onto the hill's flank, 1 cm steps.
    let places: Vec<Place> =
        (0..10).map(|i| Place { x: 1.0 + 0.01 * i as f64 + 2.3, y: 1.9, heading: 80f64.to_radians() }).collect();
    // The pose 1 cm before the first, as the previous step of the motion leaves it.
    let before = Place { x: places[0].x - 0.01, ..places[0] };
    let start = ev.evaluate(&dem, before, &arm, &cond, None).expect("admissible").pose;
    let mut g = c.benchmark_group("rover_pose");
    g.throughput(Throughput::Elements(places.len() as u64));
    g.bench_function("evaluate_warm_rough_dem", |b| {
        b.iter(|| {
            let mut warm = Some(start);
            let mut s = 0.0;
            for p in &places {
                let e = ev.evaluate(&dem, *p, &arm, &cond, warm.as_ref()).expect("admissible");
                s += e.stability;
                warm = Some(e.pose);
            }
            s
        })
    });
    // The parts: the pose alone (warm), and forces + stability at fixed poses.
    let kin = ev.kinematics();
    g.bench_function("kinematics_warm_rough_dem", |b| {
        b.iter(|| {
            let mut warm = Some(start);
            for p in &places {
                warm = Some(kin.solve(&dem, p.x, p.y, p.heading, warm.as_ref()).expect("admissible"));
            }
            warm
        })
    });
    let poses: Vec<_> =
        places.iter().map(|p| kin.solve(&dem, p.x, p.y, p.heading, None).expect("admissible")).collect();
    g.bench_function("forces_stability_rough_dem", |b| {
        b.iter(|| {
            poses.iter().map(|q| ev.evaluate_pose(&dem, q, &arm, &cond).expect("admissible").stability).sum::<f64>()
        })
    });
    g.bench_function("evaluate_cold_rough_dem", |b| {
        b.iter(|| {
            places.iter().map(|p| ev.evaluate(&dem, *p, &arm, &cond, None).expect("admissible").stability).sum::<f64>()
        })
    });
    // The same move by the same rover with its bogie turned behind (the MER/MSL
    // layout), solved as the mirror image: what the two flips and the turned force
    // balance cost.
    let mut turned = params.clone();
    turned.bogie_pivot_m.x = -turned.bogie_pivot_m.x;
    let ev_turned = Evaluator::new(&turned);
    let start_turned = ev_turned.evaluate(&dem, before, &arm, &cond, None).expect("admissible").pose;
    g.bench_function("evaluate_warm_rough_dem_bogie_behind", |b| {
        b.iter(|| {
            let mut warm = Some(start_turned);
            let mut s = 0.0;
            for p in &places {
                let e = ev_turned.evaluate(&dem, *p, &arm, &cond, warm.as_ref()).expect("admissible");
                s += e.stability;
                warm = Some(e.pose);
            }
            s
        })
    });
    g.finish();
}

criterion_group!(benches, pose);
criterion_main!(benches);
