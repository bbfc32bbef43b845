//! The Sun-table job: the Sun over a site at a fixed step, with daylight and insolation.

use areo_ephemeris::events::daylight_intervals;
use areo_ephemeris::flux::Atmosphere;
use areo_ephemeris::{HorizonMask, Site, SolarGeometry, format_utc, parse_utc};
use hifitime::Unit;

use crate::error::Result;
use crate::format::SunTableJob;
use crate::progress::Progress;
use crate::report::{SunTableReport, SunTableRow, Sunrise};
use crate::sun::SunRow;

/// Computes the table, reporting each row to `progress`.
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
    let mut table = Vec::with_capacity(rows as usize);
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
        table.push(SunTableRow { sun: row, horizon_deg: horizon, sunlit, horizontal_flux_w_m2: flux });
        progress.advance(1);
    }
    progress.finish();

    let daylight = daylight_intervals(&site, &mask, start, end);
    let g0 = SolarGeometry::at(start);
    // A daylight period that starts at the table's first instant is not a sunrise.
    let first_sunrise = daylight.iter().find(|(a, _)| *a > start).map(|(rise, _)| Sunrise {
        utc: format_utc(*rise),
        ltst_hours: SolarGeometry::at(*rise).ltst_hours(site.lon_east_deg()),
    });
    Ok(SunTableReport {
        lat_deg: site.lat_deg(),
        lon_east_deg: site.lon_east_deg(),
        start_utc: format_utc(start),
        duration_h: job.duration_h,
        tau: job.tau,
        ls_start_deg: g0.ls_deg,
        ltst_start_hours: g0.ltst_hours(site.lon_east_deg()),
        min_elevation_deg: min_el,
        max_elevation_deg: max_el,
        daylight_hours: daylight.iter().map(|(a, b)| (*b - *a).to_seconds()).fold(0.0, |a, b| a + b) / 3600.0,
        daylight_periods: daylight.len(),
        insolation_wh_m2: insolation_j_m2 / 3600.0,
        first_sunrise,
        rows: table.len(),
        table,
    })
}
