//! The terrain-shadow job: a DEM (synthesised or read) lit by the Sun at an instant.

use std::path::{Path, PathBuf};

use areo_ephemeris::{Site, SolarGeometry, SunModel, format_utc, parse_utc};
use areo_terrain::Dem;
use areo_terrain::shadow::{Curvature, GridSunDirection, Method, Shadows};
use areo_terrain::slope::slope_aspect;
use hifitime::Epoch;

use crate::error::Result;
use crate::format::{ScenarioFile, TerrainShadowJob, TerrainSource};
use crate::jobs::RunOptions;
use crate::outcome::Outcome;

/// What a terrain-shadow job computed: the placed map, the Sun at the instant and the
/// light and relief figures read off the shadow and slope maps.
struct ShadowReport {
    dem: Dem,
    utc: Epoch,
    /// The Sun's direction on the grid's axes.
    sun: GridSunDirection,
    /// Its true azimuth at the site, degrees clockwise from north.
    true_azimuth_deg: f64,
    ltst_hours: f64,
    lit_fraction: f64,
    cast_shadow_fraction: f64,
    relief_m: f64,
    max_slope_deg: f64,
    mean_slope_deg: f64,
}

/// Runs a terrain-shadow job: compute the report, then its facts and files.
pub(crate) fn run(job: &TerrainShadowJob, file: &ScenarioFile, opts: RunOptions<'_>) -> Result<Outcome> {
    let report = compute(job, file, opts)?;
    let mut o = outcome(&report);
    if let Some(dir) = opts.out_dir {
        o.files = write(dir, job, &report)?;
    }
    opts.progress.advance(1);
    opts.progress.finish();
    Ok(o)
}

fn compute(job: &TerrainShadowJob, file: &ScenarioFile, opts: RunOptions<'_>) -> Result<ShadowReport> {
    opts.progress.start(3, "terrain");
    let dem = match &job.terrain {
        TerrainSource::Synth(spec) => spec.build()?,
        TerrainSource::File(rel) => {
            let base = file.path.parent().unwrap_or(Path::new("."));
            crate::terrain::read_dem(&base.join(rel)).map_err(|e| e.referenced_by(&file.path, "job.terrain"))?
        }
    };
    opts.budget.check(&crate::budget::DemCommand::Shadow.estimate((dem.cols() * dem.rows()) as u64))?;
    opts.progress.advance(1);
    let site = Site::on(job.body.model(), job.site.lat_deg, job.site.lon_east_deg)?;
    let utc = parse_utc(&job.utc)?;
    let state = job.body.model().sun(utc);
    let at_site = state.at_site(&site);
    // A synthesised map lies on the body's reference surface (its curvature).
    let dem = dem.placed_at(job.body.model().reference_surface(), site.lat_deg(), site.lon_east_deg())?;
    // Shadows are cast along the grid: a polar map's north is not the site's.
    let grid_azimuth = dem.georef().projection.grid_azimuth_deg(at_site.azimuth_deg, site.lon_east_deg());
    let sun = GridSunDirection::new(grid_azimuth, at_site.elevation_deg);
    let curvature = if job.flat { Curvature::Flat } else { Curvature::of(&dem) };
    let map = Shadows::new(sun, curvature).map(&dem);
    let sa = slope_aspect(&dem);
    opts.progress.advance(1);

    let valid: Vec<f32> = dem.elevations().iter().zip(dem.valid_mask()).filter(|(_, v)| **v).map(|(z, _)| *z).collect();
    let (lo, hi) = valid.iter().fold((f32::MAX, f32::MIN), |(a, b), z| (a.min(*z), b.max(*z)));
    let slopes: Vec<f64> = sa.slope_deg.iter().filter(|s| s.is_finite()).map(|s| f64::from(*s)).collect();
    let cast = map.cast.iter().zip(&map.valid).filter(|(c, v)| **c && **v).count() as f64 / valid.len().max(1) as f64;
    let ltst_hours = match job.body.model() {
        areo_ephemeris::Body::Mars => SolarGeometry::at(utc).ltst_hours(site.lon_east_deg()),
        _ => state.local_solar_time_hours(site.lon_east_deg()),
    };
    Ok(ShadowReport {
        utc,
        sun,
        true_azimuth_deg: at_site.azimuth_deg,
        ltst_hours,
        lit_fraction: map.lit_fraction(),
        cast_shadow_fraction: cast,
        relief_m: f64::from(hi - lo),
        max_slope_deg: slopes.iter().copied().fold(0.0, f64::max),
        mean_slope_deg: slopes.iter().fold(0.0, |a, b| a + b) / slopes.len().max(1) as f64,
        dem,
    })
}

fn outcome(r: &ShadowReport) -> Outcome {
    let mut o = Outcome::default();
    let dem = &r.dem;
    o.count("cells", (dem.cols() * dem.rows()) as u64);
    o.number("relief_m", r.relief_m);
    o.number("max_slope_deg", r.max_slope_deg);
    o.number("mean_slope_deg", r.mean_slope_deg);
    o.number("sun_azimuth_deg", r.true_azimuth_deg);
    o.number("sun_grid_azimuth_deg", r.sun.azimuth_deg);
    o.number("sun_elevation_deg", r.sun.elevation_deg);
    o.number("ltst_hours", r.ltst_hours);
    o.number("lit_fraction", r.lit_fraction);
    o.number("cast_shadow_fraction", r.cast_shadow_fraction);
    o.summary.push(format!(
        "{} × {} cells of {} m × {} m, relief {:.1} m, slopes up to {:.1}°",
        dem.cols(),
        dem.rows(),
        dem.dx(),
        dem.dy(),
        r.relief_m,
        r.max_slope_deg
    ));
    o.summary.push(format!(
        "Sun at azimuth {:.2}°{}, elevation {:.2}° ({}): {:.1} % of the ground in direct sun, {:.1} % in cast shadow",
        r.true_azimuth_deg,
        crate::terrain::grid_azimuth_said(r.true_azimuth_deg, r.sun.azimuth_deg),
        r.sun.elevation_deg,
        format_utc(r.utc),
        100.0 * r.lit_fraction,
        100.0 * r.cast_shadow_fraction
    ));
    o
}

/// dem.tif, shadow.tif and its preview.
fn write(dir: &Path, job: &TerrainShadowJob, r: &ShadowReport) -> Result<Vec<PathBuf>> {
    let dem_path = dir.join("dem.tif");
    areo_terrain::geotiff::write(&r.dem, &dem_path)?;
    let shadow_path = dir.join("shadow.tif");
    let (files, _) = crate::terrain::write_shadow(
        &r.dem,
        r.sun.azimuth_deg,
        r.sun.elevation_deg,
        job.flat,
        Method::OwnRay,
        &shadow_path,
    )?;
    Ok(std::iter::once(dem_path).chain(files).collect())
}
