//! The terrain-shadow job: a DEM (synthesised or read) lit by the Sun at an instant.

use std::path::Path;

use areo_ephemeris::{Site, SolarGeometry, format_utc, parse_utc};

use crate::error::Result;
use crate::format::{ScenarioFile, TerrainShadowJob, TerrainSource};
use crate::jobs::RunOptions;
use crate::outcome::Outcome;

pub(crate) fn run(job: &TerrainShadowJob, file: &ScenarioFile, opts: RunOptions<'_>) -> Result<Outcome> {
    use areo_ephemeris::SunModel;
    use areo_terrain::shadow::{Curvature, Method, SunDirection, shadow_map};
    use areo_terrain::slope::slope_aspect;

    opts.progress.start(3, "terrain");
    let dem = match &job.terrain {
        TerrainSource::Synth(spec) => spec.build()?,
        TerrainSource::File(rel) => {
            let base = file.path.parent().unwrap_or(Path::new("."));
            crate::terrain::read_dem(&base.join(rel)).map_err(|e| e.referenced_by(&file.path, "job.terrain"))?
        }
    };
    opts.budget.check(&crate::budget::terrain_command("shadow", (dem.cols() * dem.rows()) as u64, 0))?;
    opts.progress.advance(1);
    let site = Site::on(job.body, job.site.lat_deg, job.site.lon_east_deg)?;
    let t = parse_utc(&job.utc)?;
    let state = job.body.sun(t);
    let sun = state.at_site(&site);
    // A synthesised map lies on the body's reference surface (its curvature).
    let dem = dem.placed_at(job.body.reference_surface(), site.lat_deg(), site.lon_east_deg())?;
    let curvature = if job.flat { Curvature::Flat } else { Curvature::of(&dem) };
    let map = shadow_map(&dem, SunDirection::new(sun.azimuth_deg, sun.elevation_deg), curvature, Method::OwnRay);
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
    let ltst = match job.body {
        areo_ephemeris::Body::Mars => SolarGeometry::at(t).ltst_hours(site.lon_east_deg()),
        _ => state.local_solar_time_hours(site.lon_east_deg()),
    };
    o.number("ltst_hours", ltst);
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
        let (files, _) = crate::terrain::write_shadow(
            &dem,
            sun.azimuth_deg,
            sun.elevation_deg,
            job.flat,
            Method::OwnRay,
            &shadow_path,
        )?;
        o.files.push(dem_path);
        o.files.extend(files);
    }
    opts.progress.advance(1);
    opts.progress.finish();
    Ok(o)
}
