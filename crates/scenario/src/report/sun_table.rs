//! The Sun-table job's report.

use serde::Serialize;

use crate::sun::SunRow;

/// The Sun over a site at a fixed step, with daylight and insolation.
#[derive(Debug, Clone, Serialize)]
pub struct SunTableReport {
    /// The site's planetocentric latitude, degrees.
    pub lat_deg: f64,
    /// The site's east longitude, degrees.
    pub lon_east_deg: f64,
    /// The table's first instant, ISO 8601 UTC.
    pub start_utc: String,
    /// How long the table covers, hours.
    pub duration_h: f64,
    /// The optical depth used for the flux.
    pub tau: f64,
    /// Areocentric solar longitude at the start, degrees.
    pub ls_start_deg: f64,
    /// Local true solar time at the start, hours.
    pub ltst_start_hours: f64,
    /// The Sun's lowest elevation over the table, degrees.
    pub min_elevation_deg: f64,
    /// The Sun's highest elevation over the table, degrees.
    pub max_elevation_deg: f64,
    /// Hours of sun above the horizon mask.
    pub daylight_hours: f64,
    /// Daylight periods (a period cut by the table's ends counts).
    pub daylight_periods: usize,
    /// Insolation on a horizontal surface, Wh/m² (trapezoidal over the rows).
    pub insolation_wh_m2: f64,
    /// The first sunrise after the start, if the table holds one.
    pub first_sunrise: Option<Sunrise>,
    /// How many rows the table has.
    pub rows: usize,
    /// The table: one row per step.
    pub table: Vec<SunTableRow>,
}

/// A sunrise.
#[derive(Debug, Clone, Serialize)]
pub struct Sunrise {
    /// ISO 8601 UTC.
    pub utc: String,
    /// Local true solar time, hours.
    pub ltst_hours: f64,
}

/// One row of the Sun table: the Sun at the instant and what the horizon mask makes
/// of it.
#[derive(Debug, Clone, Serialize)]
pub struct SunTableRow {
    /// The Sun at the instant, at the site.
    #[serde(flatten)]
    pub sun: SunRow,
    /// The horizon mask's elevation in the Sun's direction, degrees.
    pub horizon_deg: f64,
    /// Whether the Sun is above the mask.
    pub sunlit: bool,
    /// Direct flux on a horizontal surface, W/m² (0 behind the mask).
    pub horizontal_flux_w_m2: f64,
}
