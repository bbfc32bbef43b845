//! The scenario format's own types for synthesised terrain. They mirror areo-terrain's
//! `synth` types field for field and convert into them, so renaming a library field
//! cannot change what a scenario file says.

use areo_terrain::synth as lib;
use serde::{Deserialize, Serialize};

/// A terrain to synthesise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SynthSpec {
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
    pub noise: Option<FractalNoiseSpec>,
    /// Landforms, summed.
    #[serde(default)]
    pub features: Vec<FeatureSpec>,
}

/// Seeded fractal value noise: octaves of smooth random lattices, each with half the
/// wavelength and `persistence` times the amplitude of the one before.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FractalNoiseSpec {
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
pub enum FeatureSpec {
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
        passes: Vec<PassSpec>,
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
pub struct PassSpec {
    /// Where along the chain, m (y).
    pub y_m: f64,
    /// Saddle height, m (below the crest).
    pub height_m: f64,
    /// Width of the dip along the chain, m (> 0).
    pub width_m: f64,
}

impl FeatureSpec {
    /// The library's landform.
    pub fn to_feature(&self) -> lib::Feature {
        match self {
            FeatureSpec::Crater { x_m, y_m, radius_m, depth_m, rim_height_m, ejecta_radii } => lib::Feature::Crater {
                x_m: *x_m,
                y_m: *y_m,
                radius_m: *radius_m,
                depth_m: *depth_m,
                rim_height_m: *rim_height_m,
                ejecta_radii: *ejecta_radii,
            },
            FeatureSpec::Hill { x_m, y_m, radius_m, slope_deg } => {
                lib::Feature::Hill { x_m: *x_m, y_m: *y_m, radius_m: *radius_m, slope_deg: *slope_deg }
            }
            FeatureSpec::AsymmetricHill { x_m, y_m, height_m, west_slope_deg, east_slope_deg, top_radius_m } => {
                lib::Feature::AsymmetricHill {
                    x_m: *x_m,
                    y_m: *y_m,
                    height_m: *height_m,
                    west_slope_deg: *west_slope_deg,
                    east_slope_deg: *east_slope_deg,
                    top_radius_m: *top_radius_m,
                }
            }
            FeatureSpec::Ridge { from_m, to_m, height_m, width_m } => {
                lib::Feature::Ridge { from_m: *from_m, to_m: *to_m, height_m: *height_m, width_m: *width_m }
            }
            FeatureSpec::MountainChain { x_m, y_from_m, y_to_m, height_m, width_m, passes } => {
                lib::Feature::MountainChain {
                    x_m: *x_m,
                    y_from_m: *y_from_m,
                    y_to_m: *y_to_m,
                    height_m: *height_m,
                    width_m: *width_m,
                    passes: passes
                        .iter()
                        .map(|p| lib::Pass { y_m: p.y_m, height_m: p.height_m, width_m: p.width_m })
                        .collect(),
                }
            }
            FeatureSpec::Scarp { from_m, to_m, height_m, slope_deg } => {
                lib::Feature::Scarp { from_m: *from_m, to_m: *to_m, height_m: *height_m, slope_deg: *slope_deg }
            }
            FeatureSpec::Ditch { from_m, to_m, width_m, depth_m, wall_deg } => lib::Feature::Ditch {
                from_m: *from_m,
                to_m: *to_m,
                width_m: *width_m,
                depth_m: *depth_m,
                wall_deg: *wall_deg,
            },
            FeatureSpec::Rock { x_m, y_m, height_m, width_m } => {
                lib::Feature::Rock { x_m: *x_m, y_m: *y_m, height_m: *height_m, width_m: *width_m }
            }
            FeatureSpec::Tilt { slope_deg, aspect_deg } => {
                lib::Feature::Tilt { slope_deg: *slope_deg, aspect_deg: *aspect_deg }
            }
        }
    }
}

impl SynthSpec {
    /// Builds the terrain ([`areo_terrain::synth::TerrainSpec::build`]).
    pub fn build(&self) -> areo_terrain::Result<areo_terrain::Dem> {
        self.to_spec().build()
    }

    /// Checks every value, naming the first bad field
    /// ([`areo_terrain::synth::TerrainSpec::validate`]).
    pub fn validate(&self) -> areo_terrain::Result<()> {
        self.to_spec().validate()
    }

    /// The library's terrain specification.
    pub fn to_spec(&self) -> lib::TerrainSpec {
        lib::TerrainSpec {
            cols: self.cols,
            rows: self.rows,
            cell_m: self.cell_m,
            base_m: self.base_m,
            seed: self.seed,
            noise: self.noise.map(|n| lib::Noise {
                amplitude_m: n.amplitude_m,
                wavelength_m: n.wavelength_m,
                octaves: n.octaves,
                persistence: n.persistence,
            }),
            features: self.features.iter().map(FeatureSpec::to_feature).collect(),
        }
    }
}
