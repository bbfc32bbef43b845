//! The Sun as report rows: at instants (`areo sun --time`, `--times-file`), over a
//! sol (`areo sun --sol`), and in the `SunTable` job.

use std::path::Path;

use areo_ephemeris::events::solar_day;
use areo_ephemeris::{HorizonMask, MarsTime, Site, SolarGeometry, format_utc, parse_utc};
use hifitime::Epoch;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::output::csv::Table;

/// CSV header of [`SunRow`], in this order (latitude planetocentric, longitude east;
/// the last three columns are at the site and empty without one).
pub const CSV_HEADER: &str = "utc,jd_tt,ls_deg,subsolar_lat_deg,subsolar_lon_east_deg,sun_distance_au,mtc_hours,ltst_hours,azimuth_deg,elevation_deg";

/// The Sun at one instant, optionally at a site.
#[derive(Debug, Clone, Serialize)]
pub struct SunRow {
    /// ISO 8601 UTC.
    pub utc: String,
    /// Julian date, TT.
    pub jd_tt: f64,
    /// Areocentric solar longitude, degrees.
    pub ls_deg: f64,
    /// Sub-solar latitude, planetocentric degrees.
    pub subsolar_lat_deg: f64,
    /// Sub-solar longitude, degrees east.
    pub subsolar_lon_east_deg: f64,
    /// Sun–Mars distance, AU.
    pub sun_distance_au: f64,
    /// Coordinated Mars Time, hours.
    pub mtc_hours: f64,
    /// Local true solar time at the site, hours.
    pub ltst_hours: Option<f64>,
    /// The Sun's azimuth at the site, degrees clockwise from north.
    pub azimuth_deg: Option<f64>,
    /// The Sun's elevation above the site's horizontal, degrees.
    pub elevation_deg: Option<f64>,
}

impl SunRow {
    /// The row for `epoch`, at `site` if given.
    pub fn at(epoch: Epoch, site: Option<&Site>) -> SunRow {
        let mt = MarsTime::from_epoch(epoch);
        let g = SolarGeometry::at_days_since_j2000(mt.days_since_j2000_tt);
        let local = site.map(|s| (g.ltst_hours(s.lon_east_deg()), g.state().at_site(s)));
        SunRow {
            utc: format_utc(epoch),
            jd_tt: mt.jd_tt,
            ls_deg: g.ls_deg,
            subsolar_lat_deg: g.subsolar_lat_planetocentric_deg,
            subsolar_lon_east_deg: g.subsolar_lon_east_deg,
            sun_distance_au: g.distance_au,
            mtc_hours: mt.mtc_hours,
            ltst_hours: local.map(|l| l.0),
            azimuth_deg: local.map(|l| l.1.azimuth_deg),
            elevation_deg: local.map(|l| l.1.elevation_deg),
        }
    }

    /// The row's CSV fields, columns as [`CSV_HEADER`] (fixed decimals: 8 for dates
    /// and distances, 6 for angles and hours, 4 for the local direction).
    pub fn csv_fields(&self) -> Vec<String> {
        let opt = |x: Option<f64>, p: usize| x.map_or_else(String::new, |v| format!("{v:.p$}"));
        vec![
            self.utc.clone(),
            format!("{:.8}", self.jd_tt),
            format!("{:.6}", self.ls_deg),
            format!("{:.6}", self.subsolar_lat_deg),
            format!("{:.6}", self.subsolar_lon_east_deg),
            format!("{:.8}", self.sun_distance_au),
            format!("{:.6}", self.mtc_hours),
            opt(self.ltst_hours, 6),
            opt(self.azimuth_deg, 4),
            opt(self.elevation_deg, 4),
        ]
    }
}

/// Where the instants of `areo sun` come from.
#[derive(Debug, Clone, Copy)]
pub enum Instants<'a> {
    /// One ISO 8601 UTC instant.
    One(&'a str),
    /// A file of instants, one per line; blank lines and `#` comments are skipped.
    File(&'a Path),
}

/// A site given as planetocentric latitude and east longitude, degrees.
fn site(lat_lon: Option<(f64, f64)>) -> Result<Option<Site>> {
    Ok(match lat_lon {
        Some((lat, lon)) => Some(Site::new(lat, lon)?),
        None => None,
    })
}

/// The Sun at each instant, at the site if given. A bad instant in a file is an
/// error naming the file and its line.
pub fn rows(instants: Instants<'_>, lat_lon: Option<(f64, f64)>) -> Result<Vec<SunRow>> {
    let site = site(lat_lon)?;
    match instants {
        Instants::One(t) => Ok(vec![SunRow::at(parse_utc(t)?, site.as_ref())]),
        Instants::File(path) => {
            let text =
                std::fs::read_to_string(path).map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
            let mut rows = Vec::new();
            for (i, line) in text.lines().enumerate() {
                let t = line.trim();
                if t.is_empty() || t.starts_with('#') {
                    continue;
                }
                let epoch = parse_utc(t).map_err(|e| Error::Syntax {
                    path: path.to_path_buf(),
                    line: i + 1,
                    col: 1 + line.len() - line.trim_start().len(),
                    message: e.to_string(),
                })?;
                rows.push(SunRow::at(epoch, site.as_ref()));
            }
            Ok(rows)
        }
    }
}

/// Rows as a CSV table with the [`CSV_HEADER`] columns.
pub fn csv_table(rows: &[SunRow]) -> Table {
    let mut table = Table::new(CSV_HEADER.split(','));
    for r in rows {
        table.push(r.csv_fields());
    }
    table
}

/// Sunrise, noon and sunset of one sol at a site (flat horizon).
#[derive(Debug, Clone, Serialize)]
pub struct SolEvents {
    /// The local sol number (Mars Sol Date in local mean time).
    pub sol: i64,
    /// Site latitude, planetocentric degrees.
    #[serde(skip)]
    pub lat_deg: f64,
    /// Site longitude, degrees east.
    #[serde(skip)]
    pub lon_east_deg: f64,
    /// Sunrise, ISO 8601 UTC; `None` in polar day or night.
    pub sunrise_utc: Option<String>,
    /// Local solar noon, ISO 8601 UTC.
    pub noon_utc: String,
    /// Sunset, ISO 8601 UTC; `None` in polar day or night.
    pub sunset_utc: Option<String>,
    /// The Sun's elevation at noon, degrees.
    pub noon_elevation_deg: f64,
    /// Hours of sun over the sol.
    pub daylight_hours: f64,
}

impl SolEvents {
    /// The sol's CSV table (one row).
    pub fn csv_table(&self) -> Table {
        let mut table =
            Table::new(["sol", "sunrise_utc", "noon_utc", "sunset_utc", "noon_elevation_deg", "daylight_hours"]);
        let none = || "none".to_string();
        table.push(vec![
            self.sol.to_string(),
            self.sunrise_utc.clone().unwrap_or_else(none),
            self.noon_utc.clone(),
            self.sunset_utc.clone().unwrap_or_else(none),
            format!("{:.4}", self.noon_elevation_deg),
            format!("{:.4}", self.daylight_hours),
        ]);
        table
    }
}

/// Sunrise, noon and sunset of local sol `sol` at (`lat_deg`, `lon_east_deg`).
pub fn sol_events(sol: i64, lat_deg: f64, lon_east_deg: f64) -> Result<SolEvents> {
    let site = Site::new(lat_deg, lon_east_deg)?;
    let day = solar_day(sol, &site, &HorizonMask::flat())?;
    Ok(SolEvents {
        sol,
        lat_deg: site.lat_deg(),
        lon_east_deg: site.lon_east_deg(),
        sunrise_utc: day.sunrise.map(format_utc),
        noon_utc: format_utc(day.noon),
        sunset_utc: day.sunset.map(format_utc),
        noon_elevation_deg: day.noon_elevation_deg,
        daylight_hours: day.daylight_s() / 3600.0,
    })
}
