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
use crate::scenario::{Job, ScenarioFile, SunTableJob, TerrainShadowJob, TerrainSource};
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
        Job::TerrainShadow(job) => terrain_shadow(job, file, opts)?,
        Job::Tempest(job) => crate::tempest::run(job, file, opts)?,
        Job::Actions(job) => crate::actions_job::run(job, file, opts)?,
    };
    if let Some(dir) = opts.out_dir {
        let path = dir.join("facts.json");
        let json = json_for(&path, &outcome.facts, true)?;
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

fn terrain_shadow(job: &TerrainShadowJob, file: &ScenarioFile, opts: RunOptions<'_>) -> Result<Outcome> {
    use areo_ephemeris::{Mars24, SunModel};
    use areo_terrain::shadow::{Curvature, shadow_map};
    use areo_terrain::slope::slope_aspect;

    opts.progress.start(3, "terrain");
    let dem = match &job.terrain {
        TerrainSource::Synth(spec) => spec.build()?,
        TerrainSource::File(rel) => {
            let base = file.path.parent().unwrap_or(Path::new("."));
            crate::terrain_tools::read_dem(&base.join(rel))?
        }
    };
    opts.progress.advance(1);
    let site = Site::new(job.site.lat_deg, job.site.lon_east_deg)?;
    let t = parse_utc(&job.utc)?;
    let sun = Mars24.sun(t).at_site(&site);
    let curvature = if job.flat { Curvature::Flat } else { Curvature::of(&dem) };
    let map = shadow_map(&dem, sun.azimuth_deg, sun.elevation_deg, curvature);
    let sa = slope_aspect(&dem);
    opts.progress.advance(1);

    let valid: Vec<f32> = dem.elevations().iter().zip(dem.valid_mask()).filter(|(_, v)| **v).map(|(z, _)| *z).collect();
    let (lo, hi) = valid.iter().fold((f32::MAX, f32::MIN), |(a, b), z| (a.min(*z), b.max(*z)));
    let slopes: Vec<f64> = sa.slope_deg.iter().filter(|s| s.is_finite()).map(|s| f64::from(*s)).collect();
    let max_slope = slopes.iter().copied().fold(0.0, f64::max);
    let cast = map.cast.iter().zip(&map.valid).filter(|(c, v)| **c && **v).count() as f64 / valid.len().max(1) as f64;

    let mut o = Outcome::default();
    o.number("cells", (dem.cols() * dem.rows()) as f64);
    o.number("relief_m", f64::from(hi - lo));
    o.number("max_slope_deg", max_slope);
    o.number("mean_slope_deg", slopes.iter().sum::<f64>() / slopes.len().max(1) as f64);
    o.number("sun_azimuth_deg", sun.azimuth_deg);
    o.number("sun_elevation_deg", sun.elevation_deg);
    o.number("ltst_hours", SolarGeometry::at(t).ltst_hours(site.lon_east_deg()));
    o.number("lit_fraction", map.lit_fraction());
    o.number("cast_shadow_fraction", cast);
    o.summary.push(format!(
        "{} x {} cells of {} m x {} m, relief {:.1} m, slopes up to {max_slope:.1}°",
        dem.cols(),
        dem.rows(),
        dem.dx(),
        dem.dy(),
        hi - lo
    ));
    o.summary.push(format!(
        "Sun at azimuth {:.2}°, elevation {:.2}° ({}): {:.1} % of the ground in direct sun, {:.1} % in cast shadow",
        sun.azimuth_deg,
        sun.elevation_deg,
        format_utc(t),
        100.0 * map.lit_fraction(),
        100.0 * cast
    ));
    if let Some(dir) = opts.out_dir {
        let dem_path = dir.join("dem.tif");
        areo_terrain::geotiff::write(&dem, &dem_path)?;
        let shadow_path = dir.join("shadow.tif");
        let (files, _) = crate::terrain_tools::write_shadow(
            &dem,
            sun.azimuth_deg,
            sun.elevation_deg,
            job.flat,
            false,
            &shadow_path,
        )?;
        o.files.push(dem_path);
        o.files.extend(files);
    }
    opts.progress.advance(1);
    opts.progress.finish();
    Ok(o)
}

/// Writes `bytes` to `path` through a temporary file beside it, renamed into place
/// once complete: an interrupted run never leaves a truncated file under the real
/// name. Errors name the file.
pub(crate) fn write_file(path: &PathBuf, bytes: &[u8]) -> Result<()> {
    let io = |source| Error::Io { path: path.clone(), source };
    let mut partial = path.clone().into_os_string();
    partial.push(".partial");
    let partial = PathBuf::from(partial);
    let written = std::fs::File::create(&partial).and_then(|mut f| {
        f.write_all(bytes)?;
        f.sync_all()
    });
    if let Err(e) = written.and_then(|()| std::fs::rename(&partial, path)) {
        // Best effort: the partial file is of no use to anyone.
        let _ = std::fs::remove_file(&partial);
        return Err(io(e));
    }
    Ok(())
}

/// `value` as JSON (pretty), or an error naming the file it was meant for.
pub(crate) fn json_for(path: &std::path::Path, value: &impl serde::Serialize, pretty: bool) -> Result<String> {
    let text = if pretty { serde_json::to_string_pretty(value) } else { serde_json::to_string(value) };
    text.map_err(|e| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e) })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_are_written_whole_or_not_at_all() {
        let dir = std::env::temp_dir().join(format!("areo-write-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("plan.csv");
        write_file(&path, b"a,b\n1,2\n").unwrap();
        write_file(&path, b"a,b\n3,4\n").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b\n3,4\n");
        assert!(!dir.join("plan.csv.partial").exists());
        // Into a directory that does not exist: an error naming the file, nothing left.
        let missing = dir.join("no-such-dir").join("plan.json");
        let err = write_file(&missing, b"{}").unwrap_err();
        assert!(err.to_string().contains("no-such-dir/plan.json"), "{err}");
        assert!(!missing.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn json_that_cannot_be_written_is_an_error_naming_the_file() {
        // A map with non-string keys is not JSON.
        let bad: std::collections::HashMap<(u8, u8), u8> = [((1, 2), 3)].into_iter().collect();
        let err = json_for(std::path::Path::new("out/x/facts.json"), &bad, true).unwrap_err();
        assert!(err.to_string().contains("out/x/facts.json"), "{err}");
        assert_eq!(json_for(std::path::Path::new("f.json"), &[1, 2], false).unwrap(), "[1,2]");
    }
}
