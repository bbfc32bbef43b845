//! Synthesised terrain from a description (the RON `terrain` block of every shipped
//! scenario): craters, hills, ridges, N–S mountain chains with passes, ditches, rocks,
//! tilts and seeded fractal noise, summed on a base height.
//!
//! Coordinates are metres in the DEM's local frame, whose south-west corner is (0, 0):
//! x east, y north.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::dem::Dem;
use crate::error::{Error, Result};

/// The largest position or horizontal size a description may give, m (10 000 km: more
/// than any body's circumference is nonsense, and keeps every product finite).
const MAX_LENGTH_M: f64 = 1e7;
/// The largest height, depth or relief, m.
const MAX_HEIGHT_M: f64 = 1e5;

/// A terrain to synthesise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainSpec {
    /// Columns (west to east), 1..=20000.
    pub cols: usize,
    /// Rows (north to south), 1..=20000.
    pub rows: usize,
    /// Cell size, m (0.001..=10000).
    pub cell_m: f64,
    /// Height everywhere before features, m (|h| ≤ 100 km).
    #[serde(default)]
    pub base_m: f64,
    /// Seed for the noise.
    #[serde(default)]
    pub seed: u64,
    /// Fractal noise added on top.
    #[serde(default)]
    pub noise: Option<Noise>,
    /// Landforms, summed.
    #[serde(default)]
    pub features: Vec<Feature>,
}

/// Seeded fractal value noise: octaves of smooth random lattices, each with half the
/// wavelength and `persistence` times the amplitude of the one before.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Noise {
    /// Amplitude of the first octave, m (≥ 0).
    pub amplitude_m: f64,
    /// Wavelength of the first octave, m (≤ 1e7; its finest octave, wavelength /
    /// 2^(octaves − 1), no finer than half a cell).
    pub wavelength_m: f64,
    /// Number of octaves, 1..=12.
    #[serde(default = "default_octaves")]
    pub octaves: u32,
    /// Amplitude ratio between octaves, 0..=1.
    #[serde(default = "default_persistence")]
    pub persistence: f64,
}

fn default_octaves() -> u32 {
    4
}
fn default_persistence() -> f64 {
    0.5
}

/// A landform.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Feature {
    /// A simple crater: a parabolic bowl `depth_m` below the surroundings, a raised rim
    /// at `radius_m`, and ejecta decaying as (R/r)³ out to `ejecta_radii` radii.
    Crater {
        /// Centre x, m.
        x_m: f64,
        /// Centre y, m.
        y_m: f64,
        /// Rim radius, m (> 0).
        radius_m: f64,
        /// Floor depth below the surroundings, m (≥ 0).
        depth_m: f64,
        /// Rim height above the surroundings, m (≥ 0).
        rim_height_m: f64,
        /// Extent of the ejecta blanket in radii (≥ 1).
        #[serde(default = "default_ejecta")]
        ejecta_radii: f64,
    },
    /// A cone whose flanks have the given slope.
    Hill {
        /// Centre x, m.
        x_m: f64,
        /// Centre y, m.
        y_m: f64,
        /// Base radius, m (> 0).
        radius_m: f64,
        /// Flank slope, degrees (0..90).
        slope_deg: f64,
    },
    /// A cone `height_m` high whose flank steepens from `west_slope_deg` on its west
    /// side to `east_slope_deg` on its east: the slope angle is west + (east − west)·w²
    /// with w = (1 + sin azimuth)/2, so most of the west half is near the gentle slope
    /// (due south and north a quarter of the way) and exactly the stated slopes lie due
    /// west and east.
    AsymmetricHill {
        /// Summit x, m.
        x_m: f64,
        /// Summit y, m.
        y_m: f64,
        /// Height, m (> 0).
        height_m: f64,
        /// Flank slope due west, degrees (0..90).
        west_slope_deg: f64,
        /// Flank slope due east, degrees (0..90).
        east_slope_deg: f64,
        /// Radius of a flat top, m (≥ 0; default 0, a point).
        #[serde(default)]
        top_radius_m: f64,
    },
    /// A straight ridge with a cosine cross-section.
    Ridge {
        /// One end (x, y), m.
        from_m: (f64, f64),
        /// Other end (x, y), m.
        to_m: (f64, f64),
        /// Crest height, m.
        height_m: f64,
        /// Full width at the base, m (> 0).
        width_m: f64,
    },
    /// A north–south mountain chain at `x_m` from `y_from_m` to `y_to_m`, with passes
    /// where the crest dips to a saddle.
    MountainChain {
        /// Crest line x, m.
        x_m: f64,
        /// South end y, m.
        y_from_m: f64,
        /// North end y, m.
        y_to_m: f64,
        /// Crest height, m.
        height_m: f64,
        /// Full width at the base, m (> 0).
        width_m: f64,
        /// Passes through the chain.
        #[serde(default)]
        passes: Vec<Pass>,
    },
    /// A straight scarp: the ground rises across the line from `from_m` to `to_m`, on its
    /// left (looking from `from_m` to `to_m`), at `slope_deg` from 0 to `height_m`, and
    /// stays at that height beyond (a plateau). Drawn across a map, its face cannot be
    /// gone around.
    Scarp {
        /// One end (x, y), m.
        from_m: (f64, f64),
        /// Other end (x, y), m; the face rises to the left of from → to.
        to_m: (f64, f64),
        /// Height of the plateau above the foot, m (> 0).
        height_m: f64,
        /// Face slope, degrees (0 exclusive..90).
        slope_deg: f64,
    },
    /// A straight ditch with a trapezoidal cross-section.
    Ditch {
        /// One end (x, y), m.
        from_m: (f64, f64),
        /// Other end (x, y), m.
        to_m: (f64, f64),
        /// Width at the top, m (> 0).
        width_m: f64,
        /// Depth, m (> 0).
        depth_m: f64,
        /// Wall angle from horizontal, degrees (0..=90); the walls must fit in the width.
        wall_deg: f64,
    },
    /// A rock: a half-ellipsoid of the given height and width.
    Rock {
        /// Centre x, m.
        x_m: f64,
        /// Centre y, m.
        y_m: f64,
        /// Height, m (> 0).
        height_m: f64,
        /// Width, m (> 0).
        width_m: f64,
    },
    /// A uniform tilt: the plane faces `aspect_deg` (its downslope azimuth).
    Tilt {
        /// Slope, degrees (0..90).
        slope_deg: f64,
        /// Downslope azimuth, degrees clockwise from north.
        aspect_deg: f64,
    },
}

fn default_ejecta() -> f64 {
    2.5
}

/// A pass in a mountain chain.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pass {
    /// Where along the chain, m (y).
    pub y_m: f64,
    /// Saddle height, m (below the crest).
    pub height_m: f64,
    /// Width of the dip along the chain, m (> 0).
    pub width_m: f64,
}

impl Feature {
    /// Checks feature `i`'s fields, naming the first bad one.
    fn validate(&self, i: usize) -> Result<()> {
        let c = FieldCheck { i };
        match self {
            Feature::Ridge { .. } | Feature::MountainChain { .. } | Feature::Scarp { .. } | Feature::Ditch { .. } => {
                self.validate_linear(&c)
            }
            _ => self.validate_local(&c),
        }
    }

    /// The features drawn about a point.
    fn validate_local(&self, c: &FieldCheck) -> Result<()> {
        match *self {
            Feature::Crater { x_m, y_m, radius_m, depth_m, rim_height_m, ejecta_radii } => {
                c.at("x_m", x_m)?;
                c.at("y_m", y_m)?;
                c.positive("radius_m", radius_m)?;
                c.depth("depth_m", depth_m)?;
                c.depth("rim_height_m", rim_height_m)?;
                if !(1.0..=100.0).contains(&ejecta_radii) {
                    return c.bad("ejecta_radii", ejecta_radii, "1..=100");
                }
            }
            Feature::Hill { x_m, y_m, radius_m, slope_deg } => {
                c.at("x_m", x_m)?;
                c.at("y_m", y_m)?;
                c.positive("radius_m", radius_m)?;
                c.slope("slope_deg", slope_deg)?;
            }
            Feature::AsymmetricHill { x_m, y_m, height_m, west_slope_deg, east_slope_deg, top_radius_m } => {
                if !(0.0..=MAX_LENGTH_M).contains(&top_radius_m) {
                    return c.bad("top_radius_m", top_radius_m, "0..=1e7 m");
                }
                c.at("x_m", x_m)?;
                c.at("y_m", y_m)?;
                c.positive("height_m", height_m)?;
                c.slope("west_slope_deg", west_slope_deg)?;
                c.slope("east_slope_deg", east_slope_deg)?;
            }
            Feature::Rock { x_m, y_m, height_m, width_m } => {
                c.at("x_m", x_m)?;
                c.at("y_m", y_m)?;
                if !(height_m > 0.0 && height_m <= MAX_HEIGHT_M) {
                    return c.bad("height_m", height_m, "0 (exclusive)..=100000 m");
                }
                c.positive("width_m", width_m)?;
            }
            Feature::Tilt { slope_deg, aspect_deg } => {
                c.slope("slope_deg", slope_deg)?;
                if !(aspect_deg.abs() <= 360.0) {
                    return c.bad("aspect_deg", aspect_deg, "-360..=360 degrees");
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// The features drawn along a line.
    fn validate_linear(&self, c: &FieldCheck) -> Result<()> {
        match *self {
            Feature::Ridge { from_m, to_m, height_m, width_m } => {
                for (name, v) in [("from_m", from_m.0), ("from_m", from_m.1), ("to_m", to_m.0), ("to_m", to_m.1)] {
                    c.at(name, v)?;
                }
                c.height("height_m", height_m)?;
                c.positive("width_m", width_m)?;
            }
            Feature::MountainChain { x_m, y_from_m, y_to_m, height_m, width_m, ref passes } => {
                c.at("x_m", x_m)?;
                c.at("y_from_m", y_from_m)?;
                c.at("y_to_m", y_to_m)?;
                c.height("height_m", height_m)?;
                c.positive("width_m", width_m)?;
                for (k, pass) in passes.iter().enumerate() {
                    let q = |name: &str| format!("passes[{k}].{name}");
                    if !(pass.y_m.abs() <= MAX_LENGTH_M) {
                        return c.bad(&q("y_m"), pass.y_m, "-1e7..=1e7 m");
                    }
                    if !(pass.height_m.abs() <= MAX_HEIGHT_M) {
                        return c.bad(&q("height_m"), pass.height_m, "-100000..=100000 m");
                    }
                    if !(pass.width_m > 0.0 && pass.width_m <= MAX_LENGTH_M) {
                        return c.bad(&q("width_m"), pass.width_m, "0 (exclusive)..=1e7 m");
                    }
                }
            }
            Feature::Scarp { from_m, to_m, height_m, slope_deg } => {
                for (name, v) in [("from_m", from_m.0), ("from_m", from_m.1), ("to_m", to_m.0), ("to_m", to_m.1)] {
                    c.at(name, v)?;
                }
                if from_m == to_m {
                    return c.bad("to_m", to_m.0, "a point different from from_m");
                }
                c.positive("height_m", height_m)?;
                c.slope("slope_deg", slope_deg)?;
                if !(slope_deg > 0.0) {
                    return c.bad("slope_deg", slope_deg, "0 (exclusive)..90");
                }
            }
            Feature::Ditch { from_m, to_m, width_m, depth_m, wall_deg } => {
                for (name, v) in [("from_m", from_m.0), ("from_m", from_m.1), ("to_m", to_m.0), ("to_m", to_m.1)] {
                    c.at(name, v)?;
                }
                c.positive("width_m", width_m)?;
                if !(depth_m > 0.0 && depth_m <= MAX_HEIGHT_M) {
                    return c.bad("depth_m", depth_m, "0 (exclusive)..=100000 m");
                }
                if !(wall_deg > 0.0 && wall_deg <= 90.0) {
                    return c.bad("wall_deg", wall_deg, "0 (exclusive)..=90");
                }
                let run = if wall_deg >= 90.0 { 0.0 } else { depth_m / wall_deg.to_radians().tan() };
                if 2.0 * run > width_m {
                    return c.bad("wall_deg", wall_deg, "steep enough that both walls fit in width_m");
                }
            }
            _ => {}
        }
        Ok(())
    }
}

/// The range checks of feature `i`'s fields, each naming the field as
/// `features[i].name`.
struct FieldCheck {
    i: usize,
}

impl FieldCheck {
    fn bad(&self, name: &str, value: f64, allowed: &'static str) -> Result<()> {
        Err(Error::BadSynth { field: format!("features[{}].{name}", self.i), value, allowed })
    }

    /// A position, m.
    fn at(&self, name: &str, v: f64) -> Result<()> {
        if v.abs() <= MAX_LENGTH_M { Ok(()) } else { self.bad(name, v, "-1e7..=1e7 m") }
    }

    /// A size, m.
    fn positive(&self, name: &str, v: f64) -> Result<()> {
        if v > 0.0 && v <= MAX_LENGTH_M { Ok(()) } else { self.bad(name, v, "0 (exclusive)..=1e7 m") }
    }

    /// A height above or below the base, m.
    fn height(&self, name: &str, v: f64) -> Result<()> {
        if v.abs() <= MAX_HEIGHT_M { Ok(()) } else { self.bad(name, v, "-100000..=100000 m") }
    }

    /// A depth, m.
    fn depth(&self, name: &str, v: f64) -> Result<()> {
        if (0.0..=MAX_HEIGHT_M).contains(&v) { Ok(()) } else { self.bad(name, v, "0..=100000 m") }
    }

    /// A slope, degrees.
    fn slope(&self, name: &str, v: f64) -> Result<()> {
        if (0.0..90.0).contains(&v) { Ok(()) } else { self.bad(name, v, "0..90") }
    }
}

impl TerrainSpec {
    /// Checks every value, naming the first bad field. Beyond finiteness, the ranges are
    /// physical: cells from 1 mm to 10 km, positions and sizes within 10 000 km,
    /// heights within 100 km, and noise no finer than half a cell (finer adds only
    /// aliasing, and its lattice would outgrow the map).
    pub fn validate(&self) -> Result<()> {
        let bad = |field: String, value: f64, allowed: &'static str| Err(Error::BadSynth { field, value, allowed });
        if !(1..=20_000).contains(&self.cols) {
            return bad("cols".into(), self.cols as f64, "1..=20000");
        }
        if !(1..=20_000).contains(&self.rows) {
            return bad("rows".into(), self.rows as f64, "1..=20000");
        }
        if !(self.cell_m >= 1e-3 && self.cell_m <= 1e4) {
            return bad("cell_m".into(), self.cell_m, "0.001..=10000 m");
        }
        if !(self.base_m.abs() <= MAX_HEIGHT_M) {
            return bad("base_m".into(), self.base_m, "-100000..=100000 m");
        }
        if let Some(n) = &self.noise {
            if !(n.amplitude_m >= 0.0 && n.amplitude_m <= MAX_HEIGHT_M) {
                return bad("noise.amplitude_m".into(), n.amplitude_m, "0..=100000 m");
            }
            if !(1..=12).contains(&n.octaves) {
                return bad("noise.octaves".into(), f64::from(n.octaves), "1..=12");
            }
            let finest = n.wavelength_m / f64::from(1u32 << (n.octaves - 1));
            if !(finest >= 0.5 * self.cell_m && n.wavelength_m <= MAX_LENGTH_M) {
                return bad(
                    "noise.wavelength_m".into(),
                    n.wavelength_m,
                    "at most 1e7 m, and at least cell_m × 2^(octaves − 2), so that the finest octave is no finer than half a cell",
                );
            }
            if !(0.0..=1.0).contains(&n.persistence) {
                return bad("noise.persistence".into(), n.persistence, "0..=1");
            }
        }
        for (i, f) in self.features.iter().enumerate() {
            f.validate(i)?;
        }
        Ok(())
    }

    /// Builds the DEM (validating first).
    pub fn build(&self) -> Result<Dem> {
        self.validate()?;
        let noise = self
            .noise
            .map(|n| FractalNoise::new(n, self.seed, self.cols as f64 * self.cell_m, self.rows as f64 * self.cell_m));
        let dem = Dem::from_fn(self.cols, self.rows, self.cell_m, self.cell_m, |x, y| {
            let mut z = self.base_m;
            for f in &self.features {
                z += f.height(x, y);
            }
            if let Some(n) = &noise {
                z += n.at(x, y);
            }
            z
        })?;
        Ok(dem)
    }
}

/// Distance from (x, y) to the segment a–b, m.
fn segment_distance(x: f64, y: f64, a: (f64, f64), b: (f64, f64)) -> f64 {
    let (vx, vy) = (b.0 - a.0, b.1 - a.1);
    let len2 = vx * vx + vy * vy;
    let t = if len2 == 0.0 { 0.0 } else { (((x - a.0) * vx + (y - a.1) * vy) / len2).clamp(0.0, 1.0) };
    let (px, py) = (a.0 + t * vx, a.1 + t * vy);
    (x - px).hypot(y - py)
}

/// 1 at d = 0 falling to 0 at d = half with a cosine shoulder.
fn bell(d: f64, half: f64) -> f64 {
    if d >= half { 0.0 } else { 0.5 + 0.5 * (std::f64::consts::PI * d / half).cos() }
}

impl Feature {
    /// This landform's contribution to the height at (x, y), m.
    pub fn height(&self, x: f64, y: f64) -> f64 {
        match *self {
            Feature::Crater { x_m, y_m, radius_m, depth_m, rim_height_m, ejecta_radii } => {
                let r = (x - x_m).hypot(y - y_m) / radius_m;
                if r <= 1.0 {
                    -depth_m + (depth_m + rim_height_m) * r * r
                } else if r <= ejecta_radii {
                    // (1/r)³ decay, shifted so it reaches 0 at the blanket's edge.
                    let edge = ejecta_radii.powi(-3);
                    rim_height_m * (r.powi(-3) - edge) / (1.0 - edge).max(f64::MIN_POSITIVE)
                } else {
                    0.0
                }
            }
            Feature::Hill { x_m, y_m, radius_m, slope_deg } => {
                let r = (x - x_m).hypot(y - y_m);
                (radius_m - r).max(0.0) * slope_deg.to_radians().tan()
            }
            Feature::AsymmetricHill { x_m, y_m, height_m, west_slope_deg, east_slope_deg, top_radius_m } => {
                let r = (x - x_m).hypot(y - y_m);
                let east = if r > 0.0 { (x - x_m) / r } else { 0.0 };
                let w = 0.5 * (1.0 + east);
                let slope = west_slope_deg + (east_slope_deg - west_slope_deg) * (w * w) * (w * w);
                (height_m - (r - top_radius_m).max(0.0) * slope.to_radians().tan()).max(0.0)
            }
            Feature::Ridge { from_m, to_m, height_m, width_m } => {
                height_m * bell(segment_distance(x, y, from_m, to_m), width_m / 2.0)
            }
            Feature::MountainChain { x_m, y_from_m, y_to_m, height_m, width_m, ref passes } => {
                let d = segment_distance(x, y, (x_m, y_from_m), (x_m, y_to_m));
                let mut crest = height_m;
                for p in passes {
                    let dip = bell((y - p.y_m).abs(), p.width_m / 2.0);
                    crest = crest.min(height_m - (height_m - p.height_m) * dip);
                }
                crest * bell(d, width_m / 2.0)
            }
            Feature::Scarp { from_m, to_m, height_m, slope_deg } => {
                // Signed distance to the left of the line from → to.
                let (dx, dy) = (to_m.0 - from_m.0, to_m.1 - from_m.1);
                let left = (dx * (y - from_m.1) - dy * (x - from_m.0)) / dx.hypot(dy);
                (left.max(0.0) * slope_deg.to_radians().tan()).min(height_m)
            }
            Feature::Ditch { from_m, to_m, width_m, depth_m, wall_deg } => {
                let d = segment_distance(x, y, from_m, to_m);
                let half = width_m / 2.0;
                let run = if wall_deg >= 90.0 { 0.0 } else { depth_m / wall_deg.to_radians().tan() };
                let floor_half = half - run;
                if d <= floor_half {
                    -depth_m
                } else if d < half {
                    -depth_m + (d - floor_half) * wall_deg.to_radians().tan()
                } else {
                    0.0
                }
            }
            Feature::Rock { x_m, y_m, height_m, width_m } => {
                let r = (x - x_m).hypot(y - y_m) / (width_m / 2.0);
                if r < 1.0 { height_m * (1.0 - r * r).sqrt() } else { 0.0 }
            }
            Feature::Tilt { slope_deg, aspect_deg } => {
                let (s, c) = aspect_deg.to_radians().sin_cos();
                -slope_deg.to_radians().tan() * (x * s + y * c)
            }
        }
    }
}

/// Octaves of smoothly interpolated random lattices.
struct FractalNoise {
    octaves: Vec<(f64, f64, usize, Vec<f64>)>, // (amplitude, wavelength, lattice width, values)
}

impl FractalNoise {
    fn new(spec: Noise, seed: u64, width_m: f64, height_m: f64) -> FractalNoise {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut octaves = Vec::new();
        let (mut amp, mut wl) = (spec.amplitude_m, spec.wavelength_m);
        for _ in 0..spec.octaves {
            let nx = (width_m / wl).ceil() as usize + 2;
            let ny = (height_m / wl).ceil() as usize + 2;
            let values = (0..nx * ny).map(|_| rng.random_range(-1.0..1.0)).collect();
            octaves.push((amp, wl, nx, values));
            amp *= spec.persistence;
            wl /= 2.0;
        }
        FractalNoise { octaves }
    }

    fn at(&self, x: f64, y: f64) -> f64 {
        let smooth = |t: f64| t * t * (3.0 - 2.0 * t);
        let mut z = 0.0;
        for (amp, wl, nx, values) in &self.octaves {
            let (u, v) = ((x / wl).max(0.0), (y / wl).max(0.0));
            let (i, j) = (u.floor() as usize, v.floor() as usize);
            let ny = values.len() / nx;
            let (i, j) = (i.min(nx - 2), j.min(ny - 2));
            let (s, t) = (smooth(u - i as f64), smooth(v - j as f64));
            let at = |a: usize, b: usize| values[b * nx + a];
            let top = at(i, j) * (1.0 - s) + at(i + 1, j) * s;
            let bottom = at(i, j + 1) * (1.0 - s) + at(i + 1, j + 1) * s;
            z += amp * (top * (1.0 - t) + bottom * t);
        }
        z
    }
}

/// `dem` with `features` added to it: the features are placed in the map's local frame
/// (its south-west corner at (0, 0), as in [`TerrainSpec`]), whatever its georeference,
/// so a feature described for a synthesised map lands on the same cells after the map
/// is placed at a site. Missing cells stay missing. (How a simulation's true terrain
/// differs from the rover's map: a pass that is a wall, a boulder field.)
pub fn add_features(dem: &Dem, features: &[Feature]) -> Result<Dem> {
    let e = dem.extent();
    let mut z = Vec::with_capacity(dem.cols() * dem.rows());
    for row in 0..dem.rows() {
        for col in 0..dem.cols() {
            let Some(h) = dem.z(col, row) else {
                z.push(f32::NAN);
                continue;
            };
            let (x, y) = dem.cell_center(col, row);
            let (x, y) = (x - e.x_min, y - e.y_min);
            z.push(h + features.iter().map(|f| f.height(x, y)).sum::<f64>() as f32);
        }
    }
    dem.with_values(z)
}

/// Rough test terrain for the line-of-sight tests: 10 m cells, fractal noise of the
/// given amplitude and octaves, and a 25° hill in the middle.
#[cfg(test)]
pub(crate) fn rough_test_terrain(cols: usize, rows: usize, seed: u64, amplitude_m: f64, octaves: u32) -> Dem {
    let (w, h) = (cols as f64 * 10.0, rows as f64 * 10.0);
    TerrainSpec {
        cols,
        rows,
        cell_m: 10.0,
        base_m: 0.0,
        seed,
        noise: Some(Noise { amplitude_m, wavelength_m: 300.0, octaves, persistence: 0.5 }),
        features: vec![Feature::Hill { x_m: w / 2.0, y_m: h / 2.0, radius_m: w / 4.8, slope_deg: 25.0 }],
    }
    .build()
    .expect("valid test terrain")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::slope::slope_aspect;

    fn spec(features: Vec<Feature>) -> TerrainSpec {
        TerrainSpec { cols: 101, rows: 101, cell_m: 1.0, base_m: 10.0, seed: 0, noise: None, features }
    }

    #[test]
    fn a_scarp_rises_on_the_left_of_its_line_at_its_slope_to_a_plateau() {
        // West to east along y = 30.5: the face rises to the north at 35° to 12 m.
        let scarp = Feature::Scarp { from_m: (0.0, 30.5), to_m: (101.0, 30.5), height_m: 12.0, slope_deg: 35.0 };
        let dem = spec(vec![scarp]).build().unwrap();
        let sa = slope_aspect(&dem);
        // Rows run north to south: y = 100.5 − row. The foot at row 70, the face
        // between, the plateau from 12/tan 35° = 17.1 m north of the foot.
        let z = |row: usize| f64::from(dem.z(50, row).unwrap());
        assert!((z(80) - 10.0).abs() < 1e-5 && (z(20) - 22.0).abs() < 1e-5);
        assert!((z(65) - (10.0 + 5.0 * 35f64.to_radians().tan())).abs() < 1e-5);
        let face = dem.index(50, 62);
        assert!((sa.slope_deg[face] - 35.0).abs() < 0.1, "{}", sa.slope_deg[face]);
        // Every column alike: the face cannot be gone around.
        assert!((0..101).all(|c| (f64::from(dem.z(c, 65).unwrap()) - z(65)).abs() < 1e-9));
        // A line of no length is refused, with its field.
        let bad = Feature::Scarp { from_m: (1.0, 1.0), to_m: (1.0, 1.0), height_m: 1.0, slope_deg: 30.0 };
        assert!(spec(vec![bad]).build().unwrap_err().to_string().contains("features[0].to_m"));
    }

    #[test]
    fn an_asymmetric_hill_has_its_stated_slopes_due_west_and_east() {
        let hill = Feature::AsymmetricHill {
            x_m: 50.5,
            y_m: 50.5,
            height_m: 30.0,
            west_slope_deg: 25.0,
            east_slope_deg: 60.0,
            top_radius_m: 0.0,
        };
        let dem = spec(vec![hill]).build().unwrap();
        let sa = slope_aspect(&dem);
        let top = dem.z(50, 50).unwrap();
        assert!((top - 40.0).abs() < 0.5, "{top}");
        // Halfway down each flank, due west and due east of the summit.
        let (w, e) = (dem.index(40, 50), dem.index(58, 50));
        assert!((sa.slope_deg[w] - 25.0).abs() < 0.3, "west {}", sa.slope_deg[w]);
        assert!((sa.slope_deg[e] - 60.0).abs() < 0.3, "east {}", sa.slope_deg[e]);
        assert!((sa.aspect_deg[w] - 270.0).abs() < 1.0 && (sa.aspect_deg[e] - 90.0).abs() < 1.0);
        // Due north a sixteenth of the way (25° + 35°/16 along the radius; a little
        // steeper along the fall line, which the azimuthal change of slope turns).
        let n = sa.slope_deg[dem.index(50, 45)];
        assert!(n > 27.0 && n < 31.0, "north {n}");
        // A flat top 5 m across the summit, the flanks unchanged beyond it.
        let flat = Feature::AsymmetricHill {
            x_m: 50.5,
            y_m: 50.5,
            height_m: 30.0,
            west_slope_deg: 25.0,
            east_slope_deg: 60.0,
            top_radius_m: 5.0,
        };
        let dem = spec(vec![flat]).build().unwrap();
        for (c, r) in [(50, 50), (47, 50), (53, 52), (50, 46)] {
            assert!((dem.z(c, r).unwrap() - 40.0).abs() < 1e-4, "({c}, {r}) on the top");
        }
        let w = slope_aspect(&dem).slope_deg[dem.index(35, 50)];
        assert!((w - 25.0).abs() < 0.3, "west flank {w}");
    }

    #[test]
    fn hill_flanks_have_the_requested_slope() {
        let dem = spec(vec![Feature::Hill { x_m: 50.5, y_m: 50.5, radius_m: 40.0, slope_deg: 20.0 }]).build().unwrap();
        let sa = slope_aspect(&dem);
        // Halfway down the east flank: slope 20°, facing east.
        let i = dem.index(70, 50);
        assert!((sa.slope_deg[i] - 20.0).abs() < 0.2, "{}", sa.slope_deg[i]);
        assert!((sa.aspect_deg[i] - 90.0).abs() < 1.0);
        assert!((dem.z(50, 50).unwrap() - (10.0 + 40.0 * 20f32.to_radians().tan())).abs() < 0.5);
    }

    #[test]
    fn ditch_has_the_requested_depth_width_and_walls() {
        let dem = spec(vec![Feature::Ditch {
            from_m: (50.5, 0.0),
            to_m: (50.5, 101.0),
            width_m: 20.0,
            depth_m: 3.0,
            wall_deg: 45.0,
        }])
        .build()
        .unwrap();
        assert!((dem.z(50, 50).unwrap() - 7.0).abs() < 1e-4, "floor 3 m down");
        assert!((dem.z(30, 50).unwrap() - 10.0).abs() < 1e-4, "outside untouched");
        let sa = slope_aspect(&dem);
        // The walls run 3 m horizontally at 45°: cells 9 m from the centreline are on them.
        assert!((sa.slope_deg[dem.index(59, 50)] - 45.0).abs() < 0.5, "{}", sa.slope_deg[dem.index(59, 50)]);
        assert!(
            TerrainSpec {
                features: vec![Feature::Ditch {
                    from_m: (0.0, 0.0),
                    to_m: (1.0, 1.0),
                    width_m: 2.0,
                    depth_m: 3.0,
                    wall_deg: 30.0
                }],
                ..spec(vec![])
            }
            .validate()
            .is_err()
        );
    }

    #[test]
    fn crater_rim_floor_and_rock() {
        let dem = spec(vec![
            Feature::Crater {
                x_m: 50.5,
                y_m: 50.5,
                radius_m: 20.0,
                depth_m: 8.0,
                rim_height_m: 2.0,
                ejecta_radii: 2.5,
            },
            Feature::Rock { x_m: 5.5, y_m: 95.5, height_m: 0.5, width_m: 1.0 },
        ])
        .build()
        .unwrap();
        assert!((dem.z(50, 50).unwrap() - 2.0).abs() < 1e-3, "floor at -8");
        assert!((dem.z(70, 50).unwrap() - 12.0).abs() < 1e-3, "rim at +2");
        // Ejecta: (1/r)³ decay, zero at 2.5 radii.
        assert!(dem.z(80, 50).unwrap() > 10.0 && dem.z(80, 50).unwrap() < 12.0);
        assert!((dem.z(100, 50).unwrap() - 10.0).abs() < 1e-6);
        assert!((dem.z(5, 5).unwrap() - 10.5).abs() < 1e-3, "rock top");
    }

    #[test]
    fn chain_dips_at_its_pass_and_noise_is_seeded() {
        let chain = Feature::MountainChain {
            x_m: 50.5,
            y_from_m: 0.0,
            y_to_m: 101.0,
            height_m: 300.0,
            width_m: 40.0,
            passes: vec![Pass { y_m: 80.5, height_m: 50.0, width_m: 20.0 }],
        };
        let dem = spec(vec![chain]).build().unwrap();
        assert!((dem.z(50, 20).unwrap() - 60.0).abs() < 1e-3, "pass saddle: 50 m above base");
        assert!((dem.z(50, 70).unwrap() - 310.0).abs() < 1e-3, "crest");
        let noisy = |seed| {
            TerrainSpec {
                seed,
                noise: Some(Noise { amplitude_m: 5.0, wavelength_m: 30.0, octaves: 3, persistence: 0.5 }),
                ..spec(vec![])
            }
            .build()
            .unwrap()
        };
        assert_eq!(noisy(3), noisy(3));
        assert_ne!(noisy(3), noisy(4));
        let z = noisy(3);
        assert!(z.elevations().iter().all(|v| (v - 10.0).abs() <= 5.0 * 1.75 + 1e-3));
    }

    #[test]
    fn features_added_to_a_placed_map_land_where_they_were_described() {
        let hill = Feature::Hill { x_m: 50.5, y_m: 50.5, radius_m: 40.0, slope_deg: 20.0 };
        let flat = spec(vec![]).build().unwrap();
        let mut valid = vec![true; 101 * 101];
        valid[flat.index(3, 4)] = false;
        let flat = flat.with_mask(valid).unwrap();
        // Placed at a site its frame moves (x0 = −w/2), but the features must not.
        let placed = flat.clone().placed_at(crate::Spheroid::MARS_MOLA_SPHERE, -4.6, 137.4).unwrap();
        let with_hill = spec(vec![hill.clone()]).build().unwrap();
        for dem in [&flat, &placed] {
            let added = add_features(dem, std::slice::from_ref(&hill)).unwrap();
            assert_eq!(added.georef(), dem.georef());
            assert_eq!(added.z(3, 4), None, "a missing cell stays missing");
            for (col, row) in [(50, 50), (70, 50), (20, 80), (0, 0)] {
                // f32 heights: the base and the hill are rounded separately here.
                let (a, b) = (added.z(col, row).unwrap(), with_hill.z(col, row).unwrap());
                assert!((a - b).abs() < 1e-5, "cell ({col}, {row}): {a} against {b}");
            }
        }
    }
}
