//! The Sun and the Moon seen from the Earth's centre, from the truncated analytic
//! theories of Meeus, *Astronomical Algorithms* (2nd ed., 1998): chapter 25 for the
//! Sun (≈ 0.01°, distance ≈ 1e-5 AU), chapter 47 for the Moon (the truncated ELP-2000/82
//! of Chapront: ≈ 10″ in longitude, 4″ in latitude), chapter 22 for nutation and the
//! obliquity, chapter 21 for precession to the J2000 equator (ICRF to well under the
//! theories' errors).
//!
//! Time is TT Julian centuries since J2000 (TDB is taken as TT: they differ by under
//! 2 ms). Vectors are in the mean equator and equinox of J2000, which is the frame the
//! IAU rotation models of the Moon and Mars start from.

/// A point in the mean ecliptic of date: longitude and latitude (degrees) and distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ecliptic {
    /// Ecliptic longitude, degrees [0, 360).
    pub lon_deg: f64,
    /// Ecliptic latitude, degrees.
    pub lat_deg: f64,
    /// Distance from the Earth's centre (AU for the Sun, km for the Moon).
    pub distance: f64,
}

/// The Sun's geocentric position (Meeus ch. 25): apparent longitude (aberration
/// included, nutation not), latitude 0, distance in AU; `t` in TT Julian centuries
/// since J2000.
pub fn sun_ecliptic(t: f64) -> Ecliptic {
    let l0 = 280.466_46 + 36_000.769_83 * t + 0.000_303_2 * t * t;
    let m = 357.529_11 + 35_999.050_29 * t - 0.000_153_7 * t * t;
    let mr = m.to_radians();
    let c = (1.914_602 - 0.004_817 * t - 0.000_014 * t * t) * mr.sin()
        + (0.019_993 - 0.000_101 * t) * (2.0 * mr).sin()
        + 0.000_289 * (3.0 * mr).sin();
    let true_lon = l0 + c;
    let r = sun_distance_au(t);
    // Annual aberration, −20.4898″ / R.
    let aberration = -20.4898 / 3600.0 / r;
    Ecliptic { lon_deg: (true_lon + aberration).rem_euclid(360.0), lat_deg: 0.0, distance: r }
}

/// The Earth's heliocentric radius vector (the Sun's distance from the Earth's centre),
/// AU, from the VSOP87 series truncated as in Meeus's appendix III and NREL's SPA
/// (Reda & Andreas 2004, table A4.2): terms (A × 1e-8 AU, B rad, C rad per Julian
/// millennium), summed as R0 + R1 τ + R2 τ² + R3 τ³ + R4 τ⁴. The Keplerian ellipse of
/// chapter 25 misses the Moon's pull on the Earth (±3e-5 AU over a month) and the
/// planets' (about as much); these terms hold them, to about 1e-7 AU of VSOP87.
/// `t` in TT Julian centuries since J2000.
pub fn sun_distance_au(t: f64) -> f64 {
    let tau = t / 10.0;
    let series = |terms: &[(f64, f64, f64)]| terms.iter().map(|(a, b, c)| a * (b + c * tau).cos()).sum::<f64>();
    let mut r = 0.0;
    for terms in EARTH_R.iter().rev() {
        r = r * tau + series(terms);
    }
    r * 1e-8
}

/// VSOP87 R0..R4 for the Earth, as truncated by Meeus (appendix III) and NREL's SPA.
// The phases are the table's printed values (3.142, 3.14), not π.
#[allow(clippy::approx_constant)]
const EARTH_R: [&[(f64, f64, f64)]; 5] = [
    &[
        (100_013_989.0, 0.0, 0.0),
        (1_670_700.0, 3.098_463_5, 6_283.075_85),
        (13_956.0, 3.055_25, 12_566.151_7),
        (3_084.0, 5.198_5, 77_713.771_5),
        (1_628.0, 1.173_9, 5_753.384_9),
        (1_576.0, 2.846_9, 7_860.419_4),
        (925.0, 5.453, 11_506.77),
        (542.0, 4.564, 3_930.21),
        (472.0, 3.661, 5_884.927),
        (346.0, 0.964, 5_507.553),
        (329.0, 5.9, 5_223.694),
        (307.0, 0.299, 5_573.143),
        (243.0, 4.273, 11_790.629),
        (212.0, 5.847, 1_577.344),
        (186.0, 5.022, 10_977.079),
        (175.0, 3.012, 18_849.228),
        (110.0, 5.055, 5_486.778),
        (98.0, 0.89, 6_069.78),
        (86.0, 5.69, 15_720.84),
        (86.0, 1.27, 161_000.69),
        (65.0, 0.27, 17_260.15),
        (63.0, 0.92, 529.69),
        (57.0, 2.01, 83_996.85),
        (56.0, 5.24, 71_430.7),
        (49.0, 3.25, 2_544.31),
        (47.0, 2.58, 775.52),
        (45.0, 5.54, 9_437.76),
        (43.0, 6.01, 6_275.96),
        (39.0, 5.36, 4_694.0),
        (38.0, 2.39, 8_827.39),
        (37.0, 0.83, 19_651.05),
        (37.0, 4.9, 12_139.55),
        (36.0, 1.67, 12_036.46),
        (35.0, 1.84, 2_942.46),
        (33.0, 0.24, 7_084.9),
        (32.0, 0.18, 5_088.63),
        (32.0, 1.78, 398.15),
        (28.0, 1.21, 6_286.6),
        (28.0, 1.9, 6_279.55),
        (26.0, 4.59, 10_447.39),
    ],
    &[
        (103_019.0, 1.107_49, 6_283.075_85),
        (1_721.0, 1.064_4, 12_566.151_7),
        (702.0, 3.142, 0.0),
        (32.0, 1.02, 18_849.23),
        (31.0, 2.84, 5_507.55),
        (25.0, 1.32, 5_223.69),
        (18.0, 1.42, 1_577.34),
        (10.0, 5.91, 10_977.08),
        (9.0, 1.42, 6_275.96),
        (9.0, 0.27, 5_486.78),
    ],
    &[
        (4_359.0, 5.784_6, 6_283.075_8),
        (124.0, 5.579, 12_566.152),
        (12.0, 3.14, 0.0),
        (9.0, 3.63, 77_713.77),
        (6.0, 1.87, 5_573.14),
        (3.0, 5.47, 18_849.23),
    ],
    &[(145.0, 4.273, 6_283.076), (7.0, 3.92, 12_566.15)],
    &[(4.0, 2.56, 6_283.08)],
];

/// Meeus table 47.A: multiples of D, M, M′, F; Σl (1e-6°) and Σr (1e-3 km).
const MOON_LON_DIST: [(i8, i8, i8, i8, i32, i32); 60] = [
    (0, 0, 1, 0, 6_288_774, -20_905_355),
    (2, 0, -1, 0, 1_274_027, -3_699_111),
    (2, 0, 0, 0, 658_314, -2_955_968),
    (0, 0, 2, 0, 213_618, -569_925),
    (0, 1, 0, 0, -185_116, 48_888),
    (0, 0, 0, 2, -114_332, -3_149),
    (2, 0, -2, 0, 58_793, 246_158),
    (2, -1, -1, 0, 57_066, -152_138),
    (2, 0, 1, 0, 53_322, -170_733),
    (2, -1, 0, 0, 45_758, -204_586),
    (0, 1, -1, 0, -40_923, -129_620),
    (1, 0, 0, 0, -34_720, 108_743),
    (0, 1, 1, 0, -30_383, 104_755),
    (2, 0, 0, -2, 15_327, 10_321),
    (0, 0, 1, 2, -12_528, 0),
    (0, 0, 1, -2, 10_980, 79_661),
    (4, 0, -1, 0, 10_675, -34_782),
    (0, 0, 3, 0, 10_034, -23_210),
    (4, 0, -2, 0, 8_548, -21_636),
    (2, 1, -1, 0, -7_888, 24_208),
    (2, 1, 0, 0, -6_766, 30_824),
    (1, 0, -1, 0, -5_163, -8_379),
    (1, 1, 0, 0, 4_987, -16_675),
    (2, -1, 1, 0, 4_036, -12_831),
    (2, 0, 2, 0, 3_994, -10_445),
    (4, 0, 0, 0, 3_861, -11_650),
    (2, 0, -3, 0, 3_665, 14_403),
    (0, 1, -2, 0, -2_689, -7_003),
    (2, 0, -1, 2, -2_602, 0),
    (2, -1, -2, 0, 2_390, 10_056),
    (1, 0, 1, 0, -2_348, 6_322),
    (2, -2, 0, 0, 2_236, -9_884),
    (0, 1, 2, 0, -2_120, 5_751),
    (0, 2, 0, 0, -2_069, 0),
    (2, -2, -1, 0, 2_048, -4_950),
    (2, 0, 1, -2, -1_773, 4_130),
    (2, 0, 0, 2, -1_595, 0),
    (4, -1, -1, 0, 1_215, -3_958),
    (0, 0, 2, 2, -1_110, 0),
    (3, 0, -1, 0, -892, 3_258),
    (2, 1, 1, 0, -810, 2_616),
    (4, -1, -2, 0, 759, -1_897),
    (0, 2, -1, 0, -713, -2_117),
    (2, 2, -1, 0, -700, 2_354),
    (2, 1, -2, 0, 691, 0),
    (2, -1, 0, -2, 596, 0),
    (4, 0, 1, 0, 549, -1_423),
    (0, 0, 4, 0, 537, -1_117),
    (4, -1, 0, 0, 520, -1_571),
    (1, 0, -2, 0, -487, -1_739),
    (2, 1, 0, -2, -399, 0),
    (0, 0, 2, -2, -381, -4_421),
    (1, 1, 1, 0, 351, 0),
    (3, 0, -2, 0, -340, 0),
    (4, 0, -3, 0, 330, 0),
    (2, -1, 2, 0, 327, 0),
    (0, 2, 1, 0, -323, 1_165),
    (1, 1, -1, 0, 299, 0),
    (2, 0, 3, 0, 294, 0),
    (2, 0, -1, -2, 0, 8_752),
];

/// Meeus table 47.B: multiples of D, M, M′, F; Σb (1e-6°).
const MOON_LAT: [(i8, i8, i8, i8, i32); 60] = [
    (0, 0, 0, 1, 5_128_122),
    (0, 0, 1, 1, 280_602),
    (0, 0, 1, -1, 277_693),
    (2, 0, 0, -1, 173_237),
    (2, 0, -1, 1, 55_413),
    (2, 0, -1, -1, 46_271),
    (2, 0, 0, 1, 32_573),
    (0, 0, 2, 1, 17_198),
    (2, 0, 1, -1, 9_266),
    (0, 0, 2, -1, 8_822),
    (2, -1, 0, -1, 8_216),
    (2, 0, -2, -1, 4_324),
    (2, 0, 1, 1, 4_200),
    (2, 1, 0, -1, -3_359),
    (2, -1, -1, 1, 2_463),
    (2, -1, 0, 1, 2_211),
    (2, -1, -1, -1, 2_065),
    (0, 1, -1, -1, -1_870),
    (4, 0, -1, -1, 1_828),
    (0, 1, 0, 1, -1_794),
    (0, 0, 0, 3, -1_749),
    (0, 1, -1, 1, -1_565),
    (1, 0, 0, 1, -1_491),
    (0, 1, 1, 1, -1_475),
    (0, 1, 1, -1, -1_410),
    (0, 1, 0, -1, -1_344),
    (1, 0, 0, -1, -1_335),
    (0, 0, 3, 1, 1_107),
    (4, 0, 0, -1, 1_021),
    (4, 0, -1, 1, 833),
    (0, 0, 1, -3, 777),
    (4, 0, -2, 1, 671),
    (2, 0, 0, -3, 607),
    (2, 0, 2, -1, 596),
    (2, -1, 1, -1, 491),
    (2, 0, -2, 1, -451),
    (0, 0, 3, -1, 439),
    (2, 0, 2, 1, 422),
    (2, 0, -3, -1, 421),
    (2, 1, -1, 1, -366),
    (2, 1, 0, 1, -351),
    (4, 0, 0, 1, 331),
    (2, -1, 1, 1, 315),
    (2, -2, 0, -1, 302),
    (0, 0, 1, 3, -283),
    (2, 1, 1, -1, -229),
    (1, 1, 0, -1, 223),
    (1, 1, 0, 1, 223),
    (0, 1, -2, -1, -220),
    (2, 1, -1, -1, -220),
    (1, 0, 1, 1, -185),
    (2, -1, -2, -1, 181),
    (0, 1, 2, 1, -177),
    (4, 0, -2, -1, 176),
    (4, -1, -1, -1, 166),
    (1, 0, 1, -1, -164),
    (4, 0, 1, -1, 132),
    (1, 0, -1, -1, -119),
    (4, -1, 0, -1, 115),
    (2, -2, 0, 1, 107),
];

/// The Moon's geocentric position (Meeus ch. 47): mean ecliptic and equinox of date,
/// no nutation, distance in km between the centres; `t` in TT Julian centuries since
/// J2000.
pub fn moon_ecliptic(t: f64) -> Ecliptic {
    let (t2, t3, t4) = (t * t, t * t * t, t * t * t * t);
    let lp = 218.316_447_7 + 481_267.881_234_21 * t - 0.001_578_6 * t2 + t3 / 538_841.0 - t4 / 65_194_000.0;
    let d = 297.850_192_1 + 445_267.111_403_4 * t - 0.001_881_9 * t2 + t3 / 545_868.0 - t4 / 113_065_000.0;
    let m = 357.529_109_2 + 35_999.050_290_9 * t - 0.000_153_6 * t2 + t3 / 24_490_000.0;
    let mp = 134.963_396_4 + 477_198.867_505_5 * t + 0.008_741_4 * t2 + t3 / 69_699.0 - t4 / 14_712_000.0;
    let f = 93.272_095_0 + 483_202.017_523_3 * t - 0.003_653_9 * t2 - t3 / 3_526_000.0 + t4 / 863_310_000.0;
    let a1 = 119.75 + 131.849 * t;
    let a2 = 53.09 + 479_264.290 * t;
    let a3 = 313.45 + 481_266.484 * t;
    // The Earth's orbital eccentricity shrinks: terms in M are scaled by E, in 2M by E².
    let e = 1.0 - 0.002_516 * t - 0.000_007_4 * t2;
    // Every argument is a sum of small multiples of D, M, M′ and F: its sine and cosine
    // come from products of the multiples' unit phasors (four sin/cos in all instead
    // of 180).
    let d_k = Phasors::<4>::new(d.to_radians());
    // The M phasors carry E^|k| in their length.
    let m_k = Phasors::<2>::scaled(m.to_radians(), e);
    let mp_k = Phasors::<4>::new(mp.to_radians());
    let f_k = Phasors::<3>::new(f.to_radians());
    // Products D·M (kd 0..=4, km −2..=2) and M′·F (kmp −4..=4, kf −3..=3) once; each
    // term is then one product.
    let dm: [[(f64, f64); 5]; 5] =
        std::array::from_fn(|kd| std::array::from_fn(|j| mul(d_k.get(kd as i8), m_k.get(j as i8 - 2))));
    let pf: [[(f64, f64); 7]; 9] =
        std::array::from_fn(|i| std::array::from_fn(|j| mul(mp_k.get(i as i8 - 4), f_k.get(j as i8 - 3))));
    let halves = |kd: i8, km: i8, kmp: i8, kf: i8| {
        (dm[kd as usize][(km + 2) as usize], pf[(kmp + 4) as usize][(kf + 3) as usize])
    };
    let (mut sl, mut sr, mut sb) = (0.0, 0.0, 0.0);
    for &(kd, km, kmp, kf, l, r) in &MOON_LON_DIST {
        let (c, s) = {
            let (a, b) = halves(kd, km, kmp, kf);
            mul(a, b)
        };
        sl += f64::from(l) * s;
        sr += f64::from(r) * c;
    }
    for &(kd, km, kmp, kf, b) in &MOON_LAT {
        let (x, y) = halves(kd, km, kmp, kf);
        sb += f64::from(b) * (x.0 * y.1 + x.1 * y.0);
    }
    // Amplitudes ≤ 0.004°: the polynomial sine's 3e-8 is far below the theory's error.
    let sind = |x: f64| crate::sun::sin_cos_deg_small(x).0;
    // Venus (A1), Jupiter (A2) and the Earth's flattening (L′ − F).
    sl += 3958.0 * sind(a1) + 1962.0 * sind(lp - f) + 318.0 * sind(a2);
    sb += -2235.0 * sind(lp) + 382.0 * sind(a3) + 175.0 * sind(a1 - f) + 175.0 * sind(a1 + f) + 127.0 * sind(lp - mp)
        - 115.0 * sind(lp + mp);
    Ecliptic { lon_deg: (lp + sl / 1e6).rem_euclid(360.0), lat_deg: sb / 1e6, distance: 385_000.56 + sr / 1000.0 }
}

/// r^|k|·(cos k·x, sin k·x) for −N ≤ k ≤ N (N ≤ 4), indexed by k + 4.
struct Phasors<const N: usize> {
    all: [(f64, f64); 9],
}

impl<const N: usize> Phasors<N> {
    fn new(x: f64) -> Self {
        Phasors::scaled(x, 1.0)
    }

    fn scaled(x: f64, r: f64) -> Self {
        let (s, c) = x.sin_cos();
        let mut all = [(1.0, 0.0); 9];
        for k in 1..=N {
            let (pc, ps) = mul(all[4 + k - 1], (c, s));
            all[4 + k] = (pc * r, ps * r);
            all[4 - k] = (pc * r, -ps * r);
        }
        Phasors { all }
    }

    #[inline]
    fn get(&self, k: i8) -> (f64, f64) {
        self.all[(k + 4) as usize]
    }
}

/// The product of two unit phasors (cos a, sin a)·(cos b, sin b) = (cos, sin) of a + b.
fn mul(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

/// Mean obliquity of the ecliptic ε0 (Meeus 22.2, IAU 1980), degrees.
pub fn mean_obliquity_deg(t: f64) -> f64 {
    23.439_291_111 - (46.8150 * t + 0.000_59 * t * t - 0.001_813 * t * t * t) / 3600.0
}

/// Nutation in longitude Δψ and in obliquity Δε (Meeus ch. 22, the four-term form good
/// to 0.5″ and 0.1″), degrees.
pub fn nutation_deg(t: f64) -> (f64, f64) {
    let omega = (125.044_52 - 1_934.136_261 * t).to_radians();
    let l_sun = (280.4665 + 36_000.769_8 * t).to_radians();
    let l_moon = (218.3165 + 481_267.881_3 * t).to_radians();
    let dpsi =
        -17.20 * omega.sin() - 1.32 * (2.0 * l_sun).sin() - 0.23 * (2.0 * l_moon).sin() + 0.21 * (2.0 * omega).sin();
    let deps =
        9.20 * omega.cos() + 0.57 * (2.0 * l_sun).cos() + 0.10 * (2.0 * l_moon).cos() - 0.09 * (2.0 * omega).cos();
    (dpsi / 3600.0, deps / 3600.0)
}

/// Cartesian coordinates of an ecliptic point rotated to the equator by `obliquity_deg`.
pub fn ecliptic_to_equatorial(p: &Ecliptic, obliquity_deg: f64) -> [f64; 3] {
    let (sl, cl) = p.lon_deg.to_radians().sin_cos();
    let (sb, cb) = p.lat_deg.to_radians().sin_cos();
    let (se, ce) = obliquity_deg.to_radians().sin_cos();
    let (x, y, z) = (cb * cl, cb * sl, sb);
    let r = p.distance;
    [r * x, r * (ce * y - se * z), r * (se * y + ce * z)]
}

/// Right ascension (degrees [0, 360)) and declination (degrees) of an equatorial vector.
pub fn ra_dec_deg(v: [f64; 3]) -> (f64, f64) {
    let rho = (v[0] * v[0] + v[1] * v[1]).sqrt();
    (v[1].atan2(v[0]).to_degrees().rem_euclid(360.0), v[2].atan2(rho).to_degrees())
}

/// Rotates a vector in the mean equator and equinox of date `t` to the mean equator
/// and equinox of J2000 (IAU 1976 precession, Meeus 21.2–21.4 with the angles' signs
/// taken back).
pub fn precess_to_j2000(v: [f64; 3], t: f64) -> [f64; 3] {
    mat_vec(&precession_to_j2000(t), v)
}

/// The matrix of [`precess_to_j2000`].
pub fn precession_to_j2000(t: f64) -> [[f64; 3]; 3] {
    let arcsec = |a: f64| (a / 3600.0).to_radians();
    let zeta = arcsec(2306.2181 * t + 0.301_88 * t * t + 0.017_998 * t * t * t);
    let z = arcsec(2306.2181 * t + 1.094_68 * t * t + 0.018_203 * t * t * t);
    let theta = arcsec(2004.3109 * t - 0.426_65 * t * t - 0.041_833 * t * t * t);
    // J2000 → date adds ζ to the right ascension, tilts by θ and adds z (Meeus 21.4):
    // Rz(z)·Ry(−θ)·Rz(ζ) as active rotations; date → J2000 is its transpose.
    matrix_of(|v| rot_z(-zeta, rot_y(theta, rot_z(-z, v))))
}

/// The matrix of a linear map, from its images of the unit vectors (its columns).
pub(crate) fn matrix_of(f: impl Fn([f64; 3]) -> [f64; 3]) -> [[f64; 3]; 3] {
    let (c0, c1, c2) = (f([1.0, 0.0, 0.0]), f([0.0, 1.0, 0.0]), f([0.0, 0.0, 1.0]));
    [[c0[0], c1[0], c2[0]], [c0[1], c1[1], c2[1]], [c0[2], c1[2], c2[2]]]
}

/// m·v.
pub fn mat_vec(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

/// a·b.
pub fn mat_mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j]))
}

/// Active rotation of `v` by `a` radians about z.
pub(crate) fn rot_z(a: f64, v: [f64; 3]) -> [f64; 3] {
    let (s, c) = a.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]
}

/// Active rotation of `v` by `a` radians about y.
fn rot_y(a: f64, v: [f64; 3]) -> [f64; 3] {
    let (s, c) = a.sin_cos();
    [c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]]
}

/// The Sun's geocentric position vector in the mean equator of date, AU (aberration
/// included, nutation not).
pub fn sun_mean_of_date_au(t: f64) -> [f64; 3] {
    ecliptic_to_equatorial(&sun_ecliptic(t), mean_obliquity_deg(t))
}

/// The Moon's geocentric position vector in the mean equator of date, km.
pub fn moon_mean_of_date_km(t: f64) -> [f64; 3] {
    ecliptic_to_equatorial(&moon_ecliptic(t), mean_obliquity_deg(t))
}

/// TT Julian centuries since J2000 of a TT Julian date.
pub fn centuries(jd_tt: f64) -> f64 {
    (jd_tt - 2_451_545.0) / 36_525.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Meeus Example 47.a: 1992 April 12, 0h TD.
    #[test]
    fn moon_reproduces_meeus_example_47a() {
        let t = centuries(2_448_724.5);
        let p = moon_ecliptic(t);
        assert!((p.lon_deg - 133.162_655).abs() < 2e-6, "{}", p.lon_deg);
        assert!((p.lat_deg + 3.229_126).abs() < 2e-6, "{}", p.lat_deg);
        assert!((p.distance - 368_409.7).abs() < 0.1, "{}", p.distance);
        // Apparent right ascension and declination: nutation in longitude, true obliquity.
        let (dpsi, deps) = nutation_deg(t);
        let app = Ecliptic { lon_deg: p.lon_deg + dpsi, ..p };
        let (ra, dec) = ra_dec_deg(ecliptic_to_equatorial(&app, mean_obliquity_deg(t) + deps));
        assert!((ra - 134.688_470).abs() < 2e-4, "{ra}");
        assert!((dec - 13.768_368).abs() < 2e-4, "{dec}");
    }

    /// Meeus Example 25.a: 1992 October 13.0 TD, against the full VSOP87 values the
    /// book gives for the same instant (α 198.378178°, δ −7.783871°, R 0.99760775 AU).
    #[test]
    fn sun_matches_vsop87_in_meeus_example_25a() {
        let t = centuries(2_448_908.5);
        let p = sun_ecliptic(t);
        // The truncated VSOP87 radius series (chapter 25's ellipse was 5.4e-5 AU off).
        assert!((p.distance - 0.997_607_75).abs() < 2e-7, "{}", p.distance);
        let (dpsi, deps) = nutation_deg(t);
        let app = Ecliptic { lon_deg: p.lon_deg + dpsi, ..p };
        let (ra, dec) = ra_dec_deg(ecliptic_to_equatorial(&app, mean_obliquity_deg(t) + deps));
        assert!((ra - 198.378_178).abs() < 0.005, "{ra}");
        assert!((dec + 7.783_871).abs() < 0.005, "{dec}");
    }

    #[test]
    fn precession_over_a_century_is_the_general_precession() {
        // A point on the equator of date at the equinox moves by about 1.40° per
        // century in J2000 coordinates (5029″/century general precession in longitude).
        let t = 1.0;
        let v = precess_to_j2000([1.0, 0.0, 0.0], t);
        let (ra, dec) = ra_dec_deg(v);
        let ra = if ra > 180.0 { ra - 360.0 } else { ra };
        assert!((ra + 1.2811).abs() < 0.01, "{ra}");
        assert!((dec + 0.5567).abs() < 0.01, "{dec}");
        let back = precess_to_j2000(v, 0.0);
        assert!((back[0] - v[0]).abs() < 1e-15);
    }
}
