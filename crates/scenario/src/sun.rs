//! The Sun as report rows: at instants (`areo sun --time`, `--times-file`), over a
//! sol (`areo sun --sol`), and in the `SunTable` job.

use std::path::Path;

use areo_ephemeris::events::solar_day;
use areo_ephemeris::terrestrial::refraction_deg;
use areo_ephemeris::{Body, EarthFrom, HorizonMask, MarsTime, Site, SolarGeometry, SunModel, format_utc, parse_utc};
use hifitime::Epoch;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::output::csv::Table;

/// CSV header of [`SunRow`], in this order (latitude planetocentric, longitude east;
/// the last three columns are at the site and empty without one).
pub(crate) const CSV_HEADER: &str = "utc,jd_tt,ls_deg,subsolar_lat_deg,subsolar_lon_east_deg,sun_distance_au,mtc_hours,ltst_hours,azimuth_deg,elevation_deg";

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
    pub(crate) fn csv_fields(&self) -> Vec<String> {
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

/// CSV header of [`SkyRow`] on the Moon (on the Earth without the `earth_` and
/// `sub_earth_` columns, with `refracted_elevation_deg`).
pub(crate) const MOON_CSV_HEADER: &str = "utc,jd_tt,subsolar_lat_deg,subsolar_lon_east_deg,sun_distance_au,local_solar_time_hours,azimuth_deg,elevation_deg,earth_azimuth_deg,earth_elevation_deg,earth_distance_km,sub_earth_lat_deg,sub_earth_lon_east_deg";

/// CSV header of [`SkyRow`] on the Earth.
pub(crate) const EARTH_CSV_HEADER: &str = "utc,jd_tt,subsolar_lat_deg,subsolar_lon_east_deg,sun_distance_au,local_solar_time_hours,azimuth_deg,elevation_deg,refracted_elevation_deg";

/// Standard air for [`SkyRow::refracted_elevation_deg`]: 1010 hPa, 10 °C.
const STANDARD_AIR: (f64, f64) = (1010.0, 10.0);

/// The Sun (and on the Moon the Earth) at one instant over the Moon or the Earth,
/// optionally at a site. Directions at a site are topocentric and geometric.
#[derive(Debug, Clone, Serialize)]
pub struct SkyRow {
    /// ISO 8601 UTC.
    pub utc: String,
    /// Julian date, TT.
    pub jd_tt: f64,
    /// Sub-solar latitude (selenographic or geocentric), degrees.
    pub subsolar_lat_deg: f64,
    /// Sub-solar longitude, degrees east [0, 360).
    pub subsolar_lon_east_deg: f64,
    /// Sun–body distance, AU.
    pub sun_distance_au: f64,
    /// Local solar time at the site, hours (a lunar hour is 1/24 of a synodic month).
    pub local_solar_time_hours: Option<f64>,
    /// The Sun's azimuth at the site, degrees clockwise from north.
    pub azimuth_deg: Option<f64>,
    /// The Sun's elevation above the site's horizontal, degrees (geometric).
    pub elevation_deg: Option<f64>,
    /// On the Earth: the elevation with standard refraction (1010 hPa, 10 °C).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refracted_elevation_deg: Option<f64>,
    /// On the Moon: the Earth's azimuth at the site, degrees.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub earth_azimuth_deg: Option<f64>,
    /// On the Moon: the Earth's elevation at the site, degrees.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub earth_elevation_deg: Option<f64>,
    /// On the Moon: Earth–Moon centre distance, km.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub earth_distance_km: Option<f64>,
    /// On the Moon: the sub-Earth point's latitude (libration in latitude), degrees.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sub_earth_lat_deg: Option<f64>,
    /// On the Moon: the sub-Earth point's longitude (libration in longitude), degrees east.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sub_earth_lon_east_deg: Option<f64>,
}

impl SkyRow {
    /// The row for `epoch` over `body` (the Moon or the Earth), at `site` if given.
    pub fn at(body: Body, epoch: Epoch, site: Option<&Site>) -> SkyRow {
        let sun = body.sun(epoch);
        let (sub_lat, sub_lon) = sun.subsolar_deg();
        let local = site.map(|s| (sun.local_solar_time_hours(s.lon_east_deg()), sun.at_site(s)));
        let earth = body.earth(epoch);
        let earth_local = earth.zip(site).map(|(e, s)| e.at_site(s));
        let on_earth = body == Body::Earth;
        SkyRow {
            utc: format_utc(epoch),
            jd_tt: epoch.to_jde_tt_days(),
            subsolar_lat_deg: sub_lat,
            subsolar_lon_east_deg: sub_lon,
            sun_distance_au: sun.distance_au,
            local_solar_time_hours: local.map(|l| l.0),
            azimuth_deg: local.map(|l| l.1.azimuth_deg),
            elevation_deg: local.map(|l| l.1.elevation_deg),
            refracted_elevation_deg: local
                .filter(|_| on_earth)
                .map(|l| l.1.elevation_deg + refraction_deg(l.1.elevation_deg, STANDARD_AIR.0, STANDARD_AIR.1)),
            earth_azimuth_deg: earth_local.map(|e| e.0),
            earth_elevation_deg: earth_local.map(|e| e.1),
            earth_distance_km: earth.map(|e| e.distance_km),
            sub_earth_lat_deg: earth.map(|e| e.sub_point_deg().0),
            sub_earth_lon_east_deg: earth.map(|e| e.sub_point_deg().1),
        }
    }

    /// The row's CSV fields for `body`'s header.
    pub(crate) fn csv_fields(&self, body: Body) -> Vec<String> {
        let opt = |x: Option<f64>, p: usize| x.map_or_else(String::new, |v| format!("{v:.p$}"));
        let mut out = vec![
            self.utc.clone(),
            format!("{:.8}", self.jd_tt),
            format!("{:.6}", self.subsolar_lat_deg),
            format!("{:.6}", self.subsolar_lon_east_deg),
            format!("{:.8}", self.sun_distance_au),
            opt(self.local_solar_time_hours, 6),
            opt(self.azimuth_deg, 4),
            opt(self.elevation_deg, 4),
        ];
        if body == Body::Earth {
            out.push(opt(self.refracted_elevation_deg, 4));
        } else {
            out.extend([
                opt(self.earth_azimuth_deg, 4),
                opt(self.earth_elevation_deg, 4),
                opt(self.earth_distance_km, 1),
                opt(self.sub_earth_lat_deg, 4),
                opt(self.sub_earth_lon_east_deg, 4),
            ]);
        }
        out
    }
}

/// Rows of `areo sun`: Mars24's on Mars, [`SkyRow`]s on the Moon and the Earth.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum SunRows {
    /// Mars.
    Mars(Vec<SunRow>),
    /// The Moon or the Earth.
    Sky(#[serde(skip)] Body, Vec<SkyRow>),
}

impl SunRows {
    /// The rows as a CSV table with the body's header.
    pub fn csv_table(&self) -> Table {
        match self {
            SunRows::Mars(rows) => csv_table(rows),
            SunRows::Sky(body, rows) => {
                let header = if *body == Body::Earth { EARTH_CSV_HEADER } else { MOON_CSV_HEADER };
                let mut table = Table::new(header.split(','));
                for r in rows {
                    table.push(r.csv_fields(*body));
                }
                table
            }
        }
    }
}

/// Where the instants of `areo sun` come from.
#[derive(Debug, Clone, Copy)]
pub enum Instants<'a> {
    /// One ISO 8601 UTC instant.
    One(&'a str),
    /// A file of instants, one per line; blank lines and `#` comments are skipped. The
    /// path `-` is standard input.
    File(&'a Path),
    /// Every `step` from `from` to `to` (both UTC, `to` included when on a step).
    Range {
        /// The first instant.
        from: &'a str,
        /// The last instant.
        to: &'a str,
        /// The step, e.g. `10min`, `1h`, `30s`, `1sol`, `1d`.
        step: &'a str,
    },
}

/// The most rows a `--from/--to/--step` range may give.
const MAX_RANGE_ROWS: f64 = 1e6;

/// A duration written with its unit (`30s`, `10min`, `1.5h`, `1d`, `1sol`), s.
pub fn parse_step(text: &str) -> Result<f64> {
    let t = text.trim();
    let split = t.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let scale = match unit {
        "s" => 1.0,
        "min" => 60.0,
        "h" => 3600.0,
        "d" => 86_400.0,
        "sol" => areo_ephemeris::SOL_S,
        _ => {
            return Err(Error::usage(
                format!("--step {text}"),
                "give a number and a unit: s, min, h, d or sol (e.g. 10min)",
            ));
        }
    };
    match number.trim().parse::<f64>() {
        Ok(n) if n > 0.0 && n.is_finite() => Ok(n * scale),
        _ => Err(Error::usage(format!("--step {text}"), "the step must be a positive number with its unit")),
    }
}

/// A site on `body` given as latitude and east longitude, degrees.
fn site(body: Body, lat_lon: Option<(f64, f64)>) -> Result<Option<Site>> {
    Ok(match lat_lon {
        Some((lat, lon)) => Some(Site::on(body, lat, lon)?),
        None => None,
    })
}

/// The Sun over `body` at each instant, at the site if given. A bad instant in a file
/// is an error naming the file and its line.
pub fn body_rows(body: Body, instants: Instants<'_>, lat_lon: Option<(f64, f64)>) -> Result<SunRows> {
    body_rows_within(body, instants, lat_lon, crate::budget::Budget::for_this_machine())
}

/// Memory a row of the Sun table takes until it is printed, bytes: the row and its
/// text, CSV or JSON (measured peaks: a million Mars rows 394 MB printed as text and
/// 538 MB as JSON; 100 000 Moon rows with the Earth 76 MB and 88 MB).
pub const ROW_BYTES: u64 = 900;

/// [`body_rows`] under `budget`: the instants are read and counted first, and a table
/// whose rows would not fit in the memory budget is refused before any is computed.
pub fn body_rows_within(
    body: Body,
    instants: Instants<'_>,
    lat_lon: Option<(f64, f64)>,
    budget: crate::budget::Budget,
) -> Result<SunRows> {
    let site = site(body, lat_lon)?;
    if let Instants::File(path) = &instants
        && let Ok(meta) = std::fs::metadata(path)
        && meta.is_file()
    {
        // Reading holds the text and an instant (16 bytes) per line of at least 11.
        budget.check(&crate::budget::Estimate {
            what: format!("reading the {:.1} MB of instants in {}", meta.len() as f64 / 1e6, path.display()),
            memory_bytes: meta.len() + meta.len() / 11 * 16,
            work_steps: meta.len(),
            work_unit: "bytes",
        })?;
    }
    let epochs = epochs(instants)?;
    budget.check(&crate::budget::Estimate {
        what: format!("a Sun table of {} instants", epochs.len()),
        memory_bytes: epochs.len() as u64 * ROW_BYTES,
        work_steps: epochs.len() as u64,
        work_unit: "instants",
    })?;
    Ok(match body {
        Body::Mars => SunRows::Mars(epochs.into_iter().map(|t| SunRow::at(t, site.as_ref())).collect()),
        _ => SunRows::Sky(body, epochs.into_iter().map(|t| SkyRow::at(body, t, site.as_ref())).collect()),
    })
}

/// The Sun over Mars at each instant, at the site if given (see [`body_rows`]).
pub fn rows(instants: Instants<'_>, lat_lon: Option<(f64, f64)>) -> Result<Vec<SunRow>> {
    let site = site(Body::Mars, lat_lon)?;
    Ok(epochs(instants)?.into_iter().map(|t| SunRow::at(t, site.as_ref())).collect())
}

/// The instants, in order.
fn epochs(instants: Instants<'_>) -> Result<Vec<Epoch>> {
    match instants {
        Instants::One(t) => Ok(vec![parse_utc(t)?]),
        Instants::Range { from, to, step } => {
            let (t0, t1, dt) = (parse_utc(from)?, parse_utc(to)?, parse_step(step)?);
            let span = (t1 - t0).to_seconds();
            if span < 0.0 {
                return Err(Error::usage(format!("--from {from} --to {to}"), "--to must not be before --from"));
            }
            let n = (span / dt + 1e-9).floor() + 1.0;
            if n > MAX_RANGE_ROWS {
                return Err(Error::usage(
                    format!("--from {from} --to {to} --step {step}"),
                    format!("{n:.0} rows; at most {MAX_RANGE_ROWS:.0} (a longer step or a shorter span)"),
                ));
            }
            Ok((0..n as usize).map(|k| t0 + hifitime::Duration::from_seconds(k as f64 * dt)).collect())
        }
        Instants::File(path) => {
            let text = if path == Path::new("-") {
                areo_terrain::input::read_stream(std::io::stdin(), areo_terrain::input::TEXT_LIMIT)
            } else {
                crate::read_text(path)
            }
            .map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
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
                rows.push(epoch);
            }
            Ok(rows)
        }
    }
}

/// Rows as a CSV table (UTC, Julian date, Mars time and the Sun's position columns).
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
    /// The mission sol, counted from the landing's local sol (0), when a landing was
    /// given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mission_sol: Option<i64>,
    /// The landing, ISO 8601 UTC, when given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub landing_utc: Option<String>,
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
    /// The CSV table of the sol (one row; `mission_sol` empty without a landing).
    pub fn csv_table(&self) -> Table {
        let mut table = Table::new([
            "sol",
            "mission_sol",
            "sunrise_utc",
            "noon_utc",
            "sunset_utc",
            "noon_elevation_deg",
            "daylight_hours",
        ]);
        let none = || "none".to_string();
        table.push(vec![
            self.sol.to_string(),
            self.mission_sol.map_or_else(String::new, |s| s.to_string()),
            self.sunrise_utc.clone().unwrap_or_else(none),
            self.noon_utc.clone(),
            self.sunset_utc.clone().unwrap_or_else(none),
            format!("{:.4}", self.noon_elevation_deg),
            format!("{:.4}", self.daylight_hours),
        ]);
        table
    }
}

/// The Sun over one solar day of the Moon or the Earth at a site (flat horizon): every
/// sunrise and sunset, the Sun's highest point, hours of daylight, and on the Moon the
/// hours the Earth is up.
#[derive(Debug, Clone, Serialize)]
pub struct DayEvents {
    /// The body.
    pub body: String,
    /// The window's start, ISO 8601 UTC (the given date at 00:00 UTC).
    pub from_utc: String,
    /// The window's end: one solar day of the body later.
    pub to_utc: String,
    /// Sunrises in the window, ISO 8601 UTC (none in polar day or night).
    pub sunrise_utc: Vec<String>,
    /// Sunsets in the window.
    pub sunset_utc: Vec<String>,
    /// The Sun's highest point, ISO 8601 UTC.
    pub noon_utc: String,
    /// Its elevation, degrees (geometric).
    pub noon_elevation_deg: f64,
    /// Hours with the Sun's centre above the horizontal.
    pub daylight_hours: f64,
    /// On the Moon: hours with the Earth's centre above the horizontal.
    pub earth_up_hours: Option<f64>,
}

impl DayEvents {
    /// The events as a CSV table: one row per event (`event`, `utc`).
    pub fn csv_table(&self) -> Table {
        let mut table = Table::new(["event", "utc", "value"]);
        for t in &self.sunrise_utc {
            table.push(vec!["sunrise".into(), t.clone(), String::new()]);
        }
        for t in &self.sunset_utc {
            table.push(vec!["sunset".into(), t.clone(), String::new()]);
        }
        table.push(vec!["noon".into(), self.noon_utc.clone(), format!("{:.4}", self.noon_elevation_deg)]);
        table.push(vec!["daylight_hours".into(), self.from_utc.clone(), format!("{:.4}", self.daylight_hours)]);
        if let Some(h) = self.earth_up_hours {
            table.push(vec!["earth_up_hours".into(), self.from_utc.clone(), format!("{h:.4}")]);
        }
        table
    }
}

/// The Sun over the solar day of `body` (the Moon or the Earth) that starts at
/// `date` (YYYY-MM-DD, 00:00 UTC) at (`lat_deg`, `lon_east_deg`).
pub fn day_events(body: Body, date: &str, lat_deg: f64, lon_east_deg: f64) -> Result<DayEvents> {
    use areo_ephemeris::events::{culmination, daylight_intervals, earth_visible_intervals};
    let start = parse_utc(&format!("{}T00:00:00Z", date.trim()))?;
    let site = Site::on(body, lat_deg, lon_east_deg)?;
    let end = start + hifitime::Duration::from_seconds(body.solar_day_s());
    // The day must end inside the ephemeris' validity too.
    parse_utc(&format_utc(end))
        .map_err(|e| Error::usage(format!("--day {date}"), format!("the solar day runs past the ephemeris: {e}")))?;
    let flat = HorizonMask::flat();
    let days = daylight_intervals(&site, &flat, start, end);
    let hours = |iv: &[(Epoch, Epoch)]| iv.iter().map(|(a, b)| (*b - *a).to_seconds()).fold(0.0, |a, b| a + b) / 3600.0;
    let (noon, el) = culmination(&site, start, end);
    Ok(DayEvents {
        body: body.name().into(),
        from_utc: format_utc(start),
        to_utc: format_utc(end),
        // An interval open at the window's edge is no sunrise or sunset (the Julian-date
        // round trip moves the edge by microseconds).
        sunrise_utc: days
            .iter()
            .filter(|(a, _)| (*a - start).to_seconds() > 1.0)
            .map(|(a, _)| format_utc(*a))
            .collect(),
        sunset_utc: days.iter().filter(|(_, b)| (end - *b).to_seconds() > 1.0).map(|(_, b)| format_utc(*b)).collect(),
        noon_utc: format_utc(noon),
        noon_elevation_deg: el,
        daylight_hours: hours(&days),
        earth_up_hours: (body == Body::Moon).then(|| hours(&earth_visible_intervals(&site, &flat, start, end))),
    })
}

/// The sol events of mission sol `mission_sol` of a landing at `landing` (UTC, any
/// form [`parse_utc`] reads) at the site: sol 0 is the local sol the landing fell in,
/// as missions count (Curiosity landed in local sol 49269 at Gale, its sol 0).
pub fn mission_sol_events(landing: &str, mission_sol: i64, lat_deg: f64, lon_east_deg: f64) -> Result<SolEvents> {
    let site = Site::new(lat_deg, lon_east_deg)?;
    let at = parse_utc(landing)?;
    let mut events = sol_events(areo_ephemeris::local_sol(at, &site) + mission_sol, lat_deg, lon_east_deg)?;
    events.mission_sol = Some(mission_sol);
    events.landing_utc = Some(format_utc(at));
    Ok(events)
}

/// Sunrise, noon and sunset of local sol `sol` (Mars Sol Date in local mean time) at a
/// site, flat horizon.
pub fn sol_events(sol: i64, lat_deg: f64, lon_east_deg: f64) -> Result<SolEvents> {
    let site = Site::new(lat_deg, lon_east_deg)?;
    let day = solar_day(sol, &site, &HorizonMask::flat())?;
    Ok(SolEvents {
        sol,
        mission_sol: None,
        landing_utc: None,
        lat_deg: site.lat_deg(),
        lon_east_deg: site.lon_east_deg(),
        sunrise_utc: day.sunrise.map(format_utc),
        noon_utc: format_utc(day.noon),
        sunset_utc: day.sunset.map(format_utc),
        noon_elevation_deg: day.noon_elevation_deg,
        daylight_hours: day.daylight_s() / 3600.0,
    })
}
