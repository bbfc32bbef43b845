//! The Sun and the Earth seen from the Moon.
//!
//! Positions come from [`crate::geocentric`] (Meeus's truncated ELP-2000/82 and solar
//! theory, in the J2000 equator); the Moon's orientation is the IAU WGCCRE model
//! (Archinal et al. 2011, 2018: pole α0, δ0 and prime meridian W with the 13 periodic
//! terms E1…E13), which approximates the mean-Earth/polar-axis frame of the lunar maps
//! (LOLA). Directions are from the Moon's centre in that body-fixed frame; the site's
//! parallax (1737 km: up to 0.26° for the Earth) is applied by
//! [`crate::SunState::at_site`] and [`crate::EarthView::at_site`].
//!
//! Light time is not applied: the Earth moves 1.3 s × 1 km/s ≈ 1.3 km (0.0002°) while
//! its light reaches the Moon; the Sun's aberration is the Earth's (included).

use hifitime::Epoch;

use crate::body::EarthView;
use crate::geocentric::{centuries, mat_mul, mat_vec, moon_mean_of_date_km, precession_to_j2000, sun_mean_of_date_au};
use crate::site::dot;
use crate::sun::SunState;
use crate::time::J2000_JD_TT;

/// Astronomical unit, km.
const AU_KM: f64 = 149_597_870.7;

/// The IAU rotation angles of the Moon at `d` days of TDB (≈ TT) since J2000: pole right
/// ascension α0, declination δ0 and prime meridian W, degrees.
pub fn orientation_deg(d: f64) -> (f64, f64, f64) {
    let t = d / 36_525.0;
    // Amplitudes ≤ 3.9°: the polynomial sine's 3e-8 costs ≤ 1.2e-7°.
    let e = |a: f64, rate: f64| Angle(crate::sun::sin_cos_deg_small(a + rate * d));
    let e1 = e(125.045, -0.052_992_1);
    let e2 = e(250.089, -0.105_984_2);
    let e3 = e(260.008, 13.012_000_9);
    let e4 = e(176.625, 13.340_715_4);
    let e5 = e(357.529, 0.985_600_3);
    let e6 = e(311.589, 26.405_708_4);
    let e7 = e(134.963, 13.064_993_0);
    let e8 = e(276.617, 0.328_714_6);
    let e9 = e(34.226, 1.748_487_7);
    let e10 = e(15.134, -0.158_976_3);
    let e11 = e(119.743, 0.003_609_6);
    let e12 = e(239.961, 0.164_357_3);
    let e13 = e(25.053, 12.959_008_8);
    let alpha = 269.9949 + 0.0031 * t - 3.8787 * e1.sin() - 0.1204 * e2.sin() + 0.0700 * e3.sin() - 0.0172 * e4.sin()
        + 0.0072 * e6.sin()
        - 0.0052 * e10.sin()
        + 0.0043 * e13.sin();
    let delta = 66.5392 + 0.0130 * t + 1.5419 * e1.cos() + 0.0239 * e2.cos() - 0.0278 * e3.cos() + 0.0068 * e4.cos()
        - 0.0029 * e6.cos()
        + 0.0009 * e7.cos()
        + 0.0008 * e10.cos()
        - 0.0009 * e13.cos();
    let w = 38.3213 + 13.176_358_15 * d - 1.4e-12 * d * d + 3.5610 * e1.sin() + 0.1208 * e2.sin() - 0.0642 * e3.sin()
        + 0.0158 * e4.sin()
        + 0.0252 * e5.sin()
        - 0.0066 * e6.sin()
        - 0.0047 * e7.sin()
        - 0.0046 * e8.sin()
        + 0.0028 * e9.sin()
        + 0.0052 * e10.sin()
        + 0.0040 * e11.sin()
        + 0.0019 * e12.sin()
        - 0.0044 * e13.sin();
    (alpha, delta, w.rem_euclid(360.0))
}

/// sin and cos of an E angle.
#[derive(Clone, Copy)]
struct Angle((f64, f64));

impl Angle {
    fn sin(self) -> f64 {
        self.0.0
    }
    fn cos(self) -> f64 {
        self.0.1
    }
}

/// Rotates a J2000 equatorial vector into the lunar body-fixed frame:
/// Rz(W)·Rx(90° − δ0)·Rz(90° + α0) as frame rotations.
pub fn to_body_fixed(v: [f64; 3], d: f64) -> [f64; 3] {
    crate::geocentric::mat_vec(&body_fixed_matrix(d), v)
}

/// The matrix of [`to_body_fixed`].
pub fn body_fixed_matrix(d: f64) -> [[f64; 3]; 3] {
    let (alpha, delta, w) = orientation_deg(d);
    let frame_z = |a: f64, v: [f64; 3]| {
        let (s, c) = a.to_radians().sin_cos();
        [c * v[0] + s * v[1], -s * v[0] + c * v[1], v[2]]
    };
    let frame_x = |a: f64, v: [f64; 3]| {
        let (s, c) = a.to_radians().sin_cos();
        [v[0], c * v[1] + s * v[2], -s * v[1] + c * v[2]]
    };
    crate::geocentric::matrix_of(|v| frame_z(w, frame_x(90.0 - delta, frame_z(90.0 + alpha, v))))
}

/// The Sun and the Earth from the Moon's centre at one instant, lunar body-fixed frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LunarSky {
    /// The Sun: unit direction and distance (AU).
    pub sun: SunState,
    /// The Earth.
    pub earth: EarthView,
}

/// The lunar sky at `epoch`.
pub fn sky(epoch: Epoch) -> LunarSky {
    sky_at_jd_tt(epoch.to_jde_tt_days())
}

/// The lunar sky at TT Julian date `jd_tt`.
pub fn sky_at_jd_tt(jd_tt: f64) -> LunarSky {
    let t = centuries(jd_tt);
    let d = jd_tt - J2000_JD_TT;
    // Mean equator of date → J2000 → lunar body-fixed, one matrix for both bodies.
    let m = mat_mul(&body_fixed_matrix(d), &precession_to_j2000(t));
    let moon = moon_mean_of_date_km(t);
    let sun = sun_mean_of_date_au(t);
    let moon_au: [f64; 3] = std::array::from_fn(|i| moon[i] / AU_KM);
    let sun_from_moon: [f64; 3] = std::array::from_fn(|i| sun[i] - moon_au[i]);
    let earth_from_moon = [-moon[0], -moon[1], -moon[2]];
    let unit = |v: [f64; 3]| {
        let n = dot(v, v).sqrt();
        ([v[0] / n, v[1] / n, v[2] / n], n)
    };
    let (sun_dir, sun_au) = unit(mat_vec(&m, sun_from_moon));
    let (earth_dir, earth_km) = unit(mat_vec(&m, earth_from_moon));
    LunarSky {
        sun: SunState { direction_body_fixed: sun_dir, distance_au: sun_au },
        earth: EarthView { direction_body_fixed: earth_dir, distance_km: earth_km },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Meeus Example 53.a (1992 April 12, 0h TD): total librations l = −1.23°,
    /// b = +4.20° (optical −1.206°/+4.194° plus physical) — the sub-Earth point — and the
    /// selenographic position of the Sun l0 = 67.89°, b0 = +1.46°. Meeus computes them
    /// from Eckhardt's libration theory, not the IAU model: an independent check of the
    /// whole chain (lunar theory, solar theory, precession, IAU rotation). areo gives
    /// l −1.229°, b 4.173°, l0 67.894°, b0 1.451°: the latitudes differ by 0.027° and
    /// 0.009° (the two rotation models disagree at that level; docs/bodies.md).
    #[test]
    fn sub_earth_and_sub_solar_points_match_meeus_example_53a() {
        let s = sky_at_jd_tt(2_448_724.5);
        let (b, l) = s.earth.sub_point_deg();
        assert!((l + 1.23).abs() < 0.01, "l {l}");
        assert!((b - 4.20).abs() < 0.03, "b {b}");
        let (b0, l0) = s.sun.subsolar_deg();
        assert!((l0 - 67.89).abs() < 0.01, "l0 {l0}");
        assert!((b0 - 1.46).abs() < 0.015, "b0 {b0}");
        assert!((s.earth.distance_km - 368_409.7).abs() < 1.0);
    }
}

/// Chebyshev coefficients per granule (degree 12 over a day: the sky's fastest term,
/// the Sun's 12°/day turn in the lunar frame, is then fitted to ~1e-13).
const CHEB: usize = 13;
/// Tabulated functions: Sun direction (3) and distance, Earth direction (3) and distance.
const FUNCS: usize = 8;

/// The lunar sky over a span, tabulated as Chebyshev series one day at a time, as
/// SPICE kernels store ephemerides: an evaluation costs a few hundred multiply-adds
/// instead of the 120-term lunar theory, and agrees with [`sky`] to better than
/// 1e-8° and 1 cm (test `the_table_is_the_theory`). Instants outside the span fall back to the
/// theory.
#[derive(Debug, Clone)]
pub struct SkyTable {
    start_jd_tt: f64,
    granules: Vec<[[f64; CHEB]; FUNCS]>,
}

impl SkyTable {
    /// The table from `start` to `end` (whole days, at least one).
    pub fn new(start: Epoch, end: Epoch) -> SkyTable {
        let start_jd_tt = start.to_jde_tt_days();
        let days = (end.to_jde_tt_days() - start_jd_tt).ceil().max(1.0) as usize;
        let nodes: [f64; CHEB] = std::array::from_fn(|k| (std::f64::consts::PI * (k as f64 + 0.5) / CHEB as f64).cos());
        let granules = (0..days)
            .map(|g| {
                let samples: [[f64; FUNCS]; CHEB] = std::array::from_fn(|k| {
                    let s = sky_at_jd_tt(start_jd_tt + g as f64 + 0.5 * (nodes[k] + 1.0));
                    let (sd, ed) = (s.sun.direction_body_fixed, s.earth.direction_body_fixed);
                    [sd[0], sd[1], sd[2], s.sun.distance_au, ed[0], ed[1], ed[2], s.earth.distance_km]
                });
                std::array::from_fn(|f| {
                    std::array::from_fn(|j| {
                        let sum: f64 = (0..CHEB)
                            .map(|k| {
                                samples[k][f] * (std::f64::consts::PI * j as f64 * (k as f64 + 0.5) / CHEB as f64).cos()
                            })
                            .sum();
                        sum * if j == 0 { 1.0 } else { 2.0 } / CHEB as f64
                    })
                })
            })
            .collect();
        SkyTable { start_jd_tt, granules }
    }

    /// The lunar sky at `epoch`.
    pub fn sky(&self, epoch: Epoch) -> LunarSky {
        self.sky_at_jd_tt(epoch.to_jde_tt_days())
    }

    /// The lunar sky at TT Julian date `jd_tt`.
    pub fn sky_at_jd_tt(&self, jd_tt: f64) -> LunarSky {
        let u = jd_tt - self.start_jd_tt;
        let g = u.floor();
        if !(g >= 0.0 && (g as usize) < self.granules.len()) {
            return sky_at_jd_tt(jd_tt);
        }
        let c = &self.granules[g as usize];
        let x = 2.0 * (u - g) - 1.0;
        // Clenshaw's recurrence for all functions at once.
        let (mut b1, mut b2) = ([0.0; FUNCS], [0.0; FUNCS]);
        for j in (1..CHEB).rev() {
            for f in 0..FUNCS {
                let b0 = 2.0 * x * b1[f] - b2[f] + c[f][j];
                b2[f] = b1[f];
                b1[f] = b0;
            }
        }
        let v: [f64; FUNCS] = std::array::from_fn(|f| x * b1[f] - b2[f] + c[f][0]);
        let unit = |a: f64, b: f64, c: f64| {
            let n = (a * a + b * b + c * c).sqrt();
            [a / n, b / n, c / n]
        };
        LunarSky {
            sun: SunState { direction_body_fixed: unit(v[0], v[1], v[2]), distance_au: v[3] },
            earth: EarthView { direction_body_fixed: unit(v[4], v[5], v[6]), distance_km: v[7] },
        }
    }
}

impl crate::SunModel for SkyTable {
    fn sun(&self, epoch: Epoch) -> SunState {
        self.sky(epoch).sun
    }

    fn body(&self) -> crate::Body {
        crate::Body::Moon
    }
}

#[cfg(test)]
mod table_tests {
    use super::*;

    #[test]
    fn the_table_is_the_theory() {
        let start = crate::parse_utc("2025-01-01T00:00:00Z").unwrap();
        let end = start + hifitime::Duration::from_days(40.0);
        let table = SkyTable::new(start, end);
        let angle = |a: [f64; 3], b: [f64; 3]| {
            let c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            let cross = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
            dot(cross, cross).sqrt().atan2(c).to_degrees()
        };
        let mut worst = (0.0f64, 0.0f64, 0.0f64);
        for k in 0..4000 {
            let jd = start.to_jde_tt_days() + k as f64 * 0.01 + 0.003;
            let (t, d) = (table.sky_at_jd_tt(jd), sky_at_jd_tt(jd));
            worst.0 = worst.0.max(angle(t.sun.direction_body_fixed, d.sun.direction_body_fixed));
            worst.1 = worst.1.max(angle(t.earth.direction_body_fixed, d.earth.direction_body_fixed));
            worst.2 = worst.2.max((t.earth.distance_km - d.earth.distance_km).abs());
        }
        assert!(worst.0 < 1e-8 && worst.1 < 1e-8 && worst.2 < 1e-5, "{worst:?}");
        // Outside the span, the theory itself.
        let later = end.to_jde_tt_days() + 3.0;
        assert_eq!(table.sky_at_jd_tt(later), sky_at_jd_tt(later));
    }
}
