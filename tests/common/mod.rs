//! Fixtures the command-line tests share: a small Sun-table scenario at Gale crater and
//! a sweep over its optical depth.

use std::path::{Path, PathBuf};

/// Writes `NAME.ron` in `dir`: the Sun over Gale crater from 2012-08-06T00:00Z for
/// `duration_h` hours every `step_min` minutes, at optical depth `tau`. Returns its path.
pub(crate) fn sun_table(dir: &Path, name: &str, (duration_h, step_min, tau): (f64, f64, f64)) -> PathBuf {
    let path = dir.join(format!("{name}.ron"));
    std::fs::write(
        &path,
        format!(
            r#"Scenario(version: 1, description: "t", job: SunTable(site: (lat_deg: -4.5895, lon_east_deg: 137.4417),
            start_utc: "2012-08-06T00:00:00Z", duration_h: {duration_h:?}, step_min: {step_min:?}, tau: {tau:?}))"#
        ),
    )
    .unwrap();
    path
}

/// Writes `tau.sweep.ron` in `dir`: a sweep of `base` (a file beside it) over τ from
/// `from` to `to` by `step`, its tasks named `tau-{tau}`. Returns its path.
pub(crate) fn tau_sweep(dir: &Path, base: &str, (from, to, step): (f64, f64, f64)) -> PathBuf {
    let path = dir.join("tau.sweep.ron");
    std::fs::write(
        &path,
        format!(
            r#"Sweep(version: 1, base: "{base}", name: "tau-{{tau}}", axes: [(name: "tau", path: "job.tau", range: ({from:?}, {to:?}, {step:?}))])"#
        ),
    )
    .unwrap();
    path
}
