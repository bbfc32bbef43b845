//! Earth and Mars time scales: UTC, TT, Julian dates, Mars Sol Date, MTC, LMST, LTST.

use hifitime::{Epoch, TimeScale};

use crate::error::{Error, Result};
use crate::site::Site;
use crate::sun::SolarGeometry;

/// Julian date (TT) of the J2000 epoch.
pub(crate) const J2000_JD_TT: f64 = 2_451_545.0;
/// Length of the mean Mars solar day in Earth days (Mars24, 2018 constants).
pub(crate) const SOL_IN_DAYS: f64 = 1.027_491_251_7;

/// A mean Mars solar day (sol), s (areo-body's; the same 1.0274912517 Earth days).
pub use areo_body::SOL_S;
/// JD (TT) that Mars24 anchors the Mars Sol Date count to.
const MSD_ANCHOR_JD_TT: f64 = 2_451_549.5;
/// Mars Sol Date at the anchor, less the 2018 page's small correction.
const MSD_AT_ANCHOR: f64 = 44_796.0 - 0.000_962_6;

/// One instant expressed in the time scales Mars24 works with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarsTime {
    /// Julian date in UTC (A-2: milliseconds since 1970 / 86 400 000 + 2440587.5), days.
    pub jd_utc: f64,
    /// TT − UTC, seconds: leap seconds + 32.184 s.
    pub tt_minus_utc_s: f64,
    /// Julian date in TT, days.
    pub jd_tt: f64,
    /// Days of TT since J2000.
    pub days_since_j2000_tt: f64,
    /// Mars Sol Date (C-2), sols.
    pub msd: f64,
    /// Coordinated Mars Time = mean solar time at the prime meridian (C-2), hours [0, 24).
    pub mtc_hours: f64,
}

impl MarsTime {
    /// The Mars24 time quantities of `epoch`.
    pub fn from_epoch(epoch: Epoch) -> MarsTime {
        let jd_utc = epoch.to_jde_utc_days();
        let tt_minus_utc_s = (epoch.to_tt_duration() - epoch.to_utc_duration()).to_seconds();
        let jd_tt = epoch.to_jde_tt_days();
        MarsTime::from_jd_tt_with_utc(jd_tt, jd_utc, tt_minus_utc_s)
    }

    /// The Mars24 quantities from a TT Julian date alone (`jd_utc` is then derived with
    /// the current TT − UTC unknown, so it is set equal to the TT date less 69.184 s; use
    /// [`MarsTime::from_epoch`] when UTC matters).
    pub fn from_jd_tt(jd_tt: f64) -> MarsTime {
        MarsTime::from_jd_tt_with_utc(jd_tt, jd_tt - 69.184 / 86_400.0, 69.184)
    }

    fn from_jd_tt_with_utc(jd_tt: f64, jd_utc: f64, tt_minus_utc_s: f64) -> MarsTime {
        let msd = msd_from_jd_tt(jd_tt);
        MarsTime {
            jd_utc,
            tt_minus_utc_s,
            jd_tt,
            days_since_j2000_tt: jd_tt - J2000_JD_TT,
            msd,
            mtc_hours: (24.0 * msd).rem_euclid(24.0),
        }
    }

    /// Local mean solar time at east longitude `lon_east_deg` (C-3), hours [0, 24).
    pub fn lmst_hours(&self, lon_east_deg: f64) -> f64 {
        (self.mtc_hours + lon_east_deg / 15.0).rem_euclid(24.0)
    }

    /// Local true solar time at east longitude `lon_east_deg` (C-4), hours [0, 24).
    pub fn ltst_hours(&self, lon_east_deg: f64) -> f64 {
        let eot_h = SolarGeometry::at_days_since_j2000(self.days_since_j2000_tt).eot_deg / 15.0;
        (self.lmst_hours(lon_east_deg) + eot_h).rem_euclid(24.0)
    }
}

pub(crate) fn msd_from_jd_tt(jd_tt: f64) -> f64 {
    (jd_tt - MSD_ANCHOR_JD_TT) / SOL_IN_DAYS + MSD_AT_ANCHOR
}

pub(crate) fn jd_tt_from_msd(msd: f64) -> f64 {
    (msd - MSD_AT_ANCHOR) * SOL_IN_DAYS + MSD_ANCHOR_JD_TT
}

/// The instant at TT Julian date `jd_tt`.
pub(crate) fn epoch_from_jd_tt(jd_tt: f64) -> Epoch {
    Epoch::from_jde_in_time_scale(jd_tt, TimeScale::TT)
}

/// The local sol number at a site: the integer part of the Mars Sol Date counted in
/// the site's local mean solar time (sol N runs from LMST 00:00 to 24:00).
pub fn local_sol(epoch: Epoch, site: &Site) -> i64 {
    let msd = MarsTime::from_epoch(epoch).msd;
    (msd + site.lon_east_deg() / 360.0).floor() as i64
}

/// The UTC instant at which local true solar time equals `ltst_hours` during local
/// sol `sol` at `site` (see [`local_sol`]).
///
/// LTST = LMST + EOT; the equation of time moves by under 0.1 s per minute, so a few
/// fixed-point steps converge to well under a millisecond. Because EOT reaches ±50 min,
/// the instant can lie up to that much outside the mean-time bounds of sol `sol`.
pub fn utc_at_ltst(sol: i64, site: &Site, ltst_hours: f64) -> Result<Epoch> {
    if !VALID_SOLS.contains(&sol) {
        return Err(Error::OutOfRange {
            field: "sol",
            value: sol as f64,
            allowed: "-97000..=258000 (Mars Sol Dates of the years 1600 to 2600, where the ephemeris holds)",
        });
    }
    if !(0.0..=24.0).contains(&ltst_hours) {
        return Err(Error::OutOfRange { field: "ltst_hours", value: ltst_hours, allowed: "0..=24" });
    }
    let lon_frac = site.lon_east_deg() / 360.0;
    let mut eot_h = 0.0;
    let mut jd_tt = 0.0;
    for _ in 0..6 {
        let local_msd = sol as f64 + (ltst_hours - eot_h) / 24.0;
        jd_tt = jd_tt_from_msd(local_msd - lon_frac);
        eot_h = SolarGeometry::at_days_since_j2000(jd_tt - J2000_JD_TT).eot_deg / 15.0;
    }
    Ok(epoch_from_jd_tt(jd_tt))
}

/// The years the ephemeris serves (Mars24's series, hifitime's leap-second table and
/// the Keplerian elements all lose meaning far outside them).
pub const VALID_YEARS: std::ops::RangeInclusive<i32> = 1600..=2600;

/// The Mars Sol Dates inside [`VALID_YEARS`].
pub const VALID_SOLS: std::ops::RangeInclusive<i64> = -97_000..=258_000;

/// Parses an ISO 8601 UTC instant such as `2012-08-06T05:17:57Z` or
/// `2012-08-06T05:17:57.250 UTC`.
pub fn parse_utc(text: &str) -> Result<Epoch> {
    let trimmed = text.trim();
    let bad = |reason: String| Error::BadTime { text: text.to_string(), reason };
    // hifitime reads a bare date-time in UTC; it does not take the `Z` designator.
    let body = trimmed.strip_suffix('Z').unwrap_or(trimmed);
    if body.len() < 10 || !body.as_bytes()[..4].iter().all(u8::is_ascii_digit) {
        return Err(bad("not of the form YYYY-MM-DDTHH:MM:SS".into()));
    }
    let epoch = Epoch::from_gregorian_str(body).map_err(|e| match e {
        hifitime::HifitimeError::InvalidGregorianDate => bad("no such calendar date or time of day".into()),
        other => bad(other.to_string()),
    })?;
    if epoch.time_scale != TimeScale::UTC {
        return Err(bad(format!("time scale {} given; areo files and flags use UTC", epoch.time_scale)));
    }
    let year = epoch.to_gregorian_utc().0;
    if !VALID_YEARS.contains(&year) {
        return Err(bad(format!("year {year} is outside the ephemeris' validity, 1600..=2600")));
    }
    Ok(epoch)
}

/// Formats an instant as ISO 8601 UTC with milliseconds, e.g. `2012-08-06T05:17:57.000Z`.
pub fn format_utc(epoch: Epoch) -> String {
    let (y, mo, d, h, mi, s, ns) = epoch.to_gregorian_utc();
    format!("{y:04}-{mo:02}-{d:02}T{h:02}:{mi:02}:{s:02}.{:03}Z", ns / 1_000_000)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sol_of_areo_body_is_mars24s() {
        assert_eq!(SOL_S, SOL_IN_DAYS * 86_400.0);
    }

    #[test]
    fn a_sol_is_24_h_39_min_35_244_s() {
        // The published mean solar day: 24 h 39 min 35.244 s = 88 775.244 s.
        assert!((SOL_S - 88_775.244).abs() < 1e-3, "{SOL_S}");
        // One sol advances the Mars Sol Date by one.
        let t = parse_utc("2025-03-01T00:00:00Z").unwrap();
        let msd0 = MarsTime::from_epoch(t).msd;
        let msd1 = MarsTime::from_epoch(t + hifitime::Duration::from_seconds(SOL_S)).msd;
        assert!((msd1 - msd0 - 1.0).abs() < 1e-9, "{}", msd1 - msd0);
    }

    #[test]
    fn parse_accepts_z_and_rejects_garbage() {
        let t = parse_utc("2000-01-06T00:00:00Z").unwrap();
        assert_eq!(t.to_unix_milliseconds(), 947_116_800_000.0);
        assert_eq!(format_utc(t), "2000-01-06T00:00:00.000Z");
        for bad in ["", "yesterday", "2000-13-45T00:00:00Z", "2000-01-06T25:61:00Z", "20"] {
            assert!(parse_utc(bad).is_err(), "{bad:?} parsed");
        }
    }

    #[test]
    fn msd_and_jd_are_inverse() {
        for msd in [44_795.999_76, 46_215.548_557, 52_000.25] {
            assert!((msd_from_jd_tt(jd_tt_from_msd(msd)) - msd).abs() < 1e-9);
        }
    }
}
