//! The Earth seen from Mars, for direct-to-Earth communication windows.
//!
//! Model: heliocentric positions of the Earth–Moon barycentre and Mars from the JPL
//! Keplerian elements and rates of Standish, "Approximate Positions of the Planets"
//! (Table 1, valid 1800–2050; quoted errors of tens of arcseconds), in the J2000
//! ecliptic; rotated to ICRF equatorial with the J2000 obliquity 23.439 291 1°; then to
//! the Mars body-fixed frame with the IAU 2009 Mars rotation (pole α0 = 317.681 43° −
//! 0.1061° T, δ0 = 52.886 50° − 0.0609° T, prime meridian W = 176.630° +
//! 350.891 982 26° d). The Earth is taken where it was one light time earlier. The
//! Earth–barycentre offset (≤ 4700 km) is below 0.01° from Mars, and the whole chain is
//! checked against the Mars24 Sun direction (see the tests) to well under 0.5°.

use hifitime::Epoch;

use crate::site::Site;
use crate::time::{J2000_JD_TT, MarsTime};

/// Astronomical unit, m (IAU 2012).
pub const AU_M: f64 = 149_597_870_700.0;
/// Speed of light, m/s.
const C_M_S: f64 = 299_792_458.0;
const OBLIQUITY_J2000_DEG: f64 = 23.439_291_1;

/// Keplerian elements at J2000 and their rates per Julian century:
/// a (AU), e, I (deg), L (deg), ϖ (deg), Ω (deg).
struct Elements {
    at_j2000: [f64; 6],
    per_century: [f64; 6],
}

const EARTH_MOON_BARYCENTRE: Elements = Elements {
    at_j2000: [1.000_002_61, 0.016_711_23, -0.000_015_31, 100.464_571_66, 102.937_681_93, 0.0],
    per_century: [0.000_005_62, -0.000_043_92, -0.012_946_68, 35_999.372_449_81, 0.323_273_64, 0.0],
};

const MARS: Elements = Elements {
    at_j2000: [1.523_710_34, 0.093_394_10, 1.849_691_42, -4.553_432_05, -23.943_629_59, 49.559_538_91],
    per_century: [0.000_018_47, 0.000_078_82, -0.008_131_31, 19_140.302_684_99, 0.444_410_88, -0.292_573_43],
};

impl Elements {
    /// Heliocentric position in the J2000 ecliptic frame, AU, `dt` days of TT after J2000.
    fn position(&self, dt: f64) -> [f64; 3] {
        let t = dt / 36_525.0;
        let el: [f64; 6] = std::array::from_fn(|i| self.at_j2000[i] + self.per_century[i] * t);
        let [a, e, inc, l, peri, node] = el;
        let omega = peri - node;
        let m = (l - peri).to_radians();
        let ecc_anomaly = solve_kepler(m, e);
        let xp = a * (ecc_anomaly.cos() - e);
        let yp = a * (1.0 - e * e).sqrt() * ecc_anomaly.sin();
        let (so, co) = omega.to_radians().sin_cos();
        let (sn, cn) = node.to_radians().sin_cos();
        let (si, ci) = inc.to_radians().sin_cos();
        [
            (co * cn - so * sn * ci) * xp + (-so * cn - co * sn * ci) * yp,
            (co * sn + so * cn * ci) * xp + (-so * sn + co * cn * ci) * yp,
            (so * si) * xp + (co * si) * yp,
        ]
    }
}

fn solve_kepler(m: f64, e: f64) -> f64 {
    let m = (m + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    let mut ea = m + e * m.sin();
    for _ in 0..8 {
        let d = (ea - e * ea.sin() - m) / (1.0 - e * ea.cos());
        ea -= d;
        if d.abs() < 1e-14 {
            break;
        }
    }
    ea
}

fn ecliptic_to_equatorial(v: [f64; 3]) -> [f64; 3] {
    let (s, c) = OBLIQUITY_J2000_DEG.to_radians().sin_cos();
    [v[0], c * v[1] - s * v[2], s * v[1] + c * v[2]]
}

/// Rotates an ICRF (J2000 equatorial) vector into the Mars body-fixed frame.
fn equatorial_to_mars_body_fixed(v: [f64; 3], dt: f64) -> [f64; 3] {
    let t = dt / 36_525.0;
    let alpha0 = (317.681_43 - 0.1061 * t).to_radians();
    let delta0 = (52.886_50 - 0.0609 * t).to_radians();
    let w = (176.630 + 350.891_982_26 * dt).rem_euclid(360.0).to_radians();
    // Rz(W) · Rx(90° − δ0) · Rz(90° + α0)
    let rz = |a: f64, v: [f64; 3]| {
        let (s, c) = a.sin_cos();
        [c * v[0] + s * v[1], -s * v[0] + c * v[1], v[2]]
    };
    let rx = |a: f64, v: [f64; 3]| {
        let (s, c) = a.sin_cos();
        [v[0], c * v[1] + s * v[2], -s * v[1] + c * v[2]]
    };
    let v = rz(std::f64::consts::FRAC_PI_2 + alpha0, v);
    let v = rx(std::f64::consts::FRAC_PI_2 - delta0, v);
    rz(w, v)
}

/// The Earth seen from Mars at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EarthState {
    /// Unit vector from Mars to the Earth (light-time corrected), body-fixed frame.
    pub direction_body_fixed: [f64; 3],
    /// Mars–Earth distance, AU.
    pub distance_au: f64,
    /// One-way light time, s.
    pub light_time_s: f64,
}

/// The Earth as seen from Mars at `epoch`.
pub fn earth_from_mars(epoch: Epoch) -> EarthState {
    earth_from_mars_at(MarsTime::from_epoch(epoch).jd_tt - J2000_JD_TT)
}

fn earth_from_mars_at(dt: f64) -> EarthState {
    let mars = MARS.position(dt);
    let mut tau_days = 0.0;
    let mut rel = [0.0; 3];
    for _ in 0..4 {
        let earth = EARTH_MOON_BARYCENTRE.position(dt - tau_days);
        rel = [earth[0] - mars[0], earth[1] - mars[1], earth[2] - mars[2]];
        let d = norm(rel);
        tau_days = d * AU_M / C_M_S / 86_400.0;
    }
    let d = norm(rel);
    let bf = equatorial_to_mars_body_fixed(ecliptic_to_equatorial(rel), dt);
    EarthState {
        direction_body_fixed: [bf[0] / d, bf[1] / d, bf[2] / d],
        distance_au: d,
        light_time_s: tau_days * 86_400.0,
    }
}

/// The Earth's azimuth (clockwise from north) and elevation above the local horizontal
/// at `site`, degrees.
pub fn earth_azimuth_elevation_deg(epoch: Epoch, site: &Site) -> (f64, f64) {
    site.azimuth_elevation_deg(earth_from_mars(epoch).direction_body_fixed)
}

/// The Sun's body-fixed direction from the same Keplerian chain (no light time: the Sun
/// sits at the origin). Used to validate the chain against Mars24.
pub fn sun_direction_keplerian(epoch: Epoch) -> [f64; 3] {
    let dt = MarsTime::from_epoch(epoch).jd_tt - J2000_JD_TT;
    let mars = MARS.position(dt);
    let bf = equatorial_to_mars_body_fixed(ecliptic_to_equatorial([-mars[0], -mars[1], -mars[2]]), dt);
    let d = norm(bf);
    [bf[0] / d, bf[1] / d, bf[2] / d]
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kepler_solution_satisfies_the_equation() {
        for &(m, e) in &[(0.3, 0.0934), (3.0, 0.2), (-2.0, 0.0167)] {
            let ea = solve_kepler(m, e);
            let back = ea - e * ea.sin();
            assert!((back - m).abs() < 1e-12);
        }
    }

    #[test]
    fn orbits_have_the_right_size() {
        let r_earth = norm(EARTH_MOON_BARYCENTRE.position(0.0));
        assert!((r_earth - 0.9833).abs() < 0.002, "{r_earth}"); // near perihelion on 1 Jan
        // Mars at J2000: Mars24 D-2 gives rH for the same instant.
        let r_mars = norm(MARS.position(0.0));
        let r24 = crate::SolarGeometry::at_days_since_j2000(0.0).distance_au;
        assert!((r_mars - r24).abs() < 1e-3, "{r_mars} vs {r24}");
    }
}
