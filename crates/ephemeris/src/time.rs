//! Earth and Mars time scales: UTC, TT, Julian dates, Mars Sol Date, MTC, LMST, LTST.

use hifitime::{Epoch, TimeScale};

use crate::error::{Error, Result};
use crate::site::Site;
use crate::sun::SolarGeometry;

/// Julian date (TT) of the J2000 epoch.
pub(crate) const J2000_JD_TT: f64 = 2_451_545.0;
/// Length of the mean Mars solar day in Earth days (Mars24, 2018 constants; areo-body's).
pub(crate) use areo_body::SOL_IN_DAYS;

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
    let bad = |reason: String| Error::BadTime { text: text.to_string(), reason };
    let iso = calendar_form(text.trim()).map_err(bad)?;
    let trimmed = iso.as_str();
    // hifitime reads a bare date-time in UTC; it does not take the `Z` designator.
    let body = trimmed.strip_suffix('Z').unwrap_or(trimmed);
    if body.len() < 10 || !body.as_bytes()[..4].iter().all(u8::is_ascii_digit) {
        return Err(bad(
            "not a UTC instant: write YYYY-MM-DDTHH:MM:SS[Z], YYYY-DDDTHH:MM:SS (day of year) or YYYY MON DD HH:MM:SS"
                .into(),
        ));
    }
    // hifitime reads a leap second's :60 as :59; refuse it rather than move the instant.
    if body.get(17..19) == Some("60") && body.as_bytes().get(16) == Some(&b':') {
        return Err(bad("second 60 (a leap second) is not read: give :59.999 or the next minute".into()));
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

/// The ISO 8601 calendar form (`2012-08-06T05:17:57`) of a UTC instant written in one
/// of the forms missions use: that form itself (a trailing `Z` allowed), ISO 8601
/// day-of-year (`2012-219T05:17:57`, as PDS labels and mission logs write it) or
/// SPICE's (`2012 AUG 06 05:17:57`, a trailing `UTC` allowed).
fn calendar_form(text: &str) -> std::result::Result<String, String> {
    let text = text.strip_suffix("UTC").map_or(text, str::trim_end);
    let b = text.as_bytes();
    let digits = |r: std::ops::Range<usize>| b.get(r.clone()).is_some_and(|s| s.iter().all(u8::is_ascii_digit));
    // Day of year: YYYY-DDD, then T or the end.
    if digits(0..4) && b.get(4) == Some(&b'-') && digits(5..8) && matches!(b.get(8), None | Some(b'T')) {
        let year: i32 = text[..4].parse().map_err(|_| "bad year".to_string())?;
        let doy: u32 = text[5..8].parse().map_err(|_| "bad day of year".to_string())?;
        let leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
        let lengths = [31, if leap { 29 } else { 28 }, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31];
        let days: u32 = lengths.iter().sum();
        if !(1..=days).contains(&doy) {
            return Err(format!("day of year {doy} is outside 1..={days} in {year}"));
        }
        let (mut month, mut day) = (1, doy);
        for len in lengths {
            if day <= len {
                break;
            }
            day -= len;
            month += 1;
        }
        let rest = if text.len() > 8 { &text[8..] } else { "T00:00:00" };
        return Ok(format!("{year:04}-{month:02}-{day:02}{rest}"));
    }
    // SPICE: YYYY MON DD HH:MM:SS[.fff]
    let parts: Vec<&str> = text.split_whitespace().collect();
    if parts.len() >= 3 && digits(0..4) && parts[0].len() == 4 && parts[1].chars().all(|c| c.is_ascii_alphabetic()) {
        const MONTHS: [&str; 12] = ["JAN", "FEB", "MAR", "APR", "MAY", "JUN", "JUL", "AUG", "SEP", "OCT", "NOV", "DEC"];
        let month = MONTHS
            .iter()
            .position(|m| parts[1].len() >= 3 && parts[1][..3].eq_ignore_ascii_case(m))
            .ok_or_else(|| format!("{:?} is not a month (JAN..DEC)", parts[1]))?;
        let day: u32 = parts[2].parse().map_err(|_| format!("{:?} is not a day of the month", parts[2]))?;
        let time = parts.get(3).copied().unwrap_or("00:00:00");
        if parts.len() > 4 {
            return Err("write YYYY MON DD HH:MM:SS".into());
        }
        return Ok(format!("{}-{:02}-{day:02}T{time}", parts[0], month + 1));
    }
    Ok(text.to_string())
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

    /// Curiosity's landing as PDS labels (day of year) and SPICE write it is the same
    /// instant as in ISO 8601; 2012 is a leap year (day 219 is August 6; day 366 exists),
    /// 2013 is not.
    #[test]
    fn parse_accepts_day_of_year_and_spice_forms() {
        let iso = parse_utc("2012-08-06T05:17:57Z").unwrap();
        for same in ["2012-219T05:17:57", "2012-219T05:17:57Z", "2012 AUG 06 05:17:57", "2012 aug 06 05:17:57 UTC"] {
            assert_eq!(parse_utc(same).unwrap(), iso, "{same}");
        }
        assert_eq!(format_utc(parse_utc("2012-366T12:00:00").unwrap()), "2012-12-31T12:00:00.000Z");
        assert_eq!(format_utc(parse_utc("2013-060").unwrap()), "2013-03-01T00:00:00.000Z");
        assert_eq!(format_utc(parse_utc("2012 FEB 29").unwrap()), "2012-02-29T00:00:00.000Z");
        for bad in [
            "2013-366T00:00:00",
            "2012-000T00:00:00",
            "2012 FOO 06 05:17:57",
            "2013 FEB 29 00:00:00",
            // A leap second is refused, not read as :59.
            "2016-12-31T23:59:60Z",
            "2016-366T23:59:60",
        ] {
            assert!(parse_utc(bad).is_err(), "{bad:?} parsed");
        }
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
