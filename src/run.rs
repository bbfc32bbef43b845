//! Runs a scenario's job through the library crates and collects its [`Outcome`].

use std::io::Write;
use std::path::{Path, PathBuf};

use areo_ephemeris::events::daylight_intervals;
use areo_ephemeris::flux::Atmosphere;
use areo_ephemeris::{HorizonMask, Site, SolarGeometry, format_utc, parse_utc};
use hifitime::Unit;

use crate::error::{Error, Result};
use crate::outcome::Outcome;
use crate::progress::Progress;
use crate::scenario::{Job, ScenarioFile, SunTableJob};
use crate::sun_report::{CSV_HEADER, SunRow};

/// How to run a job.
#[derive(Clone, Copy)]
pub struct RunOptions<'a> {
    /// Where to write output files (`None`: write nothing).
    pub out_dir: Option<&'a Path>,
    /// Where to report progress.
    pub progress: &'a dyn Progress,
}

impl std::fmt::Debug for RunOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RunOptions").field("out_dir", &self.out_dir).finish_non_exhaustive()
    }
}

/// Runs the scenario's job; writes its files into `opts.out_dir` if given.
pub fn run(file: &ScenarioFile, opts: RunOptions<'_>) -> Result<Outcome> {
    if let Some(dir) = opts.out_dir {
        std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.to_path_buf(), source })?;
    }
    let mut outcome = match &file.scenario.job {
        Job::SunTable(job) => sun_table(job, opts)?,
    };
    if let Some(dir) = opts.out_dir {
        let path = dir.join("facts.json");
        let json = serde_json::to_string_pretty(&outcome.facts).unwrap_or_default();
        write_file(&path, json.as_bytes())?;
        outcome.files.push(path);
    }
    Ok(outcome)
}

fn sun_table(job: &SunTableJob, opts: RunOptions<'_>) -> Result<Outcome> {
    let site = Site::new(job.site.lat_deg, job.site.lon_east_deg)?;
    let start = parse_utc(&job.start_utc)?;
    let mask = match &job.horizon_deg {
        Some(h) => HorizonMask::new(h.clone())?,
        None => HorizonMask::flat(),
    };
    let atmosphere = Atmosphere::BeerLambert { tau: job.tau };
    let step_s = job.step_min * 60.0;
    let rows = (job.duration_h * 3600.0 / step_s).floor() as u64 + 1;
    let end = start + job.duration_h * Unit::Hour;

    opts.progress.start(rows, "sun table");
    let mut csv = String::with_capacity(rows as usize * 120);
    csv.push_str(CSV_HEADER);
    csv.push_str(",horizon_deg,sunlit,horizontal_flux_w_m2\n");
    let (mut max_el, mut min_el) = (f64::MIN, f64::MAX);
    let mut insolation_j_m2 = 0.0;
    let mut prev_flux: Option<f64> = None;
    for k in 0..rows {
        let t = start + (k as f64 * step_s) * Unit::Second;
        let row = SunRow::at(t, Some(&site));
        let (az, el) = (row.azimuth_deg.unwrap_or(0.0), row.elevation_deg.unwrap_or(0.0));
        let horizon = mask.elevation_at(az);
        let sunlit = el > horizon;
        let flux = if sunlit { atmosphere.horizontal_w_m2(el, row.sun_distance_au) } else { 0.0 };
        if let Some(p) = prev_flux {
            insolation_j_m2 += 0.5 * (p + flux) * step_s;
        }
        prev_flux = Some(flux);
        max_el = max_el.max(el);
        min_el = min_el.min(el);
        csv.push_str(&format!("{},{horizon:.4},{},{flux:.3}\n", row.csv(), u8::from(sunlit)));
        opts.progress.advance(1);
    }
    opts.progress.finish();

    let daylight = daylight_intervals(&site, &mask, start, end);
    let daylight_h: f64 = daylight.iter().map(|(a, b)| (*b - *a).to_seconds()).sum::<f64>() / 3600.0;
    let g0 = SolarGeometry::at(start);

    let mut o = Outcome::default();
    o.number("rows", rows as f64);
    o.number("ls_start_deg", g0.ls_deg);
    o.number("ltst_start_hours", g0.ltst_hours(site.lon_east_deg()));
    o.number("max_elevation_deg", max_el);
    o.number("min_elevation_deg", min_el);
    o.number("daylight_hours", daylight_h);
    o.number("daylight_periods", daylight.len() as f64);
    o.number("insolation_wh_m2", insolation_j_m2 / 3600.0);
    // A daylight period that starts at the table's first instant is not a sunrise.
    if let Some((rise, _)) = daylight.iter().find(|(a, _)| *a > start) {
        o.text("first_sunrise_utc", format_utc(*rise));
        o.number("first_sunrise_ltst_hours", SolarGeometry::at(*rise).ltst_hours(site.lon_east_deg()));
    }
    o.summary.push(format!(
        "Sun over ({:.4}°, {:.4}°E) from {} for {:.2} h: Ls {:.2}°, elevation {:.2}°..{:.2}°",
        site.lat_deg(),
        site.lon_east_deg(),
        format_utc(start),
        job.duration_h,
        g0.ls_deg,
        min_el,
        max_el
    ));
    o.summary.push(format!(
        "{} daylight period(s), {:.2} h of sun; insolation on a horizontal surface {:.0} Wh/m² (τ = {})",
        daylight.len(),
        daylight_h,
        insolation_j_m2 / 3600.0,
        job.tau
    ));
    if let Some(dir) = opts.out_dir {
        let path = dir.join("sun.csv");
        write_file(&path, csv.as_bytes())?;
        o.files.push(path);
    }
    Ok(o)
}

fn write_file(path: &PathBuf, bytes: &[u8]) -> Result<()> {
    let io = |source| Error::Io { path: path.clone(), source };
    let mut f = std::fs::File::create(path).map_err(io)?;
    f.write_all(bytes).map_err(io)
}
