//! A sweep through a real single-node Slurm: `.ci/slurm-up` starts slurmctld, slurmd
//! and munge from Debian's packages and prints the SLURM_CONF; `.ci/run` exports it with
//! `AREO_REQUIRE_SLURM=1`. Eight tasks go through `areo sweep slurm` and `sbatch
//! --wait` as a job array, are collected, and must equal the same tasks run in-process.
//! Without a Slurm, the test fails where `AREO_REQUIRE_SLURM` is set (CI) and says it
//! did not run otherwise.

use std::path::{Path, PathBuf};
use std::process::Command;

fn areo(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_areo")).args(args).output().expect("run areo")
}

fn slurm_ready() -> Result<(), String> {
    match Command::new("sinfo").args(["-h", "-o", "%t"]).output() {
        Ok(out) if out.status.success() => {
            let states = String::from_utf8_lossy(&out.stdout).into_owned();
            if states.lines().any(|s| matches!(s.trim(), "idle" | "mix" | "alloc")) {
                Ok(())
            } else {
                Err(format!("sinfo shows no usable node: {states:?}"))
            }
        }
        Ok(out) => Err(format!("sinfo failed: {}", String::from_utf8_lossy(&out.stderr))),
        Err(e) => Err(format!("sinfo not found ({e}): start one with .ci/slurm-up")),
    }
}

fn sweep_dir(root: &Path, name: &str) -> PathBuf {
    let dir = root.join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
// Saying that the test did not run is the point of its one message.
#[allow(clippy::print_stderr)]
fn an_eight_task_sweep_through_a_real_slurm_equals_running_it_in_process() {
    if let Err(why) = slurm_ready() {
        if std::env::var_os("AREO_REQUIRE_SLURM").is_some() {
            panic!("AREO_REQUIRE_SLURM is set but there is no Slurm to run on: {why}");
        }
        eprintln!("not run: no Slurm here ({why}); .ci/run starts one and requires it");
        return;
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target").join("slurm-test");
    std::fs::create_dir_all(&root).unwrap();
    std::fs::write(
        root.join("shadow.ron"),
        r#"Scenario(version: 1, description: "slurm", job: TerrainShadow(
            terrain: Synth(cols: 60, rows: 40, cell_m: 10.0, seed: 9,
                noise: (amplitude_m: 2.0, wavelength_m: 150.0, octaves: 2),
                features: [Hill(x_m: 300, y_m: 200, radius_m: 90, slope_deg: 25)]),
            site: (lat_deg: -4.5895, lon_east_deg: 137.4417),
            utc: "2012-08-06T21:00:00Z",
            flat: false))"#,
    )
    .unwrap();
    std::fs::write(
        root.join("shadows.sweep.ron"),
        r#"Sweep(version: 1, base: "shadow.ron", name: "{index}-flat-{flat}", axes: [
            (name: "utc", path: "job.utc", values: ["2012-08-06T20:00:00Z", "2012-08-06T21:00:00Z", "2012-08-06T23:00:00Z", "2012-08-07T01:30:00Z"]),
            (name: "flat", path: "job.flat", values: [false, true]),
        ])"#,
    )
    .unwrap();
    let sweep = root.join("shadows.sweep.ron");
    let (on_slurm, in_process) = (sweep_dir(&root, "on-slurm"), sweep_dir(&root, "in-process"));
    for dir in [&on_slurm, &in_process] {
        let out = areo(&["sweep", "expand", sweep.to_str().unwrap(), "-o", dir.to_str().unwrap()]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    // Through Slurm: the recipe as printed, submitted, waited for.
    let script = areo(&["sweep", "slurm", on_slurm.to_str().unwrap(), "--parallel", "4", "--cpus", "1"]);
    assert!(script.status.success());
    let job = on_slurm.join("job.sh");
    std::fs::write(&job, &script.stdout).unwrap();
    let submitted = Command::new("sbatch").arg("--wait").arg(&job).output().expect("sbatch");
    assert!(
        submitted.status.success(),
        "sbatch: {} {}",
        String::from_utf8_lossy(&submitted.stdout),
        String::from_utf8_lossy(&submitted.stderr)
    );
    // Every task logged its run, with the allocation's thread count.
    let logs: Vec<String> = std::fs::read_dir(on_slurm.join("logs"))
        .unwrap()
        .map(|e| std::fs::read_to_string(e.unwrap().path()).unwrap())
        .collect();
    assert_eq!(logs.len(), 8, "{logs:?}");
    assert!(logs.iter().all(|l| l.contains(": done") && l.contains("1 threads (SLURM_CPUS_PER_TASK)")), "{logs:?}");
    // In-process: the same tasks one by one.
    for i in 0..8 {
        let out = areo(&["sweep", "run", in_process.to_str().unwrap(), "--index", &i.to_string()]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    for dir in [&on_slurm, &in_process] {
        let out = areo(&["sweep", "collect", dir.to_str().unwrap()]);
        assert!(String::from_utf8_lossy(&out.stdout).starts_with("8 finished, 0 missing, 0 failed"));
    }
    let a = std::fs::read_to_string(on_slurm.join("results.csv")).unwrap();
    let b = std::fs::read_to_string(in_process.join("results.csv")).unwrap();
    assert_eq!(a.lines().count(), 9);
    assert_eq!(a, b, "the Slurm run and the in-process run differ");
}
