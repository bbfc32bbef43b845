//! The Sun at one instant as a report row: the `areo sun` CSV/JSON/text outputs and
//! the `SunTable` job share this.

use areo_ephemeris::{MarsTime, Site, SolarGeometry, format_utc};
use hifitime::Epoch;
use serde::Serialize;

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

    /// The row as CSV, columns as [`CSV_HEADER`].
    pub fn csv(&self) -> String {
        let opt = |x: Option<f64>, p: usize| x.map_or_else(String::new, |v| format!("{v:.p$}"));
        format!(
            "{},{:.8},{:.6},{:.6},{:.6},{:.8},{:.6},{},{},{}",
            self.utc,
            self.jd_tt,
            self.ls_deg,
            self.subsolar_lat_deg,
            self.subsolar_lon_east_deg,
            self.sun_distance_au,
            self.mtc_hours,
            opt(self.ltst_hours, 6),
            opt(self.azimuth_deg, 4),
            opt(self.elevation_deg, 4),
        )
    }
}
