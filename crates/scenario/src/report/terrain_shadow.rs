//! The terrain-shadow job's report.

use areo_terrain::geotiff::Grid;
use serde::Serialize;

use super::Raster;

/// A map lit by the Sun at one instant: the Sun, the light and relief figures, and the
/// rasters its files show.
#[derive(Debug, Clone, Serialize)]
pub struct TerrainShadowReport {
    /// Local solar time at the site, hours (true solar time on Mars).
    pub ltst_hours: f64,
    /// The Sun at the site.
    pub sun: ShadowSun,
    /// The map's grid: size, cell, corner and projection.
    pub grid: Grid,
    /// Cells of the map.
    pub cells: usize,
    /// Highest minus lowest elevation, m.
    pub relief_m: f64,
    /// The steepest slope, degrees.
    pub max_slope_deg: f64,
    /// The mean slope over cells with one, degrees.
    pub mean_slope_deg: f64,
    /// Fraction of cells with data in direct sun (neither in a cast shadow nor on a
    /// slope facing away from the Sun).
    pub lit_fraction: f64,
    /// Fraction of cells with data in a shadow cast by other terrain.
    pub cast_shadow_fraction: f64,
    /// Elevations, m (NaN where the map has no data).
    pub elevation_m: Raster<f32>,
    /// Direct sun: 1 lit, 0 in shadow (cast, or on a slope facing away), 255 no data.
    pub direct_sun: Raster<u8>,
    /// A hillshade with the shadows darkened, RGB bytes per cell.
    pub preview_rgb: Raster<[u8; 3]>,
}

/// The Sun's direction at the site at the job's instant.
#[derive(Debug, Clone, Serialize)]
pub struct ShadowSun {
    /// The instant, ISO 8601 UTC.
    pub utc: String,
    /// True azimuth, degrees clockwise from north.
    pub azimuth_deg: f64,
    /// Azimuth on the grid's axes, degrees clockwise from the grid's up (differs from
    /// the true azimuth on a polar map).
    pub grid_azimuth_deg: f64,
    /// Elevation above the horizontal, degrees.
    pub elevation_deg: f64,
}
