//! The action planner's unit of work: executing plans on the LSR-1 model. Targets
//! : ≥ 50 000 module executions per second per core (a 40-module plan in
//! < 1 ms), and a full 50 × 20 GA run on task 1 in < 2 s on 2 cores.

use areo_actions::{ExecConfig, Executor, GaConfig, Inventory, Sample, Scale, Task, Weights, evolve};
use areo_rover::RoverParams;
use areo_rover::evaluation::Evaluator;
use areo_rover::motion::Module;
use areo_terrain::Dem;
use areo_terrain::synth::{Feature, Noise, TerrainSpec};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

/// Task 1's terrain (scenarios/ditch-and-hill.ron).
fn terrain() -> Dem {
    let rock = |x_m, y_m, height_m, width_m| Feature::Rock { x_m, y_m, height_m, width_m };
    TerrainSpec {
        cols: 200,
        rows: 320,
        cell_m: 0.02,
        base_m: 0.0,
        seed: 5,
        noise: Some(Noise { amplitude_m: 0.005, wavelength_m: 0.5, octaves: 2, persistence: 0.5 }),
        features: vec![
            Feature::Ditch { from_m: (0.0, 1.9), to_m: (4.0, 1.9), width_m: 0.25, depth_m: 0.25, wall_deg: 70.0 },
            Feature::AsymmetricHill {
                x_m: 2.4,
                y_m: 5.0,
                height_m: 0.65,
                west_slope_deg: 25.0,
                east_slope_deg: 70.0,
                top_radius_m: 0.5,
            },
            rock(1.70, 1.45, 0.20, 0.22),
            rock(2.30, 2.75, 0.19, 0.22),
            rock(2.00, 3.60, 0.15, 0.20),
            rock(2.55, 2.35, 0.12, 0.18),
            rock(1.35, 2.65, 0.16, 0.20),
            rock(2.80, 3.50, 0.18, 0.22),
            rock(1.05, 0.95, 0.10, 0.15),
            rock(2.95, 0.85, 0.14, 0.18),
            rock(1.10, 3.90, 0.12, 0.16),
        ],
    }
    .build()
    .expect("the bench terrain is valid")
}

fn task() -> Task {
    let sample = |x_m, y_m| Sample { x_m, y_m, mass_kg: 0.1 };
    Task {
        start: (2.0, 0.6, 0.0),
        target: (2.4, 5.0),
        target_radius_m: 0.25,
        samples: vec![
            sample(1.55, 1.25),
            sample(1.45, 2.85),
            sample(2.70, 2.60),
            sample(3.10, 1.30),
            sample(3.00, 4.30),
        ],
        samples_wanted: 1,
        // The rocks as obstacles for the body, as the scenario job lists them.
        rocks: vec![
            areo_actions::Rock { x_m: 1.70, y_m: 1.45, height_m: 0.20, width_m: 0.22 },
            areo_actions::Rock { x_m: 2.30, y_m: 2.75, height_m: 0.19, width_m: 0.22 },
            areo_actions::Rock { x_m: 2.00, y_m: 3.60, height_m: 0.15, width_m: 0.20 },
        ],
        manipulation: false,
        communication: false,
        video: false,
        recharge: false,
        tray: false,
    }
}

fn bench(c: &mut Criterion) {
    let dem = terrain();
    let params = RoverParams::lsr1();
    let evaluator = Evaluator::new(&params);
    let task = task();
    let executor = Executor::new(&dem, &evaluator, &task, ExecConfig::default());
    // 40 modules on the ground before the ditch (clear of the rocks): forward, turn, back, turn, a wide arc
    // and its way back — ten driving centimetres or five degrees each.
    let plan: Vec<Module> = (0..40)
        .map(|i| match i % 4 {
            0 => Module::Forward,
            1 => Module::TurnLeft,
            2 => Module::Backward,
            _ => Module::TurnRight,
        })
        .collect();
    let e = executor.run(&plan, false);
    assert_eq!(e.prefix_len, 40, "the bench plan runs to its end");
    let mut g = c.benchmark_group("actions");
    g.throughput(Throughput::Elements(40));
    g.bench_function("execute_40_modules", |b| b.iter(|| executor.run(&plan, false)));
    g.throughput(Throughput::Elements(1));
    g.sample_size(10);
    let inventory = Inventory::from_codes(&[101, 105, 106, 107, 108, 3000, 3001, 3002, 3003]).expect("valid codes");
    let scale = Scale {
        start_distance_m: task.start_distance_m(),
        samples_wanted: 1,
        reference_time_s: task.start_distance_m() / params.speed_m_s,
        battery_wh: 48.0,
        s_floor: 0.2,
    };
    let config = GaConfig { initial_length: (60, 100), ..GaConfig::default() };
    let weights = Weights { samples: 2.0, ..Weights::default() };
    g.bench_function("ga_50x20_task1", |b| {
        b.iter(|| evolve(&executor, &inventory, &weights, &scale, &config).expect("valid settings"))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
