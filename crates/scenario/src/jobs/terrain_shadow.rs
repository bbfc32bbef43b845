//! The terrain-shadow job: a DEM (synthesised or read) lit by the Sun at an instant.

use std::path::Path;

use areo_ephemeris::{Site, SolarGeometry, SunModel, format_utc, parse_utc};
use areo_terrain::geotiff::Grid;
use areo_terrain::hillshade::hillshade_rgb;
use areo_terrain::shadow::{Curvature, GridSunDirection, Shadows};
use areo_terrain::slope::slope_aspect;

use crate::error::Result;
use crate::format::{ScenarioFile, TerrainShadowJob, TerrainSource};
use crate::jobs::RunOptions;
use crate::report::{Raster, ShadowSun, TerrainShadowReport};

/// Computes the report: the map placed at the site, the Sun at the instant, the
/// direct-sun and slope maps and the figures read off them.
pub(crate) fn compute(
    job: &TerrainShadowJob,
    file: &ScenarioFile,
    opts: RunOptions<'_>,
) -> Result<TerrainShadowReport> {
    opts.progress.start(3, "terrain");
    let dem = match &job.terrain {
        TerrainSource::Synth(spec) => spec.build()?,
        TerrainSource::File(rel) => crate::terrain::read_job_dem(file, Path::new(rel), "job.terrain")?,
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

    // Read off the maps as they are dropped, so the report's rasters take their place:
    // the peak stays within the budget's bytes a cell.
    let (valid, lo, hi) = (dem.elevations().iter().zip(dem.valid_mask()))
        .filter(|(_, v)| **v)
        .fold((0usize, f32::MAX, f32::MIN), |(n, a, b), (z, _)| (n + 1, a.min(*z), b.max(*z)));
    let (steepest, slope_sum, with_slope) = (sa.slope_deg.iter().filter(|s| s.is_finite()))
        .fold((0.0, 0.0, 0usize), |(m, sum, n), s| (f64::max(m, f64::from(*s)), sum + f64::from(*s), n + 1));
    let cast = map.cast.iter().zip(&map.valid).filter(|(c, v)| **c && **v).count() as f64 / valid.max(1) as f64;
    let ltst_hours = match job.body.model() {
        areo_ephemeris::Body::Mars => SolarGeometry::at(utc).ltst_hours(site.lon_east_deg()),
        _ => state.local_solar_time_hours(site.lon_east_deg()),
    };
    let (lit_fraction, direct_sun) = (map.lit_fraction(), map.to_u8());
    let dark: Vec<bool> = (0..map.cast.len()).map(|i| !map.direct_sun(i)).collect();
    drop(map);
    let rgb = hillshade_rgb(&dem, &sa, Some(&dark), sun.azimuth_deg, sun.elevation_deg);
    drop((sa, dark));
    let preview: Vec<[u8; 3]> = rgb.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    drop(rgb);
    let (cols, rows) = (dem.cols(), dem.rows());
    let elevation_m =
        dem.elevations().iter().zip(dem.valid_mask()).map(|(z, ok)| if *ok { *z } else { f32::NAN }).collect();
    opts.progress.advance(1);
    opts.progress.finish();
    Ok(TerrainShadowReport {
        ltst_hours,
        sun: ShadowSun {
            utc: format_utc(utc),
            azimuth_deg: at_site.azimuth_deg,
            grid_azimuth_deg: sun.azimuth_deg,
            elevation_deg: sun.elevation_deg,
        },
        grid: Grid::of(&dem),
        cells: cols * rows,
        relief_m: f64::from(hi - lo),
        max_slope_deg: steepest,
        mean_slope_deg: slope_sum / with_slope.max(1) as f64,
        lit_fraction,
        cast_shadow_fraction: cast,
        elevation_m: Raster { cols, rows, values: elevation_m },
        direct_sun: Raster { cols, rows, values: direct_sun },
        preview_rgb: Raster { cols, rows, values: preview },
    })
}
