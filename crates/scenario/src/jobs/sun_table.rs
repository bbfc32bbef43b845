//! The Sun-table job: the Sun over a site at a fixed step, with daylight and insolation.

use areo_ephemeris::events::daylight_intervals;
use areo_ephemeris::flux::Atmosphere;
use areo_ephemeris::{HorizonMask, Site, SolarGeometry, format_utc, parse_utc};
use hifitime::Unit;

use crate::error::Result;
use crate::format::SunTableJob;
use crate::jobs::RunOptions;
use crate::outcome::Outcome;
use crate::output::csv::Table;
use crate::progress::Progress;
use crate::sun::{CSV_HEADER, SunRow};

/// What a Sun table found.
#[derive(Debug, Clone)]
pub(crate) struct SunTableReport {
    /// The site's latitude (planetocentric) and east longitude, degrees.
    pub site_deg: (f64, f64),
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
    /// The Sun's highest and lowest elevation over the table, degrees.
    pub elevation_range_deg: (f64, f64),
    /// Hours of sun above the horizon mask.
    pub daylight_hours: f64,
    /// Daylight periods (a period cut by the table's ends counts).
    pub daylight_periods: usize,
    /// Insolation on a horizontal surface, Wh/m² (trapezoidal over the rows).
    pub insolation_wh_m2: f64,
    /// The first sunrise after the start: UTC and LTST hours.
    pub first_sunrise: Option<(String, f64)>,
    /// The table: one row per step.
    pub table: Table,
}

impl SunTableReport {
    /// The report's facts and summary lines.
    pub(crate) fn outcome(&self) -> Outcome {
        let mut o = Outcome::default();
        o.count("rows", self.table.len() as u64);
        o.number("ls_start_deg", self.ls_start_deg);
        o.number("ltst_start_hours", self.ltst_start_hours);
        o.number("max_elevation_deg", self.elevation_range_deg.1);
        o.number("min_elevation_deg", self.elevation_range_deg.0);
        o.number("daylight_hours", self.daylight_hours);
        o.count("daylight_periods", self.daylight_periods as u64);
        o.number("insolation_wh_m2", self.insolation_wh_m2);
        if let Some((utc, ltst)) = &self.first_sunrise {
            o.text("first_sunrise_utc", utc.clone());
            o.number("first_sunrise_ltst_hours", *ltst);
        }
        o.summary.push(format!(
            "Sun over ({:.4}°, {:.4}°E) from {} for {:.2} h: Ls {:.2}°, elevation {:.2}°..{:.2}°",
            self.site_deg.0,
            self.site_deg.1,
            self.start_utc,
            self.duration_h,
            self.ls_start_deg,
            self.elevation_range_deg.0,
            self.elevation_range_deg.1
        ));
        o.summary.push(format!(
            "{} daylight period(s), {:.2} h of sun; insolation on a horizontal surface {:.0} Wh/m² (τ = {})",
            self.daylight_periods, self.daylight_hours, self.insolation_wh_m2, self.tau
        ));
        o
    }
}

/// Computes the table.
pub(crate) fn compute(job: &SunTableJob, progress: &dyn Progress) -> Result<SunTableReport> {
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

    progress.start(rows, "sun table");
    let mut table = Table::new(CSV_HEADER.split(',').chain(["horizon_deg", "sunlit", "horizontal_flux_w_m2"]));
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
        let mut fields = row.csv_fields();
        fields.extend([format!("{horizon:.4}"), u8::from(sunlit).to_string(), format!("{flux:.3}")]);
        table.push(fields);
        progress.advance(1);
    }
    progress.finish();

    let daylight = daylight_intervals(&site, &mask, start, end);
    let g0 = SolarGeometry::at(start);
    // A daylight period that starts at the table's first instant is not a sunrise.
    let first_sunrise = daylight
        .iter()
        .find(|(a, _)| *a > start)
        .map(|(rise, _)| (format_utc(*rise), SolarGeometry::at(*rise).ltst_hours(site.lon_east_deg())));
    Ok(SunTableReport {
        site_deg: (site.lat_deg(), site.lon_east_deg()),
        start_utc: format_utc(start),
        duration_h: job.duration_h,
        tau: job.tau,
        ls_start_deg: g0.ls_deg,
        ltst_start_hours: g0.ltst_hours(site.lon_east_deg()),
        elevation_range_deg: (min_el, max_el),
        daylight_hours: daylight.iter().map(|(a, b)| (*b - *a).to_seconds()).fold(0.0, |a, b| a + b) / 3600.0,
        daylight_periods: daylight.len(),
        insolation_wh_m2: insolation_j_m2 / 3600.0,
        first_sunrise,
        table,
    })
}

/// Runs the job: the report's facts, and `sun.csv` in the output directory.
pub(crate) fn run(job: &SunTableJob, opts: RunOptions<'_>) -> Result<Outcome> {
    let report = compute(job, opts.progress)?;
    let mut o = report.outcome();
    if let Some(dir) = opts.out_dir {
        let path = dir.join("sun.csv");
        report.table.write(&path)?;
        o.files.push(path);
    }
    Ok(o)
}
