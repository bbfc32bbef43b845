//! The action planner's unit of work: executing plans on the LSR-1 model. Targets
//! (issue 9): ≥ 50 000 module executions per second per core (a 40-module plan in
//! < 1 ms), and a full 50 × 20 GA run on task 1 in < 2 s on 2 cores.

use areo_actions::{ExecConfig, Executor, GaConfig, Inventory, Sample, Scale, Task, Weights, evolve};
use areo_rover::RoverParams;
use areo_rover::evaluation::Evaluator;
use areo_rover::motion::Module;
use areo_terrain::Dem;
use areo_terrain::synth::{Feature, Noise, TerrainSpec};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

/// Task 1's terrain (scenarios/ditch-and-hill.ron without the rocks).
fn terrain() -> Dem {
    TerrainSpec {
        cols: 150,
        rows: 300,
        cell_m: 0.02,
        base_m: 0.0,
        seed: 5,
        noise: Some(Noise { amplitude_m: 0.005, wavelength_m: 0.5, octaves: 2, persistence: 0.5 }),
        features: vec![
            Feature::Ditch { from_m: (0.0, 1.5), to_m: (3.0, 1.5), width_m: 0.2, depth_m: 0.2, wall_deg: 70.0 },
            Feature::Hill { x_m: 1.5, y_m: 4.6, radius_m: 1.39, slope_deg: 25.0 },
        ],
    }
    .build()
    .expect("the bench terrain is valid")
}

fn task() -> Task {
    Task {
        start: (1.5, 0.6, 0.0),
        target: (1.5, 4.6),
        target_radius_m: 0.2,
        samples: vec![Sample { x_m: 1.45, y_m: 1.05, mass_kg: 0.1 }],
        samples_wanted: 1,
        rocks: Vec::new(),
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
    // 40 modules on the ground before the ditch: forward, turn, back, turn, a wide arc
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
    g.bench_function("ga_50x20_task1", |b| {
        b.iter(|| evolve(&executor, &inventory, &Weights::default(), &scale, &config).expect("valid settings"))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
