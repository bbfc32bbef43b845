//! The Mars24 solar geometry and the `SunModel` abstraction the planners consume.

use hifitime::Epoch;

use crate::site::Site;
use crate::time::{J2000_JD_TT, MarsTime, msd_from_jd_tt};

/// Mars24 PBS perturbation terms: amplitude A (deg), period τ (Julian years), phase φ (deg).
const PERTURBATIONS: [(f64, f64, f64); 7] = [
    (0.0071, 2.2353, 49.409),
    (0.0057, 2.7543, 168.173),
    (0.0039, 1.1177, 191.837),
    (0.0037, 15.7866, 21.736),
    (0.0021, 2.1354, 15.704),
    (0.0020, 2.4694, 95.528),
    (0.0018, 32.8493, 49.095),
];

/// The perturbation terms with their rates 0.985626°/day ÷ τ precomputed.
const PERTURBATION_RATES: [(f64, f64, f64); 7] = {
    let mut out = [(0.0, 0.0, 0.0); 7];
    let mut i = 0;
    while i < 7 {
        let (a, tau, phi) = PERTURBATIONS[i];
        out[i] = (a, 0.985_626 / tau, phi);
        i += 1;
    }
    out
};

/// sin of Mars' obliquity used by Mars24 for the solar declination (sin 25.19°).
const SIN_OBLIQUITY: f64 = 0.42565;

/// Every intermediate and final quantity of the Mars24 algorithm at one instant
/// (2018 constants). Angles in degrees, wrapped to [0, 360) where they are angles of a
/// circle. Letters in the field docs are the steps of the GISS page.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolarGeometry {
    /// Days of TT since J2000.
    pub days_since_j2000_tt: f64,
    /// Mars mean anomaly M (B-1).
    pub mean_anomaly_deg: f64,
    /// Right ascension of the fictitious mean Sun α_FMS (B-2).
    pub alpha_fms_deg: f64,
    /// Sum of the seven planetary perturbations PBS (B-3).
    pub perturbations_deg: f64,
    /// Equation of centre ν − M (B-4).
    pub equation_of_center_deg: f64,
    /// Areocentric solar longitude Ls (B-5), apparent (aberration included).
    pub ls_deg: f64,
    /// Equation of time (C-1): LTST − LMST expressed as an angle.
    pub eot_deg: f64,
    /// Coordinated Mars Time (C-2), hours [0, 24).
    pub mtc_hours: f64,
    /// Sub-solar longitude, east (360° − C-5's west longitude).
    pub subsolar_lon_east_deg: f64,
    /// Sub-solar latitude, planetocentric: asin(0.42565 sin Ls) — the declination of
    /// the Sun's direction from Mars' centre.
    pub subsolar_lat_planetocentric_deg: f64,
    /// Sub-solar latitude, planetographic (D-1): planetocentric + 0.25° sin Ls.
    pub subsolar_lat_planetographic_deg: f64,
    /// Heliocentric distance of Mars rH (D-2), astronomical units.
    pub distance_au: f64,
    /// Heliocentric longitude of Mars (D-3).
    pub heliocentric_lon_deg: f64,
    /// Heliocentric latitude of Mars (D-4).
    pub heliocentric_lat_deg: f64,
}

impl SolarGeometry {
    /// The geometry at `epoch`.
    pub fn at(epoch: Epoch) -> SolarGeometry {
        SolarGeometry::at_days_since_j2000(MarsTime::from_epoch(epoch).days_since_j2000_tt)
    }

    /// The geometry `dt` days of TT after J2000.
    pub fn at_days_since_j2000(dt: f64) -> SolarGeometry {
        let core = Core::at(dt);
        let dec_c = core.sin_dec.asin().to_degrees();
        let helio_lon =
            (core.ls + 85.061 - 0.015 * (71.0 + 2.0 * core.ls).to_radians().sin() - 5.5e-6 * dt).rem_euclid(360.0);
        let helio_lat = -(1.8497 - 2.23e-5 * dt) * (core.ls - 144.50 + 2.57e-6 * dt).to_radians().sin();
        SolarGeometry {
            days_since_j2000_tt: dt,
            mean_anomaly_deg: core.m,
            alpha_fms_deg: core.alpha,
            perturbations_deg: core.pbs,
            equation_of_center_deg: core.eoc,
            ls_deg: core.ls,
            eot_deg: core.eot,
            mtc_hours: core.mtc,
            subsolar_lon_east_deg: core.subsolar_lon_east,
            subsolar_lat_planetocentric_deg: dec_c,
            subsolar_lat_planetographic_deg: dec_c + 0.25 * core.sin_ls,
            distance_au: core.r,
            heliocentric_lon_deg: helio_lon,
            heliocentric_lat_deg: helio_lat,
        }
    }

    /// Only the Sun's direction and distance `dt` days of TT after J2000: the planners'
    /// hot path, skipping the heliocentric coordinates.
    pub fn sun_state_at_days(dt: f64) -> SunState {
        Core::at(dt).state()
    }

    /// The first instant after `after_days` (days of TT since J2000) at which Ls
    /// equals `target_deg`, as days of TT since J2000, found by bracketing (Ls advances
    /// 0.3–0.7° per day) and bisection to ~1 ms.
    pub fn next_ls_days(target_deg: f64, after_days: f64) -> f64 {
        // Degrees still to go until Ls reaches the target, in (0, 360].
        let to_go = |dt: f64| {
            let d = (target_deg - SolarGeometry::at_days_since_j2000(dt).ls_deg).rem_euclid(360.0);
            if d == 0.0 { 360.0 } else { d }
        };
        let mut a = after_days;
        let mut fa = to_go(a);
        loop {
            let b = a + 1.0;
            let fb = to_go(b);
            // Crossing the target makes the distance to go jump from ~0 back to ~360.
            if fb > fa {
                let (mut lo, mut hi) = (a, b);
                while hi - lo > 1e-8 {
                    let mid = 0.5 * (lo + hi);
                    if to_go(mid) > 180.0 {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return 0.5 * (lo + hi);
            }
            a = b;
            fa = fb;
        }
    }

    /// Equation of time, hours (LTST − LMST).
    pub fn eot_hours(&self) -> f64 {
        self.eot_deg / 15.0
    }

    /// Local mean solar time at east longitude `lon_east_deg`, hours [0, 24).
    pub fn lmst_hours(&self, lon_east_deg: f64) -> f64 {
        (self.mtc_hours + lon_east_deg / 15.0).rem_euclid(24.0)
    }

    /// Local true solar time at east longitude `lon_east_deg`, hours [0, 24).
    pub fn ltst_hours(&self, lon_east_deg: f64) -> f64 {
        (self.lmst_hours(lon_east_deg) + self.eot_hours()).rem_euclid(24.0)
    }

    /// The Sun's state: unit direction from Mars' centre in the body-fixed frame (x to
    /// 0° E on the equator, z to the north pole) and its distance.
    pub fn state(&self) -> SunState {
        sun_state(self.subsolar_lat_planetocentric_deg, self.subsolar_lon_east_deg, self.distance_au)
    }

    /// The GISS page's own local formulas (D-5, D-6): solar zenith angle and azimuth
    /// (clockwise from north), degrees, for a planetographic latitude and east
    /// longitude, with the planetographic declination. Kept to reproduce the published
    /// worked examples; [`SunState::at_site`] is the geometric computation on the
    /// ellipsoid and differs from this by up to ~0.25°.
    pub fn mars24_zenith_azimuth_deg(&self, planetographic_lat_deg: f64, lon_east_deg: f64) -> (f64, f64) {
        let lon_west = (360.0 - lon_east_deg).rem_euclid(360.0);
        let subsolar_lon_west = 360.0 - self.subsolar_lon_east_deg;
        let h = (lon_west - subsolar_lon_west).to_radians();
        let phi = planetographic_lat_deg.to_radians();
        let dec = self.subsolar_lat_planetographic_deg.to_radians();
        let cos_z = (dec.sin() * phi.sin() + dec.cos() * phi.cos() * h.cos()).clamp(-1.0, 1.0);
        let az = h.sin().atan2(phi.cos() * dec.tan() - phi.sin() * h.cos());
        (cos_z.acos().to_degrees(), az.to_degrees().rem_euclid(360.0))
    }
}

fn sun_state(lat_deg: f64, lon_east_deg: f64, distance_au: f64) -> SunState {
    let (sp, cp) = lat_deg.to_radians().sin_cos();
    let (sl, cl) = lon_east_deg.to_radians().sin_cos();
    SunState { direction_body_fixed: [cp * cl, cp * sl, sp], distance_au }
}

/// The Mars24 steps B-1 to D-2 that every use needs. Multiples of M and Ls come from
/// the angle-addition recurrences (one sin/cos pair each instead of nine trig calls).
struct Core {
    m: f64,
    alpha: f64,
    pbs: f64,
    eoc: f64,
    ls: f64,
    sin_ls: f64,
    eot: f64,
    mtc: f64,
    subsolar_lon_east: f64,
    /// sin of the planetocentric declination of the Sun.
    sin_dec: f64,
    r: f64,
}

impl Core {
    fn at(dt: f64) -> Core {
        let m = wrap(19.3871 + 0.524_020_73 * dt, 360.0);
        let alpha = wrap(270.3871 + 0.524_038_496 * dt, 360.0);
        let pbs: f64 = PERTURBATION_RATES.iter().map(|&(a, rate, phi)| a * cos_deg_small(rate * dt + phi)).sum();
        let (s1, c1) = m.to_radians().sin_cos();
        let (s2, c2) = (2.0 * s1 * c1, c1 * c1 - s1 * s1);
        let (s3, c3) = (s2 * c1 + c2 * s1, c2 * c1 - s2 * s1);
        let (s4, c4) = (2.0 * s2 * c2, c2 * c2 - s2 * s2);
        let s5 = s4 * c1 + c4 * s1;
        let eoc = (10.691 + 3.0e-7 * dt) * s1 + 0.623 * s2 + 0.050 * s3 + 0.005 * s4 + 0.0005 * s5 + pbs;
        let ls = wrap(alpha + eoc, 360.0);
        let (sin_ls, cos_ls) = ls.to_radians().sin_cos();
        let (sl2, cl2) = (2.0 * sin_ls * cos_ls, cos_ls * cos_ls - sin_ls * sin_ls);
        let (sl4, cl4) = (2.0 * sl2 * cl2, cl2 * cl2 - sl2 * sl2);
        let sl6 = sl4 * cl2 + cl4 * sl2;
        let eot = 2.861 * sl2 - 0.071 * sl4 + 0.002 * sl6 - eoc;
        let msd = msd_from_jd_tt(dt + J2000_JD_TT);
        let mtc = wrap(24.0 * msd, 24.0);
        let subsolar_lon_west = wrap(mtc * 15.0 + eot + 180.0, 360.0);
        let sin_dec = SIN_OBLIQUITY * sin_ls;
        let r = 1.523_679_34 * (1.004_36 - 0.093_09 * c1 - 0.004_336 * c2 - 0.000_31 * c3 - 0.000_03 * c4);
        Core {
            m,
            alpha,
            pbs,
            eoc,
            ls,
            sin_ls,
            eot,
            mtc,
            subsolar_lon_east: wrap(360.0 - subsolar_lon_west, 360.0),
            sin_dec,
            r,
        }
    }

    fn state(&self) -> SunState {
        let cos_dec = (1.0 - self.sin_dec * self.sin_dec).sqrt();
        let (sl, cl) = self.subsolar_lon_east.to_radians().sin_cos();
        SunState { direction_body_fixed: [cos_dec * cl, cos_dec * sl, self.sin_dec], distance_au: self.r }
    }
}

/// `x` wrapped to [0, period) without the cost of `fmod`.
fn wrap(x: f64, period: f64) -> f64 {
    let w = x - period * (x / period).floor();
    if w >= period { w - period } else { w }
}

/// An angle in degrees reduced to the nearest multiple of 90° (its quadrant, 0..4) and
/// the cosine and sine of the remainder on [−45°, 45°] by Taylor polynomials, each to
/// ~3e-8 absolute.
#[inline(always)]
fn reduced(deg: f64) -> (i64, f64, f64) {
    let q = (deg / 90.0).round();
    let x = (deg - 90.0 * q).to_radians();
    let x2 = x * x;
    let c = 1.0 - x2 / 2.0 * (1.0 - x2 / 12.0 * (1.0 - x2 / 30.0 * (1.0 - x2 / 56.0)));
    let s = x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0))));
    ((q as i64).rem_euclid(4), c, s)
}

/// cos of an angle in degrees, to ~3e-8 absolute. Used only for the perturbation terms,
/// whose amplitudes (≤ 0.0071°) make the error below 1e-9°; it halves the cost of the
/// Sun's direction.
fn cos_deg_small(deg: f64) -> f64 {
    match reduced(deg) {
        (0, c, _) => c,
        (1, _, s) => -s,
        (2, c, _) => -c,
        (_, _, s) => s,
    }
}

/// sin and cos of an angle in degrees, each to ~3e-8 absolute: for terms whose
/// amplitude makes that error negligible.
pub(crate) fn sin_cos_deg_small(deg: f64) -> (f64, f64) {
    match reduced(deg) {
        (0, c, s) => (s, c),
        (1, c, s) => (c, -s),
        (2, c, s) => (-s, -c),
        (_, c, s) => (-c, s),
    }
}

/// The Sun seen from a body's centre at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SunState {
    /// Unit vector from the body's centre to the Sun, body-fixed frame.
    pub direction_body_fixed: [f64; 3],
    /// Sun–body distance, astronomical units.
    pub distance_au: f64,
}

impl SunState {
    /// Latitude (planetocentric) and east longitude [0, 360) of the sub-solar point,
    /// degrees.
    pub fn subsolar_deg(&self) -> (f64, f64) {
        let v = self.direction_body_fixed;
        (v[2].clamp(-1.0, 1.0).asin().to_degrees(), v[1].atan2(v[0]).to_degrees().rem_euclid(360.0))
    }

    /// Local true solar time at east longitude `lon_east_deg`, hours [0, 24): 12 h when
    /// the Sun crosses the meridian, one hour per 15° of the body's turn against the
    /// Sun (a lunar "hour" is 29.5 Earth hours).
    pub fn local_solar_time_hours(&self, lon_east_deg: f64) -> f64 {
        (12.0 + (lon_east_deg - self.subsolar_deg().1) / 15.0).rem_euclid(24.0)
    }

    /// The Sun's azimuth and elevation above the local horizontal at `site`. On Mars the
    /// Sun is taken at infinity, as Mars24 does (the parallax from a site 3400 km
    /// off-centre is below 0.001°); on the Moon and the Earth the direction is
    /// topocentric, from the site.
    pub fn at_site(&self, site: &Site) -> TrueSunDirection {
        let d = if site.body() == crate::Body::Mars {
            self.direction_body_fixed
        } else {
            let p = site.position_m();
            let r = self.distance_au * crate::earth::AU_M;
            let v: [f64; 3] = std::array::from_fn(|i| self.direction_body_fixed[i] * r - p[i]);
            let n = crate::site::dot(v, v).sqrt();
            [v[0] / n, v[1] / n, v[2] / n]
        };
        let (azimuth_deg, elevation_deg) = site.azimuth_elevation_deg(d);
        let [e, n, u] = site.enu_axes();
        let enu = [crate::site::dot(e, d), crate::site::dot(n, d), crate::site::dot(u, d)];
        TrueSunDirection { azimuth_deg, elevation_deg, direction_enu: enu }
    }
}

/// The Sun in a site's local frame, azimuth from true north (areo-terrain's
/// `GridSunDirection` is the same Sun on a map's grid).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrueSunDirection {
    /// Azimuth, clockwise from true north, degrees [0, 360).
    pub azimuth_deg: f64,
    /// Elevation above the local horizontal (ellipsoid tangent plane), degrees.
    pub elevation_deg: f64,
    /// Unit vector to the Sun in local east-north-up coordinates.
    pub direction_enu: [f64; 3],
}

/// Where the Sun is, as a function of time. areo-terrain's LOS sequences and
/// areo-mission's planner take any implementation, so a higher-fidelity ephemeris can
/// replace [`Mars24`] (or a [`crate::Body`]'s) without touching them.
pub trait SunModel {
    /// The Sun's direction (body-fixed, from the body's centre) and distance at `epoch`.
    fn sun(&self, epoch: Epoch) -> SunState;

    /// The body whose sky this is; default Mars.
    fn body(&self) -> crate::Body {
        crate::Body::Mars
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn fast_sine_is_accurate_everywhere() {
        let mut worst = 0.0f64;
        let mut x = -5000.0;
        while x < 5000.0 {
            worst = worst.max((super::sin_cos_deg_small(x).0 - x.to_radians().sin()).abs());
            x += 0.37;
        }
        assert!(worst < 5e-8, "{worst}");
    }

    #[test]
    fn fast_cosine_is_accurate_everywhere() {
        let mut worst = 0.0f64;
        let mut x = -5000.0;
        while x < 5000.0 {
            worst = worst.max((super::cos_deg_small(x) - x.to_radians().cos()).abs());
            x += 0.37;
        }
        assert!(worst < 5e-8, "{worst}");
    }
}

/// The Mars24 algorithm (Allison & McEwen 2000, 2018 GISS constants) as a [`SunModel`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Mars24;

impl SunModel for Mars24 {
    fn sun(&self, epoch: Epoch) -> SunState {
        SolarGeometry::sun_state_at_days(MarsTime::from_epoch(epoch).days_since_j2000_tt)
    }
}
