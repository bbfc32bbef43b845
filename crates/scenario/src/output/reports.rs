//! The files and summary lines of the Sun-table and terrain-shadow jobs, read off their
//! [`Report`]s alone, so what a file shows is what the report holds.

use std::path::{Path, PathBuf};

use areo_terrain::geotiff;

use crate::error::Result;
use crate::report::{Report, SunTableReport, TerrainShadowReport};
use crate::sun::CSV_HEADER;

use super::csv::Table;

mod actions;
mod actions_files;
mod actions_view;
mod shadows;
mod stac;
mod tempest;
mod tempest_files;
mod tempest_time;
mod view;

/// Writes the report's files into `dir`; returns them. (A TEMPEST job's routes, layers
/// and plots, and the actions job's files, are written by the job from what it
/// computed.)
pub(crate) fn write(dir: &Path, report: &Report) -> Result<Vec<PathBuf>> {
    match report {
        Report::SunTable(r) => sun_table_files(dir, r),
        Report::TerrainShadow(r) => terrain_shadow_files(dir, r),
        Report::Tempest(r) => tempest_files::write(dir, r),
        Report::Actions(r) => actions_files::write(dir, r),
    }
}

/// The report's lines for a person to read.
pub(crate) fn summary(report: &Report) -> Vec<String> {
    match report {
        Report::SunTable(r) => sun_table_summary(r),
        Report::TerrainShadow(r) => terrain_shadow_summary(r),
        Report::Tempest(r) => tempest::summary(r),
        Report::Actions(r) => actions::summary(r),
    }
}

/// `sun.csv`: the Sun's columns, then the horizon mask's elevation, whether the Sun
/// is above it and the horizontal flux.
fn sun_table_files(dir: &Path, r: &SunTableReport) -> Result<Vec<PathBuf>> {
    let mut table = Table::new(CSV_HEADER.split(',').chain(["horizon_deg", "sunlit", "horizontal_flux_w_m2"]));
    for row in &r.table {
        let mut fields = row.sun.csv_fields();
        fields.extend([
            format!("{:.4}", row.horizon_deg),
            u8::from(row.sunlit).to_string(),
            format!("{:.3}", row.horizontal_flux_w_m2),
        ]);
        table.push(fields);
    }
    let path = dir.join("sun.csv");
    table.write(&path)?;
    Ok(vec![path])
}

fn sun_table_summary(r: &SunTableReport) -> Vec<String> {
    vec![
        format!(
            "Sun over ({:.4}°, {:.4}°E) from {} for {:.2} h: Ls {:.2}°, elevation {:.2}°..{:.2}°",
            r.lat_deg,
            r.lon_east_deg,
            r.start_utc,
            r.duration_h,
            r.ls_start_deg,
            r.min_elevation_deg,
            r.max_elevation_deg
        ),
        format!(
            "{} daylight period(s), {:.2} h of sun; insolation on a horizontal surface {:.0} Wh/m² (τ = {})",
            r.daylight_periods, r.daylight_hours, r.insolation_wh_m2, r.tau
        ),
    ]
}

/// `dem.tif` (float32, NaN where no data; Cloud-Optimized, as every layer a job
/// writes), `direct_sun.tif` (1 in direct sun, 0 not
/// — a cast shadow or a slope facing away —, 255 no data) and its preview
/// `direct_sun.png` with a world file.
fn terrain_shadow_files(dir: &Path, r: &TerrainShadowReport) -> Result<Vec<PathBuf>> {
    let dem_path = dir.join("dem.tif");
    let elevation = &super::bands::ELEVATION;
    super::write_with(&dem_path, |tmp| Ok(geotiff::write_cog_f32(&r.grid, &r.elevation_m.values, elevation, tmp)?))?;
    let shadow_path = dir.join("direct_sun.tif");
    let sun = &super::bands::DIRECT_SUN;
    super::write_with(&shadow_path, |tmp| {
        Ok(geotiff::write_cog_u8(&r.grid, &r.direct_sun.values, Some(255), sun, tmp)?)
    })?;
    let rgb: Vec<u8> = r.preview_rgb.values.iter().flatten().copied().collect();
    let mut files = vec![dem_path, shadow_path.clone()];
    files.extend(super::png::write_grid_png(&shadow_path.with_extension("png"), &r.grid, &rgb)?);
    Ok(files)
}

fn terrain_shadow_summary(r: &TerrainShadowReport) -> Vec<String> {
    let g = &r.grid;
    vec![
        format!(
            "{} × {} cells of {} m × {} m, relief {:.1} m, slopes up to {:.1}°",
            g.cols, g.rows, g.dx, g.dy, r.relief_m, r.max_slope_deg
        ),
        format!(
            "Sun at azimuth {:.2}°{}, elevation {:.2}° ({}): {:.1} % of the ground in direct sun, {:.1} % in cast shadow",
            r.sun.azimuth_deg,
            super::grid_azimuth_said(r.sun.azimuth_deg, r.sun.grid_azimuth_deg),
            r.sun.elevation_deg,
            r.sun.utc,
            100.0 * r.lit_fraction,
            100.0 * r.cast_shadow_fraction
        ),
    ]
}
