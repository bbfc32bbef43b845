//! What a GA actions run's viewer (`view.html`) shows, as plain data: the terrain from
//! above and the ground along the best plan's path in profile, and the rover after each
//! module — its pose in both, each wheel's normal load, the stability margin and the
//! friction the module needed against the available μ. The profile's abscissa is the
//! distance the reference point has travelled along its path, its ordinate height; a
//! wheel or the tool is placed along the path by its offset along the rover's heading.

use serde::Serialize;

use super::Raster;

/// The longest side of the top view's image, pixels: a larger map is downsampled by
/// whole cells.
pub const ACTIONS_VIEW_PIXELS: usize = 600;

/// How far the ground under each side's wheels is drawn ahead and behind the reference
/// point, m.
pub const SECTION_HALF_M: f64 = 0.8;

/// The spacing of those heights, m.
pub const SECTION_STEP_M: f64 = 0.025;

/// An actions run's viewer data.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ActionsView {
    /// The run's name.
    pub run: String,
    /// The rover's name.
    pub rover: String,
    /// The friction coefficient the plan was executed with.
    pub mu: f64,
    /// The least stability margin the executor admits (0..1 of flat ground's).
    pub stability_floor: f64,
    /// Wheel radius, m.
    pub wheel_radius_m: f64,
    /// The body's half length, half width and half height, m.
    pub body_half_m: (f64, f64, f64),
    /// The terrain shaded from the north-west, grey, a byte per pixel, north row first.
    pub hillshade: Raster<u8>,
    /// The map's south-west corner (east, north), m, and its size (east, north), m: the
    /// hillshade spans it.
    pub map_origin_m: (f64, f64),
    /// See [`ActionsView::map_origin_m`].
    pub map_size_m: (f64, f64),
    /// Where the rover starts: east, north (m) and heading (degrees clockwise from
    /// north).
    pub start: (f64, f64, f64),
    /// The target (east, north), m, and its radius, m.
    pub target: (f64, f64, f64),
    /// The samples (east, north), m.
    pub samples: Vec<(f64, f64)>,
    /// The rocks: east, north and width, m.
    pub rocks: Vec<(f64, f64, f64)>,
    /// The ground under the reference point's path: (distance along it, height), m.
    /// Where the path turns, the wheels stand on the ground of their own sections
    /// ([`ActionsViewStep::left_ground_m`]), not on this.
    pub ground: Vec<(f64, f64)>,
    /// `SECTION_HALF_M` and `SECTION_STEP_M`, m, for the page.
    pub section_half_step_m: (f64, f64),
    /// The rover after each module, in the plan's order.
    pub steps: Vec<ActionsViewStep>,
}

/// The rover after one module.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ActionsViewStep {
    /// Table 1 code.
    pub code: u16,
    /// What the module does, in words.
    pub action: String,
    /// Distance the reference point has travelled along its path, m.
    pub along_m: f64,
    /// The reference point: east, north, height (body), m.
    pub at_m: (f64, f64, f64),
    /// Heading, degrees clockwise from north.
    pub heading_deg: f64,
    /// Body pitch, degrees, nose up positive.
    pub pitch_deg: f64,
    /// The wheels' axles from above (east, north), m: left front, middle, rear, then
    /// right.
    pub wheels_top_m: [(f64, f64); 6],
    /// The wheels' axles in profile (along the path, height), m.
    pub wheels_profile_m: [(f64, f64); 6],
    /// The arm's tool in profile (along the path, height), m.
    pub tool_profile_m: (f64, f64),
    /// The ground under the left wheels' track: heights, m, along the rover's heading
    /// through the left wheels' mean offset from the reference point, from
    /// `along_m − SECTION_HALF_M` to `along_m + SECTION_HALF_M` every
    /// `SECTION_STEP_M` (none off the map).
    pub left_ground_m: Vec<Option<f32>>,
    /// The same under the right wheels.
    pub right_ground_m: Vec<Option<f32>>,
    /// Each wheel's normal load, N, in the wheels' order.
    pub wheel_loads_n: [f64; 6],
    /// The least stability margin during the module (0..1), if it moved anything.
    pub stability: Option<f64>,
    /// The largest |T|/N any wheel used in the module: the least μ it needs.
    pub friction_used: f64,
    /// Battery energy the module used, Wh.
    pub energy_wh: f64,
    /// How long the module took, s.
    pub duration_s: f64,
}
