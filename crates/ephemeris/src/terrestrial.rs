//! The Sun from a site on the Earth: apparent place of date from
//! [`crate::geocentric`] (Meeus ch. 25 with nutation), the Earth's rotation as Greenwich
//! apparent sidereal time (Meeus 12.4 plus the equation of the equinoxes) with UTC
//! taken as UT1 (|UT1 − UTC| < 0.9 s, under 0.004° of hour angle), and sites on the
//! WGS84 ellipsoid at geodetic latitude. Polar motion (< 0.5″) is ignored.
//!
//! The class of accuracy is NREL's Solar Position Algorithm's worked example to
//! ≈ 0.005° (test `sun_matches_the_nrel_spa_worked_example`); refraction is separate
//! ([`refraction_deg`]), since the planners want the geometric Sun.

use hifitime::Epoch;

use crate::geocentric::{
    Ecliptic, centuries, ecliptic_to_equatorial, mean_obliquity_deg, nutation_deg, rot_z, sun_ecliptic,
};
use crate::sun::SunState;

/// WGS84 equatorial radius, m.
pub const WGS84_A_M: f64 = areo_body::Spheroid::EARTH_WGS84.equatorial_radius_m;
/// WGS84 flattening.
pub const WGS84_F: f64 = 1.0 / areo_body::WGS84_INVERSE_FLATTENING;

/// Greenwich apparent sidereal time, degrees [0, 360), at UT1 Julian date `jd_ut` with
/// `t_tt` the TT Julian centuries (for nutation).
pub fn apparent_sidereal_time_deg(jd_ut: f64, t_tt: f64) -> f64 {
    let d = jd_ut - 2_451_545.0;
    let t = d / 36_525.0;
    let gmst = 280.460_618_37 + 360.985_647_366_29 * d + 0.000_387_933 * t * t - t * t * t / 38_710_000.0;
    let (dpsi, deps) = nutation_deg(t_tt);
    let eps = mean_obliquity_deg(t_tt) + deps;
    (gmst + dpsi * eps.to_radians().cos()).rem_euclid(360.0)
}

/// The Sun from the Earth's centre at `epoch`, in the Earth-fixed frame (x to the
/// Greenwich meridian on the equator, z to the pole), with its distance in AU.
pub fn sun(epoch: Epoch) -> SunState {
    sun_at(epoch.to_jde_utc_days(), epoch.to_jde_tt_days())
}

/// [`sun`] from the UTC (= UT1 here) and TT Julian dates.
pub fn sun_at(jd_ut: f64, jd_tt: f64) -> SunState {
    let t = centuries(jd_tt);
    let p = sun_ecliptic(t);
    let (dpsi, deps) = nutation_deg(t);
    let apparent = Ecliptic { lon_deg: p.lon_deg + dpsi, ..p };
    let v = ecliptic_to_equatorial(&apparent, mean_obliquity_deg(t) + deps);
    let theta = apparent_sidereal_time_deg(jd_ut, t).to_radians();
    let bf = rot_z(-theta, v);
    let n = (bf[0] * bf[0] + bf[1] * bf[1] + bf[2] * bf[2]).sqrt();
    SunState { direction_body_fixed: [bf[0] / n, bf[1] / n, bf[2] / n], distance_au: p.distance }
}

/// Atmospheric refraction (degrees to add to a geometric elevation) at `pressure_hpa`
/// and `temperature_c`, the formula NREL's SPA uses (Bennett's, scaled by pressure and
/// temperature); 0 for a Sun more than its semi-diameter plus the horizon refraction
/// (0.8333°) below the horizon.
pub fn refraction_deg(elevation_deg: f64, pressure_hpa: f64, temperature_c: f64) -> f64 {
    if elevation_deg < -0.833_3 {
        return 0.0;
    }
    let e = elevation_deg;
    (pressure_hpa / 1010.0) * (283.0 / (273.0 + temperature_c)) * 1.02
        / (60.0 * (e + 10.3 / (e + 5.11)).to_radians().tan())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Site;
    use crate::body::Body;

    /// NREL SPA (Reda & Andreas 2004/2008), the worked example of its Table A5.1:
    /// 2003-10-17 12:30:30 local (UTC−7), 39.742476° N, 105.1786° W, 1830.14 m,
    /// 820 hPa, 11 °C → topocentric zenith 50.11162° (refracted), azimuth 194.34024°,
    /// Earth–Sun distance 0.9965422974 AU. (SPA uses ΔT = 67 s and UT1 = UTC; so does
    /// areo, within a second.)
    #[test]
    fn sun_matches_the_nrel_spa_worked_example() {
        let t = crate::parse_utc("2003-10-17T19:30:30Z").unwrap();
        let site = Site::on(Body::Earth, 39.742_476, -105.1786).unwrap();
        let s = sun(t);
        // The same truncated VSOP87 series as SPA's: equal to rounding.
        assert!((s.distance_au - 0.996_542_297_4).abs() < 1e-8, "{}", s.distance_au);
        let p = s.at_site(&site);
        let refracted = p.elevation_deg + refraction_deg(p.elevation_deg, 820.0, 11.0);
        let zenith = 90.0 - refracted;
        assert!((zenith - 50.111_62).abs() < 0.01, "zenith {zenith}");
        let daz = (p.azimuth_deg - 194.340_24) * p.elevation_deg.to_radians().cos();
        assert!(daz.abs() < 0.01, "azimuth {}", p.azimuth_deg);
    }

    /// Published equinox and solstice instants (to the minute, UTC) between 2000 and
    /// 2025: the Sun's apparent declination crosses zero at an equinox and peaks at
    /// ±23.44° at a solstice; its longitude moves 0.0007° a minute, so a minute's
    /// rounding is 0.0007° and the test bounds the theory's error over 25 years: the
    /// chapter-25 theory leaves out the Moon's and planets' pulls (up to ≈ 0.008°).
    #[test]
    fn equinoxes_and_solstices_fall_at_their_published_minutes() {
        let apparent_lon = |utc: &str| {
            let e = crate::parse_utc(utc).unwrap();
            let t = centuries(e.to_jde_tt_days());
            (sun_ecliptic(t).lon_deg + nutation_deg(t).0).rem_euclid(360.0)
        };
        for (utc, lon) in [
            ("2000-03-20T07:35:00Z", 0.0),
            ("2019-03-20T21:58:00Z", 0.0),
            ("2020-03-20T03:50:00Z", 0.0),
            ("2021-03-20T09:37:00Z", 0.0),
            ("2024-03-20T03:06:00Z", 0.0),
            ("2025-03-20T09:01:00Z", 0.0),
            ("2020-06-20T21:43:00Z", 90.0),
            ("2024-06-20T20:51:00Z", 90.0),
        ] {
            let d = (apparent_lon(utc) - lon + 180.0).rem_euclid(360.0) - 180.0;
            assert!(d.abs() < 0.01, "{utc}: {d}");
        }
    }

    #[test]
    fn refraction_is_half_a_degree_at_the_horizon_and_small_overhead() {
        let r0 = refraction_deg(0.0, 1010.0, 10.0);
        assert!((r0 - 0.48).abs() < 0.03, "{r0}");
        assert!(refraction_deg(89.0, 1010.0, 10.0) < 0.001);
        assert_eq!(refraction_deg(-2.0, 1010.0, 10.0), 0.0);
    }
}
