//! Sweeps at scale: expanding a 10 000-task sweep and collecting 10 000 finished tasks
//! (targets < 5 s each), and a task's overhead beyond its job (< 50 ms): a trivial Sun
//! table run as sweep task against the same job run directly.

use std::hint::black_box;
use std::path::{Path, PathBuf};

use areo_scenario::budget::Budget;
use areo_scenario::{NoProgress, sweep};
use criterion::{Criterion, criterion_group, criterion_main};

const BASE: &str = r#"Scenario(version: 1, description: "bench", job: SunTable(
    site: (lat_deg: -4.5895, lon_east_deg: 137.4417),
    start_utc: "2012-08-06T00:00:00Z", duration_h: 1, step_min: 30, tau: 0.5))"#;

fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("areo-sweep-bench-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A 100 × 100 sweep over the Sun table's optical depth and step.
fn sweep_file(dir: &Path) -> PathBuf {
    std::fs::write(dir.join("sun.ron"), BASE).unwrap();
    let path = dir.join("big.sweep.ron");
    std::fs::write(
        &path,
        r#"Sweep(version: 1, base: "sun.ron", axes: [
            (name: "tau", path: "job.tau", range: (0.0, 4.95, 0.05)),
            (name: "step", path: "job.step_min", range: (1, 100, 1)),
        ])"#,
    )
    .unwrap();
    path
}

fn sweeps(c: &mut Criterion) {
    let mut g = c.benchmark_group("sweep");
    g.sample_size(10);
    let dir = scratch("expand");
    let file = sweep_file(&dir);
    g.bench_function("expand_10000_tasks", |b| {
        b.iter(|| black_box(sweep::expand(&file, &dir.join("run")).unwrap().len()))
    });
    // Collect: every task finished with a facts file like a Sun table's (expanded here
    // too, so a filtered run that skips the expansion bench still has its tasks).
    let tasks = sweep::expand(&file, &dir.join("run")).unwrap();
    for t in &tasks {
        let out = dir.join("run/out").join(&t.id);
        std::fs::create_dir_all(&out).unwrap();
        std::fs::write(
            out.join("facts.json"),
            format!(
                "{{\"rows\": 3.0, \"max_elevation_deg\": {}, \"sunrise_utc\": \"2012-08-06T11:00:00.000Z\"}}",
                t.index
            ),
        )
        .unwrap();
    }
    g.bench_function("collect_10000_tasks", |b| {
        b.iter(|| black_box(sweep::collect(&dir.join("run"), None).unwrap().finished))
    });
    // A task's overhead: the same Sun table as a sweep task (manifest, staging, rename,
    // facts) and run directly in memory.
    let small = scratch("task");
    std::fs::write(small.join("sun.ron"), BASE).unwrap();
    std::fs::write(
        small.join("one.sweep.ron"),
        r#"Sweep(version: 1, base: "sun.ron", axes: [(name: "tau", path: "job.tau", values: [0.5])])"#,
    )
    .unwrap();
    sweep::expand(&small.join("one.sweep.ron"), &small.join("run")).unwrap();
    g.bench_function("task_as_sweep_task", |b| {
        b.iter(|| {
            black_box(sweep::run_task(&small.join("run"), 0, true, &NoProgress, Budget::for_this_machine()).is_ok())
        })
    });
    let file = areo_scenario::format::load(&small.join("sun.ron")).unwrap();
    g.bench_function("task_run_directly", |b| {
        b.iter(|| {
            black_box(
                areo_scenario::run(
                    &file,
                    areo_scenario::RunOptions {
                        out_dir: None,
                        progress: &NoProgress,
                        budget: Budget::for_this_machine(),
                    },
                )
                .is_ok(),
            )
        })
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&small);
}

criterion_group!(benches, sweeps);
criterion_main!(benches);
