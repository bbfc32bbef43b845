//! `areo sun`: the Sun at instants, or one sol's events.

use areo_scenario::Error;
use areo_scenario::sun::{DayEvents, SkyRow, SolEvents, SunRow, SunRows};

use crate::Format;

/// Rows of the Sun at instants, over any body.
pub(crate) fn rows(rows: &SunRows, format: Format) -> Result<String, Error> {
    Ok(match (format, rows) {
        (Format::Csv, _) => super::csv(&rows.csv_table())?,
        (Format::Json, SunRows::Mars(r)) => super::json(r)? + "\n",
        (Format::Json, SunRows::Sky(_, r)) => super::json(r)? + "\n",
        (Format::Text, SunRows::Mars(r)) => mars_text(r),
        (Format::Text, SunRows::Sky(_, r)) => sky_text(r),
    })
}

/// The Sun over the Moon or the Earth, as text.
fn sky_text(rows: &[SkyRow]) -> String {
    let mut s = String::new();
    for r in rows {
        s += &format!("{}\n", r.utc);
        s += &format!("  sub-solar latitude {:10.5}°\n", r.subsolar_lat_deg);
        s += &format!("  sub-solar longitude{:10.5}° E\n", r.subsolar_lon_east_deg);
        s += &format!("  Sun distance       {:10.6} AU\n", r.sun_distance_au);
        if let (Some(l), Some(a), Some(e)) = (r.local_solar_time_hours, r.azimuth_deg, r.elevation_deg) {
            s += &format!("  local solar time   {l:10.5} h\n");
            s += &format!("  Sun azimuth        {a:10.4}° (from north, clockwise)\n");
            s += &format!("  Sun elevation      {e:10.4}° (geometric, topocentric)\n");
        }
        if let Some(e) = r.refracted_elevation_deg {
            s += &format!("  refracted          {e:10.4}° (1010 hPa, 10 °C)\n");
        }
        if let (Some(a), Some(e)) = (r.earth_azimuth_deg, r.earth_elevation_deg) {
            s += &format!("  Earth azimuth      {a:10.4}°\n");
            s += &format!("  Earth elevation    {e:10.4}°\n");
        }
        if let (Some(d), Some(la), Some(lo)) = (r.earth_distance_km, r.sub_earth_lat_deg, r.sub_earth_lon_east_deg) {
            s += &format!("  Earth distance     {d:10.1} km\n");
            s += &format!("  libration          {la:+.4}° lat, {lo:+.4}° lon (sub-Earth point)\n");
        }
    }
    s
}

/// Mars24 rows as text.
fn mars_text(rows: &[SunRow]) -> String {
    {
        {
            let mut s = String::new();
            for r in rows {
                s += &format!("{}\n", r.utc);
                s += &format!("  Ls                 {:10.5}°\n", r.ls_deg);
                s += &format!("  sub-solar latitude {:10.5}° (planetocentric)\n", r.subsolar_lat_deg);
                s += &format!("  sub-solar longitude{:10.5}° E\n", r.subsolar_lon_east_deg);
                s += &format!("  Sun distance       {:10.6} AU\n", r.sun_distance_au);
                s += &format!("  MTC                {:10.5} h\n", r.mtc_hours);
                if let (Some(l), Some(a), Some(e)) = (r.ltst_hours, r.azimuth_deg, r.elevation_deg) {
                    s += &format!("  LTST               {l:10.5} h\n");
                    s += &format!("  Sun azimuth        {a:10.4}° (from north, clockwise)\n");
                    s += &format!("  Sun elevation      {e:10.4}°\n");
                }
            }
            s
        }
    }
}

/// Sunrise, noon and sunset of a sol.
pub(crate) fn sol(day: &SolEvents, format: Format) -> Result<String, Error> {
    let t = |e: &Option<String>| e.clone().unwrap_or_else(|| "none".to_string());
    Ok(match format {
        Format::Csv => super::csv(&day.csv_table())?,
        Format::Json => super::json(day)? + "\n",
        Format::Text => format!(
            "sol {}{} at ({:.4}°, {:.4}°E)\n  sunrise  {}\n  noon     {}  (Sun {:.2}° high)\n  sunset   {}\n  daylight {:.3} h\n",
            day.sol,
            match (day.mission_sol, &day.landing_utc) {
                (Some(n), Some(at)) => format!(" (mission sol {n} of the landing at {at})"),
                _ => String::new(),
            },
            day.lat_deg,
            day.lon_east_deg,
            t(&day.sunrise_utc),
            day.noon_utc,
            day.noon_elevation_deg,
            t(&day.sunset_utc),
            day.daylight_hours
        ),
    })
}

/// A solar day of the Moon or the Earth.
pub(crate) fn day(d: &DayEvents, format: Format) -> Result<String, Error> {
    Ok(match format {
        Format::Csv => super::csv(&d.csv_table())?,
        Format::Json => super::json(d)? + "\n",
        Format::Text => {
            let list = |v: &[String]| if v.is_empty() { "none".to_string() } else { v.join(", ") };
            let mut s = format!("{} from {} to {}\n", d.body, d.from_utc, d.to_utc);
            s += &format!("  sunrise  {}\n", list(&d.sunrise_utc));
            s += &format!("  noon     {}  (Sun {:.2}° high)\n", d.noon_utc, d.noon_elevation_deg);
            s += &format!("  sunset   {}\n", list(&d.sunset_utc));
            s += &format!("  daylight {:.3} h\n", d.daylight_hours);
            if let Some(h) = d.earth_up_hours {
                s += &format!("  Earth up {h:.3} h\n");
            }
            s
        }
    })
}
