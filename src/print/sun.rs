//! `areo sun`: the Sun at instants, or one sol's events.

use areo_scenario::Error;
use areo_scenario::sun::{SolEvents, SunRow};

use crate::Format;

/// Rows of the Sun at instants.
pub(crate) fn rows(rows: &[SunRow], format: Format) -> Result<String, Error> {
    Ok(match format {
        Format::Csv => super::csv(&areo_scenario::sun::csv_table(rows))?,
        Format::Json => super::json(&rows)? + "\n",
        Format::Text => {
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
    })
}

/// Sunrise, noon and sunset of a sol.
pub(crate) fn sol(day: &SolEvents, format: Format) -> Result<String, Error> {
    let t = |e: &Option<String>| e.clone().unwrap_or_else(|| "none".to_string());
    Ok(match format {
        Format::Csv => super::csv(&day.csv_table())?,
        Format::Json => super::json(day)? + "\n",
        Format::Text => format!(
            "sol {} at ({:.4}°, {:.4}°E)\n  sunrise  {}\n  noon     {}  (Sun {:.2}° high)\n  sunset   {}\n  daylight {:.3} h\n",
            day.sol,
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
