//! The world model of TEMPEST (Table 1): terrain (DEM, slope, ground normals), the Sun
//! from any [`SunModel`] tabulated over the planning horizon, line of sight to the Sun
//! from a horizon map (lit or shadowed, and the Sun's elevation above the local ground
//! plane, at any time), and the solar flux.
//!
//! Time is seconds after the world's epoch (`t = 0`). The Sun's direction is taken at
//! the region's reference site: over a few kilometres it changes by well under a tenth
//! of a degree.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

use areo_ephemeris::flux::Atmosphere;
use areo_ephemeris::{Body, EarthFrom, Site, SunModel};
use areo_rover::resources::SolarArray;
use areo_terrain::Dem;
use areo_terrain::horizon::HorizonMap;
use areo_terrain::shadow::{Curvature, GridSunDirection};
use areo_terrain::slope::{SlopeAspect, slope_aspect};
use areo_terrain::tiles::Region;
use hifitime::{Duration, Epoch};

use crate::error::{Error, Result};
use crate::ground::ClassMap;

mod attitude;

/// ‖R(b) − R(a)‖ for the rotations R that take straight up to ground normals `a` and
/// `b` (as a rover's attitude on the ground, [`SolarArray::tipped_normal_enu`]): with
/// Q = R(b)·R(a)ᵀ a rotation by φ, ‖(R(b) − R(a))v‖ = ‖(Q − I)R(a)v‖ ≤ 2 sin(φ/2) =
/// √(3 − tr Q), and tr Q is the sum of the dot products of the two rotations' columns.
fn attitude_change(a: [f64; 3], b: [f64; 3]) -> f64 {
    let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let trace: f64 = axes
        .iter()
        .map(|&e| {
            let (ra, rb) = (SolarArray::tipped_normal_enu(e, a), SolarArray::tipped_normal_enu(e, b));
            ra[0] * rb[0] + ra[1] * rb[1] + ra[2] * rb[2]
        })
        .sum();
    (3.0 - trace).max(0.0).sqrt()
}

/// The sphere a body's horizon maps drop away on ([`Curvature::of_body`]).
pub fn curvature_of(body: Body) -> Curvature {
    Curvature::of_body(body)
}

/// The Earth at one instant in the sky of the reference site.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EarthSky {
    /// Azimuth, degrees clockwise from the grid's north (as [`GridSun`]'s).
    pub azimuth_deg: f64,
    /// Elevation above the horizontal, degrees (topocentric).
    pub elevation_deg: f64,
}

/// How to build a [`World`].
#[derive(Debug, Clone)]
pub struct WorldConfig {
    /// The instant t = 0.
    pub epoch: Epoch,
    /// How long the Sun is tabulated for, s (the planning horizon).
    pub span_s: f64,
    /// Sun table step, s (linear interpolation between samples).
    pub sun_step_s: f64,
    /// Horizon-map sectors for terrain shadows (16..=360), or `None` for no terrain
    /// shadowing (lit whenever the Sun is above the horizontal).
    pub horizon_sectors: Option<usize>,
    /// Surface flux model.
    pub atmosphere: Atmosphere,
    /// Where the Sun is computed (latitude, east longitude); `None` takes the DEM's
    /// georeferenced centre.
    pub site: Option<Site>,
}

/// The Sun at one instant, at the reference site, on the map's axes: its azimuth from
/// the grid's north, as the terrain's [`areo_terrain::shadow::GridSunDirection`] (the
/// ephemeris' `TrueSunDirection` is from true north).
///
/// Its direction is areo-terrain's one grid-north Sun type, [`GridSunDirection`] (its
/// `azimuth_deg` and `elevation_deg` read through `Deref`); this adds the light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSun {
    /// Azimuth, degrees clockwise from the grid's north (true north wherever the map's
    /// meridians are its columns; see [`areo_terrain::Projection::true_north_on_grid_deg`]),
    /// and elevation above the horizontal, degrees.
    pub direction: GridSunDirection,
    /// Unit vector toward the Sun on the grid's axes: (grid east, grid north, up).
    pub enu: [f64; 3],
    /// Direct-beam flux at the surface, W/m² normal to the beam (0 below the horizon).
    pub beam_w_m2: f64,
}

impl std::ops::Deref for GridSun {
    type Target = GridSunDirection;

    fn deref(&self) -> &GridSunDirection {
        &self.direction
    }
}

/// Terrain, Sun and light for planning. What sensing can change (elevation, slope,
/// normal, blocked cells, the horizon) is held in atomics — and sensed horizons in a
/// small locked table — so plans and their searches can keep borrowing the world while
/// it is updated between re-plans. [`World::dem`] stays the map as loaded.
#[derive(Debug)]
pub struct World {
    dem: Dem,
    elevation: Vec<AtomicU32>,
    slope_deg: Vec<AtomicU32>,
    /// The ground normal's east and north components (f32 bits): the up component
    /// follows, as the normal is a unit vector pointing up.
    normal: Vec<[AtomicU32; 2]>,
    blocked: Vec<AtomicBool>,
    /// The horizon map; a true world built with [`World::truth`] shares the map's and
    /// holds its differences as sensed profiles.
    horizon: Option<Arc<HorizonMap>>,
    /// Whether `horizon` is another world's (so not counted in [`World::bytes`]).
    shares_horizon: bool,
    /// Whether `horizon` was traced on `dem` itself (a region's horizons are the whole
    /// map's): a true world then traces only the lines near the cells it changes.
    horizon_of_dem: bool,
    /// Cells whose horizon was sensed: their profile is in `sensed_horizon`.
    horizon_sensed: Vec<AtomicBool>,
    sensed_horizon: Mutex<HashMap<u32, Box<[f32]>>>,
    sun: Vec<GridSun>,
    /// The Earth, tabulated like the Sun (empty on the Earth itself).
    earth: Vec<EarthSky>,
    sun_step_s: f64,
    epoch: Epoch,
    site: Site,
    body: Body,
    /// The terrains a plan must hold on ([`World::envelope`]), if any.
    members: Option<Arc<Members>>,
    /// Cells sensed since the envelope was made: there the world's own values hold,
    /// not the members' (empty without members).
    members_off: Vec<AtomicBool>,
    /// The terrain classes, if the map has them (sensing does not change them).
    ground: Option<Arc<ClassMap>>,
}

/// What an envelope world keeps of the terrains it stands for (the map and its error
/// clones): their heights, cell-major (cell c's for member i at `c * n + i`), and at
/// each cell how far their ground normals tip a body away from the map's
/// ([`World::attitude_spread`]).
#[derive(Debug)]
struct Members {
    n: usize,
    heights: Vec<f32>,
    spread: Vec<f32>,
}

impl World {
    /// Bytes a world's own grids hold per cell beyond its DEM and horizon map: slope
    /// and aspect (f32 each), the normal (two f32) and the sensing flags (see
    /// [`World::bytes`]).
    pub const GRID_BYTES_PER_CELL: u64 = 4 + 4 + 8 + 2;

    /// Bytes a world on `cells` cells with `sectors` horizon sectors holds at most, with
    /// a true world beside it when `with_truth` (its own DEM and grids; it shares the
    /// map's horizon map), for memory estimates made before either is built.
    pub fn estimate_bytes(cells: u64, sectors: usize, with_truth: bool) -> u64 {
        let dem = areo_terrain::Dem::BYTES_PER_CELL;
        let per_cell = dem + HorizonMap::bytes_per_cell(sectors) + World::GRID_BYTES_PER_CELL;
        let truth = if with_truth { dem + World::GRID_BYTES_PER_CELL } else { 0 };
        cells.saturating_mul(per_cell + truth)
    }

    /// Builds the world: slope and normals, the horizon map (in parallel), and the Sun
    /// table from `sun_model`.
    pub fn new(dem: Dem, config: &WorldConfig, sun_model: &impl SunModel) -> Result<World> {
        World::check(config)?;
        let sa = slope_aspect(&dem);
        let horizon = match config.horizon_sectors {
            Some(k) => Some(HorizonMap::compute(&dem, k, curvature_of(sun_model.body()))?),
            None => None,
        };
        World::from_parts(dem, sa, horizon, config, sun_model)
    }

    /// The world of a planning region cut from a map too large to hold
    /// ([`areo_terrain::tiles::region`]): its slopes, normals and every sector horizon at
    /// or above the region's lowest planned Sun are the whole map's, while memory
    /// follows the region (test `a_world_for_a_region_cut_from_a_larger_map_sees_what_the_whole_map_sees`,
    /// lit cells compared at a sector-centre azimuth). Lower horizons are stored as that
    /// Sun, so a lookup between sectors near it can differ from the whole map's. The
    /// region's horizon map must have `config.horizon_sectors` sectors.
    pub fn for_region(region: Region, config: &WorldConfig, sun_model: &impl SunModel) -> Result<World> {
        World::check(config)?;
        let sectors = region.horizon.as_ref().map(HorizonMap::sectors);
        if sectors != config.horizon_sectors {
            return Err(Error::Config {
                field: "horizon_sectors",
                message: format!("{:?}: the region's horizon map has {sectors:?}", config.horizon_sectors),
            });
        }
        let mut world = World::from_parts(region.dem, region.slope, region.horizon, config, sun_model)?;
        world.horizon_of_dem = false;
        Ok(world)
    }

    fn check(config: &WorldConfig) -> Result<()> {
        if !(config.span_s > 0.0 && config.span_s <= 400.0 * 86_400.0) {
            return Err(Error::Config {
                field: "span_s",
                message: format!("{} s: allowed (0, 400 days]", config.span_s),
            });
        }
        if !(config.sun_step_s >= 1.0 && config.sun_step_s <= 3600.0) {
            return Err(Error::Config {
                field: "sun_step_s",
                message: format!("{} s: allowed 1..=3600", config.sun_step_s),
            });
        }
        Ok(())
    }

    fn from_parts(
        dem: Dem,
        sa: SlopeAspect,
        horizon: Option<HorizonMap>,
        config: &WorldConfig,
        sun_model: &impl SunModel,
    ) -> Result<World> {
        let site = site_of(&dem, config, sun_model)?;
        let body = sun_model.body();
        let cells = dem.cols() * dem.rows();
        let normal = (0..cells)
            .map(|i| {
                let n = sa.normal(i);
                [AtomicU32::new((n[0] as f32).to_bits()), AtomicU32::new((n[1] as f32).to_bits())]
            })
            .collect();
        let elevation = (0..cells)
            .map(|i| {
                let z = if dem.valid_mask()[i] { dem.elevations()[i] } else { f32::NAN };
                AtomicU32::new(z.to_bits())
            })
            .collect();
        let horizon = horizon.map(Arc::new);
        let (sun, earth) = sky_tables(&dem, config, sun_model, &site);
        Ok(World {
            dem,
            elevation,
            horizon_sensed: (0..cells).map(|_| AtomicBool::new(false)).collect(),
            sensed_horizon: Mutex::new(HashMap::new()),
            slope_deg: sa.slope_deg.iter().map(|s| AtomicU32::new(s.to_bits())).collect(),
            normal,
            blocked: (0..cells).map(|_| AtomicBool::new(false)).collect(),
            horizon,
            shares_horizon: false,
            horizon_of_dem: true,
            sun,
            earth,
            sun_step_s: config.sun_step_s,
            epoch: config.epoch,
            site,
            body,
            members: None,
            members_off: Vec::new(),
            ground: None,
        })
    }

    /// A copy of the world as it is now, sensed values included, that senses on its own
    /// from here: a simulation mutates the world it believes ([`World::sense`]), so
    /// runs that must not learn from one another each take a snapshot of the belief.
    /// Shares the horizon map (read-only); copies the grids, flags and sensed profiles.
    pub fn snapshot(&self) -> World {
        let u32s = |v: &[AtomicU32]| v.iter().map(|a| AtomicU32::new(a.load(Ordering::Relaxed))).collect();
        let flags = |v: &[AtomicBool]| v.iter().map(|a| AtomicBool::new(a.load(Ordering::Relaxed))).collect();
        let sensed = self.sensed_horizon.lock().unwrap_or_else(std::sync::PoisonError::into_inner).clone();
        World {
            dem: self.dem.clone(),
            elevation: u32s(&self.elevation),
            slope_deg: u32s(&self.slope_deg),
            normal: self
                .normal
                .iter()
                .map(|[e, n]| [AtomicU32::new(e.load(Ordering::Relaxed)), AtomicU32::new(n.load(Ordering::Relaxed))])
                .collect(),
            blocked: flags(&self.blocked),
            horizon: self.horizon.clone(),
            shares_horizon: true,
            horizon_of_dem: self.horizon_of_dem,
            horizon_sensed: flags(&self.horizon_sensed),
            sensed_horizon: Mutex::new(sensed),
            sun: self.sun.clone(),
            earth: self.earth.clone(),
            sun_step_s: self.sun_step_s,
            epoch: self.epoch,
            site: self.site,
            body: self.body,
            members: self.members.clone(),
            members_off: flags(&self.members_off),
            ground: self.ground.clone(),
        }
    }

    /// The world a plan that must hold on every one of several terrains is made on:
    /// `map` (its Sun, its sensing state) with each cell's slope the steepest of the
    /// members', its horizon in every sector the highest (so a cell is lit only when
    /// it is lit on every member, and the Earth in view only when it is on every
    /// member), and the members' heights and ground normals kept, so that a drive costs
    /// its worst over the members ([`crate::ActionModel::drive_geometry`]) and the
    /// array earns its least ([`crate::ActionModel::source_w`]). The members are `map`
    /// itself and `clones` — error clones of it ([`crate::uncertainty::dem_clone`]) on
    /// its grid with its horizon sectors. Sensing a cell ([`World::sense`]) ends the
    /// uncertainty there: the sensed values hold.
    pub fn envelope(map: &World, clones: &[World]) -> Result<World> {
        let mut world = map.snapshot();
        let cells = world.cells();
        for c in clones {
            if c.cols() != map.cols() || c.rows() != map.rows() {
                return Err(Error::Config {
                    field: "uncertainty.terrain_plan_clones",
                    message: format!(
                        "a clone of {}×{} cells for a map of {}×{}",
                        c.cols(),
                        c.rows(),
                        map.cols(),
                        map.rows()
                    ),
                });
            }
        }
        let n = clones.len() + 1;
        let members: Vec<&World> = std::iter::once(map).chain(clones).collect();
        let mut heights = Vec::with_capacity(cells * n);
        let mut spread = Vec::with_capacity(cells);
        for i in 0..cells {
            let mut steepest = world.slope_deg(i as u32);
            let mut widest = 0.0f64;
            for m in &members {
                heights.push(f32::from_bits(m.elevation[i].load(Ordering::Relaxed)));
                widest = widest.max(attitude_change(map.normal(i as u32), m.normal(i as u32)));
                // NaN (missing data) on any member stays NaN: the cell is impassable.
                let s = m.slope_deg(i as u32);
                steepest = if s.is_nan() || steepest.is_nan() { f64::NAN } else { steepest.max(s) };
            }
            world.slope_deg[i].store((steepest as f32).to_bits(), Ordering::Relaxed);
            // Rounded up past single precision's rounding (zero stays zero: members
            // that agree leave the map's sunlight as it is).
            spread.push((widest * (1.0 + 1e-6)) as f32);
        }
        // The highest horizon of every member, held as the envelope's own map (a
        // lookup per `lit` as fast as the map's) where any member's differs.
        if let Some(map_horizon) = &world.horizon {
            let sensed = |w: &World, i: usize| w.horizon_sensed[i].load(Ordering::Relaxed);
            let raised = (0..cells).filter(|&i| sensed(&world, i) || clones.iter().any(|c| sensed(c, i)));
            let profiles = raised.filter_map(|i| {
                let mut highest = world.horizon_profile(i)?;
                for c in clones {
                    for (h, v) in highest.iter_mut().zip(c.horizon_profile(i)?) {
                        *h = h.max(v);
                    }
                }
                Some((i, highest))
            });
            let own = map_horizon.raised(profiles.collect::<Vec<_>>());
            world.horizon = Some(Arc::new(own));
            world.shares_horizon = false;
            world.sensed_horizon.lock().unwrap_or_else(std::sync::PoisonError::into_inner).clear();
            for flag in &world.horizon_sensed {
                flag.store(false, Ordering::Relaxed);
            }
        }
        world.members = Some(Arc::new(Members { n, heights, spread }));
        world.members_off = (0..cells).map(|_| AtomicBool::new(false)).collect();
        Ok(world)
    }

    /// How many terrains the world stands for: 1, or the members of an envelope
    /// ([`World::envelope`]).
    pub fn terrain_members(&self) -> usize {
        self.members.as_ref().map_or(1, |m| m.n)
    }

    /// The members' heights at a cell, m (NaN: missing), when the world is an envelope
    /// and the cell has not been sensed since.
    pub(crate) fn member_heights(&self, cell: u32) -> Option<&[f32]> {
        let m = self.members.as_ref()?;
        let i = cell as usize;
        (!self.members_off[i].load(Ordering::Relaxed)).then(|| &m.heights[i * m.n..(i + 1) * m.n])
    }

    /// How far the members' ground normals tip anything on the ground away from where
    /// the map's normal tips it, at a cell of an envelope not sensed since: the largest
    /// ‖(R_i − R_map)·v‖ over members i and unit vectors v, R the rotation that takes
    /// straight up to a ground normal. A unit vector on the rover (its array's normal)
    /// then points within this chord of where it points on the map, so its cosine with
    /// any unit direction (the Sun's) is within this of the map's.
    pub(crate) fn attitude_spread(&self, cell: u32) -> Option<f64> {
        let m = self.members.as_ref()?;
        let i = cell as usize;
        (!self.members_off[i].load(Ordering::Relaxed)).then(|| f64::from(m.spread[i]))
    }

    /// The DEM.
    pub fn dem(&self) -> &Dem {
        &self.dem
    }

    /// The instant t = 0.
    pub fn epoch(&self) -> Epoch {
        self.epoch
    }

    /// The reference site.
    pub fn site(&self) -> Site {
        self.site
    }

    /// Where true north points on the grid at the site, degrees clockwise from the
    /// grid's north: what the Sun's and the Earth's true azimuths were turned by.
    pub fn true_north_on_grid_deg(&self) -> f64 {
        self.dem.georef().projection.true_north_on_grid_deg(self.site.lon_east_deg())
    }

    /// The tabulated span, s.
    pub fn span_s(&self) -> f64 {
        (self.sun.len() - 2) as f64 * self.sun_step_s
    }

    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.normal.len()
    }

    /// Columns.
    pub fn cols(&self) -> usize {
        self.dem.cols()
    }

    /// Rows.
    pub fn rows(&self) -> usize {
        self.dem.rows()
    }

    /// The cell index of (col, row).
    pub fn cell(&self, col: usize, row: usize) -> u32 {
        (row * self.dem.cols() + col) as u32
    }

    /// (col, row) of a cell.
    pub fn col_row(&self, cell: u32) -> (usize, usize) {
        let c = cell as usize;
        (c % self.dem.cols(), c / self.dem.cols())
    }

    /// The cell containing map point (x, y), m, if on the map: its four edges included,
    /// a point on the east or south edge in the last column or row.
    pub fn cell_at(&self, x: f64, y: f64) -> Option<u32> {
        let d = &self.dem;
        let (cols, rows) = (d.cols() as f64, d.rows() as f64);
        // The map's four edges alike: a point on the east or south edge is in the last
        // column or row, as one on the west or north edge is in the first.
        let col = ((x - d.x0()) / d.dx()).floor();
        let col = if col == cols && x <= d.x0() + cols * d.dx() { col - 1.0 } else { col };
        let row = ((d.y_top() - y) / d.dy()).floor();
        let row = if row == rows && y >= d.y_top() - rows * d.dy() { row - 1.0 } else { row };
        (col >= 0.0 && row >= 0.0 && col < cols && row < rows).then(|| self.cell(col as usize, row as usize))
    }

    /// Fewest 8-connected steps between two cells.
    pub fn chebyshev(&self, a: u32, b: u32) -> f64 {
        let (ac, ar) = self.col_row(a);
        let (bc, br) = self.col_row(b);
        ac.abs_diff(bc).max(ar.abs_diff(br)) as f64
    }

    /// Octile distance between cell centres, m.
    pub fn octile_m(&self, a: u32, b: u32) -> f64 {
        let (ac, ar) = self.col_row(a);
        let (bc, br) = self.col_row(b);
        let (dx, dy) = (ac.abs_diff(bc) as f64 * self.dem.dx(), ar.abs_diff(br) as f64 * self.dem.dy());
        let (lo, hi) = (dx.min(dy), dx.max(dy));
        hi - lo + lo * std::f64::consts::SQRT_2
    }

    /// Centre of a cell, map frame, m.
    pub fn center(&self, cell: u32) -> (f64, f64) {
        let (c, r) = self.col_row(cell);
        self.dem.cell_center(c, r)
    }

    /// Elevation of a cell, m (`None` on missing data).
    pub fn elevation(&self, cell: u32) -> Option<f64> {
        let z = f32::from_bits(self.elevation[cell as usize].load(Ordering::Relaxed));
        (!z.is_nan()).then_some(f64::from(z))
    }

    /// Slope of a cell, degrees (NaN on missing data).
    pub fn slope_deg(&self, cell: u32) -> f64 {
        f64::from(f32::from_bits(self.slope_deg[cell as usize].load(Ordering::Relaxed)))
    }

    /// Upward unit ground normal of a cell, east-north-up.
    pub fn normal(&self, cell: u32) -> [f64; 3] {
        let n = &self.normal[cell as usize];
        let (e, n) = (
            f64::from(f32::from_bits(n[0].load(Ordering::Relaxed))),
            f64::from(f32::from_bits(n[1].load(Ordering::Relaxed))),
        );
        [e, n, (1.0 - e * e - n * n).max(0.0).sqrt()]
    }

    /// The most any passable cell's ground tips the rover from level, degrees (the
    /// angle of its [`World::normal`] from the vertical): as the map is now.
    pub fn steepest_tilt_deg(&self) -> f64 {
        let cells = (0..self.normal.len() as u32).filter(|&c| self.passable(c));
        let cos = cells.map(|c| self.normal(c)[2]).fold(1.0, f64::min);
        cos.clamp(-1.0, 1.0).acos().to_degrees()
    }

    /// Whether a cell can be entered: valid data and not blocked.
    pub fn passable(&self, cell: u32) -> bool {
        !self.blocked[cell as usize].load(Ordering::Relaxed) && self.slope_deg(cell).is_finite()
    }

    /// Marks cells impassable (or passable again): a sensed obstacle. Returns the cells
    /// whose state changed, for re-planning.
    pub fn set_blocked(&self, cells: &[u32], blocked: bool) -> Vec<u32> {
        let mut changed = Vec::new();
        for &c in cells {
            if self.blocked[c as usize].swap(blocked, Ordering::Relaxed) != blocked {
                changed.push(c);
            }
        }
        changed
    }

    /// Overrides the slope of cells (a sensed slope map), degrees. Returns the cells
    /// whose slope changed.
    pub fn set_slope(&self, cells: &[(u32, f64)]) -> Vec<u32> {
        let mut changed = Vec::new();
        for &(c, s) in cells {
            let bits = (s as f32).to_bits();
            if self.slope_deg[c as usize].swap(bits, Ordering::Relaxed) != bits {
                changed.push(c);
            }
        }
        changed
    }

    /// Senses `cells` on the true terrain `truth` (a world on the same grid): copies
    /// its elevation, slope, ground normal and — where both have horizon maps — the
    /// horizon, so light and shadow there are the true ones. Returns the cells whose
    /// values changed, for re-planning.
    pub fn sense(&self, truth: &World, cells: &[u32]) -> Result<Vec<u32>> {
        if truth.cols() != self.cols() || truth.rows() != self.rows() {
            return Err(Error::Config {
                field: "truth",
                message: format!(
                    "the true terrain is {}×{} cells and the map {}×{}: they must share one grid",
                    truth.cols(),
                    truth.rows(),
                    self.cols(),
                    self.rows()
                ),
            });
        }
        let mut changed = Vec::new();
        for &c in cells {
            let i = c as usize;
            let mut differs = false;
            let copy = |dst: &AtomicU32, src: &AtomicU32, differs: &mut bool| {
                let v = src.load(Ordering::Relaxed);
                if dst.swap(v, Ordering::Relaxed) != v {
                    *differs = true;
                }
            };
            copy(&self.elevation[i], &truth.elevation[i], &mut differs);
            copy(&self.slope_deg[i], &truth.slope_deg[i], &mut differs);
            if let Some(off) = self.members_off.get(i) {
                // The members' spread ends where the rover has seen the ground.
                differs |= !off.swap(true, Ordering::Relaxed);
            }
            for k in 0..2 {
                copy(&self.normal[i][k], &truth.normal[i][k], &mut differs);
            }
            if let (Some(believed), Some(truth_profile)) = (self.horizon_profile(i), truth.horizon_profile(i)) {
                // A horizon that differs only where neither the Sun nor the Earth ever
                // stands near it changes no answer of `lit` or `earth_visible`, so no
                // step's cost: the cell is not reported (its repair would reopen every
                // time class there for nothing).
                if believed != truth_profile && self.horizon_change_is_seen(&believed, &truth_profile) {
                    differs = true;
                }
                let mut table = self.sensed_horizon.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
                table.insert(c, truth_profile.into_boxed_slice());
                self.horizon_sensed[i].store(true, Ordering::Relaxed);
            }
            if differs {
                changed.push(c);
            }
        }
        Ok(changed)
    }

    /// Whether replacing a cell's horizon profile `old` by `new` can change whether the
    /// Sun lights it or the Earth is in view from it at some instant of the span. The
    /// Sun and the Earth move linearly in azimuth (the shorter way) and elevation
    /// between table samples ([`World::sun`], [`World::earth`]), and the profile is
    /// interpolated linearly between sectors, so over one table interval the floor
    /// stays within the values of the sectors the azimuth passes through and their next ones:
    /// if the body stands above both profiles there, or at or below both, nothing can
    /// differ. Conservative: `true` whenever that cannot be shown.
    fn horizon_change_is_seen(&self, old: &[f32], new: &[f32]) -> bool {
        let sectors = old.len();
        if sectors == 0 || new.len() != sectors {
            return old != new;
        }
        let width = 360.0 / sectors as f64;
        let seen = |(a_az, a_el): (f64, f64), (b_az, b_el): (f64, f64)| {
            let (el_lo, el_hi) = (a_el.min(b_el), a_el.max(b_el));
            if el_hi <= 0.0 {
                return false; // below the horizontal: unseen under both floors (≥ 0)
            }
            let daz = (b_az - a_az + 180.0).rem_euclid(360.0) - 180.0;
            let from = a_az.min(a_az + daz);
            let first = (from / width).floor() as i64;
            let last = ((from + daz.abs()) / width).floor() as i64 + 1;
            let (mut lo, mut hi, mut same) = (f64::INFINITY, 0.0f64, true);
            for s in first..=last {
                let k = s.rem_euclid(sectors as i64) as usize;
                let (o, n) = (f64::from(old[k]).max(0.0), f64::from(new[k]).max(0.0));
                same &= o == n;
                lo = lo.min(o.min(n));
                hi = hi.max(o.max(n));
            }
            !(same || el_lo > hi || el_hi <= lo)
        };
        let sun = self
            .sun
            .windows(2)
            .any(|w| seen((w[0].azimuth_deg, w[0].elevation_deg), (w[1].azimuth_deg, w[1].elevation_deg)));
        sun || self
            .earth
            .windows(2)
            .any(|w| seen((w[0].azimuth_deg, w[0].elevation_deg), (w[1].azimuth_deg, w[1].elevation_deg)))
    }

    /// The Sun table's step, s.
    pub fn sun_step_s(&self) -> f64 {
        self.sun_step_s
    }

    /// The Sun at time `t` (s after the epoch), interpolated; clamped to the table.
    pub fn sun(&self, t: f64) -> GridSun {
        let pos = (t / self.sun_step_s).clamp(0.0, (self.sun.len() - 1) as f64);
        let k = (pos as usize).min(self.sun.len() - 2);
        let f = pos - k as f64;
        let (a, b) = (&self.sun[k], &self.sun[k + 1]);
        // Linear in every field (samples are minutes apart): cheaper than renormalising
        // and converting, and within 0.01° at a 2-minute step.
        let enu: [f64; 3] = std::array::from_fn(|i| a.enu[i] + (b.enu[i] - a.enu[i]) * f);
        let mut daz = b.azimuth_deg - a.azimuth_deg;
        if daz > 180.0 {
            daz -= 360.0;
        } else if daz < -180.0 {
            daz += 360.0;
        }
        // Tabulated azimuths are in [0, 360) and |daz| ≤ 180: one wrap at most, without
        // fmod.
        let az = a.azimuth_deg + daz * f;
        let azimuth_deg = if az < 0.0 {
            az + 360.0
        } else if az >= 360.0 {
            az - 360.0
        } else {
            az
        };
        GridSun {
            direction: GridSunDirection::new(azimuth_deg, a.elevation_deg + (b.elevation_deg - a.elevation_deg) * f),
            enu,
            beam_w_m2: a.beam_w_m2 + (b.beam_w_m2 - a.beam_w_m2) * f,
        }
    }

    /// Local true solar time at east longitude `lon_east_deg` at time `t` (s after the
    /// epoch), hours: Mars24's LTST on Mars, the sub-solar longitude's elsewhere.
    pub fn local_solar_time_h(&self, t: f64, lon_east_deg: f64) -> f64 {
        let epoch = self.epoch + Duration::from_seconds(t);
        match self.body {
            Body::Mars => areo_ephemeris::SolarGeometry::at(epoch).ltst_hours(lon_east_deg),
            other => other.sun(epoch).local_solar_time_hours(lon_east_deg),
        }
    }

    /// The local solar day at east longitude `lon_east_deg` at `t` s after the epoch,
    /// counted from the epoch's (0: the day the world starts; on the Moon a lunar day):
    /// the number of local midnights passed, consistent with
    /// [`World::local_solar_time_h`] however the equation of time moves it.
    pub fn local_sol(&self, t: f64, lon_east_deg: f64) -> i64 {
        let days = t / self.body.solar_day_s();
        let turned = (self.local_solar_time_h(0.0, lon_east_deg) - self.local_solar_time_h(t, lon_east_deg)) / 24.0;
        (days + turned).round() as i64
    }

    /// The body the world is on.
    pub fn body(&self) -> Body {
        self.body
    }

    /// The Earth at time `t` (s after the epoch), interpolated; `None` on the Earth.
    pub fn earth(&self, t: f64) -> Option<EarthSky> {
        if self.earth.len() < 2 {
            return None;
        }
        let pos = (t / self.sun_step_s).clamp(0.0, (self.earth.len() - 1) as f64);
        let k = (pos as usize).min(self.earth.len() - 2);
        let f = pos - k as f64;
        let (a, b) = (&self.earth[k], &self.earth[k + 1]);
        let daz = (b.azimuth_deg - a.azimuth_deg + 180.0).rem_euclid(360.0) - 180.0;
        Some(EarthSky {
            azimuth_deg: (a.azimuth_deg + daz * f).rem_euclid(360.0),
            elevation_deg: a.elevation_deg + (b.elevation_deg - a.elevation_deg) * f,
        })
    }

    /// Whether the Earth is in view from a cell at time `t`: above the horizontal and
    /// above the terrain's horizon there (the cell's horizon map, as for the Sun).
    /// Always false on the Earth.
    pub fn earth_visible(&self, cell: u32, t: f64) -> bool {
        self.earth(t).is_some_and(|e| e.elevation_deg > self.horizon_floor_deg(cell, e.azimuth_deg))
    }

    /// The terrain's horizon at a cell toward `azimuth_deg`, not below the horizontal,
    /// degrees: what the Sun must stand above to light the cell.
    pub fn horizon_floor_deg(&self, cell: u32, azimuth_deg: f64) -> f64 {
        match &self.horizon {
            Some(_) if self.horizon_sensed[cell as usize].load(Ordering::Relaxed) => {
                let table = self.sensed_horizon.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
                table.get(&cell).map_or(0.0, |p| HorizonMap::profile_deg(p, azimuth_deg).max(0.0))
            }
            Some(h) => h.horizon_deg(cell as usize, azimuth_deg).max(0.0),
            None => 0.0,
        }
    }

    /// Cell `i`'s horizon profile (degrees per sector), sensed or from the map.
    fn horizon_profile(&self, i: usize) -> Option<Vec<f32>> {
        let map = self.horizon.as_ref()?;
        if self.horizon_sensed[i].load(Ordering::Relaxed) {
            let table = self.sensed_horizon.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
            if let Some(p) = table.get(&(i as u32)) {
                return Some(p.to_vec());
            }
        }
        Some(map.cell_profile(i))
    }

    /// Whether the Sun lights a cell: above the horizontal and above the terrain's
    /// horizon there.
    pub fn lit(&self, cell: u32, sun: &GridSun) -> bool {
        sun.elevation_deg > self.horizon_floor_deg(cell, sun.azimuth_deg)
    }

    /// The Sun's elevation above a cell's ground plane, degrees (TEMPEST's LOS-map value).
    pub fn sun_above_ground_deg(&self, cell: u32, sun: &GridSun) -> f64 {
        let n = self.normal(cell);
        (n[0] * sun.enu[0] + n[1] * sun.enu[1] + n[2] * sun.enu[2]).clamp(-1.0, 1.0).asin().to_degrees()
    }

    /// The tabulated Sun, one sample per Sun step from t = 0.
    pub fn sun_table(&self) -> &[GridSun] {
        &self.sun
    }

    /// Largest beam flux in the table, W/m².
    pub fn max_beam_w_m2(&self) -> f64 {
        self.sun.iter().map(|s| s.beam_w_m2).fold(0.0, f64::max)
    }

    /// Latitude and east longitude of a cell's centre (the site's if the DEM has no
    /// georeference).
    pub fn lat_lon(&self, cell: u32) -> (f64, f64) {
        let (x, y) = self.center(cell);
        self.dem.geographic(x, y).unwrap_or((self.site.lat_deg(), self.site.lon_east_deg()))
    }

    /// Bytes held by the world's grids (a shared horizon map counts for its owner only).
    pub fn bytes(&self) -> usize {
        let cells = self.cells();
        let sectors = self.horizon.as_ref().map_or(0, |h| h.sectors());
        let sensed = self.sensed_horizon.lock().map_or(0, |t| t.len() * (sectors * 4 + 24));
        let map = if self.shares_horizon { 0 } else { self.horizon.as_ref().map_or(0, |h| h.bytes()) };
        let members =
            self.members.as_ref().map_or(0, |m| m.heights.len() * 4 + m.spread.len() * 4 + self.members_off.len());
        cells * (4 + 4 + 8 + 2) + map + sensed + self.sun.len() * 48 + self.earth.len() * 16 + members
    }

    /// Holds the horizon map in one byte per angle ([`HorizonMap::narrowed`]: half the
    /// memory, angles within 0.353° of the two-byte map's) when that error is small
    /// against the planner's time classes of `time_s`: a horizon error e moves a shadow's
    /// edge by what the Sun's elevation does in e/ω, ω its fastest elevation change over
    /// the span (¼° a minute at Mars's equator, almost none at a pole), so the map is
    /// narrowed when e/ω is at most half a class. Returns e/ω, s, when it narrowed;
    /// `None` (the map kept) without a horizon map, when it is shared or when the Sun
    /// is too slow. Call it before building a truth on this map, which then shares the
    /// narrowed map and keeps its differences at that precision.
    pub fn narrow_horizon_within(&mut self, time_s: f64) -> Option<f64> {
        if self.shares_horizon {
            return None;
        }
        let map = self.horizon.as_ref()?;
        let error = areo_terrain::horizon::NARROW_ERROR_DEG;
        let fastest = self
            .sun
            .windows(2)
            .map(|w| (w[1].elevation_deg - w[0].elevation_deg).abs() / self.sun_step_s)
            .fold(0.0, f64::max);
        let shift = error / fastest;
        if !(shift <= time_s / 2.0) {
            return None;
        }
        if !map.is_narrow() {
            self.horizon = Some(Arc::new(map.narrowed()));
        }
        Some(shift)
    }

    /// Whether the horizon map holds one byte per angle (see
    /// [`World::narrow_horizon_within`]).
    pub fn horizon_is_narrow(&self) -> bool {
        self.horizon.as_ref().is_some_and(|h| h.is_narrow())
    }

    /// The true world a rover drives on, on the map's grid, for simulation: like
    /// [`World::new`], except that with the same horizon sectors as `map` it shares the
    /// map's horizon map and keeps only where the true horizon differs
    /// ([`HorizonMap::changes_from`], tracing only the lines near the cells the truth
    /// changes; [`HorizonMap::changes`] for a region, whose horizons are a larger map's)
    /// — as if those cells' horizons had been sensed. Holding
    /// one full map instead of two halves the horizons' memory (0.38 GB at the LITA
    /// map's size and 32 sectors).
    pub fn truth(dem: Dem, config: &WorldConfig, sun_model: &impl SunModel, map: &World) -> Result<World> {
        let shared = match (&map.horizon, config.horizon_sectors) {
            (Some(h), Some(k)) if h.sectors() == k && map.cols() == dem.cols() && map.rows() == dem.rows() => h.clone(),
            _ => return World::new(dem, config, sun_model),
        };
        // Only the lines near the cells the truth changes can differ, where the map's
        // horizons were traced on the map's own DEM.
        let curvature = curvature_of(sun_model.body());
        let changes = if map.horizon_of_dem {
            shared.changes_from(&map.dem, &dem, curvature)?
        } else {
            shared.changes(&dem, curvature)?
        };
        let mut world = World::new(dem, &WorldConfig { horizon_sectors: None, ..config.clone() }, sun_model)?;
        world.horizon = Some(shared);
        world.shares_horizon = true;
        let mut table = world.sensed_horizon.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        for i in 0..world.cells() {
            if let Some(p) = changes.profile(i) {
                table.insert(i as u32, p.into());
                world.horizon_sensed[i].store(true, Ordering::Relaxed);
            }
        }
        drop(table);
        Ok(world)
    }
}

/// The site the Sun is computed at: the configured one, or the DEM's middle cell where
/// its georeference tells where that is; on the Sun model's body.
fn site_of(dem: &Dem, config: &WorldConfig, sun_model: &impl SunModel) -> Result<Site> {
    let site = match config.site {
        Some(s) => s,
        None => {
            let (x, y) = dem.cell_center(dem.cols() / 2, dem.rows() / 2);
            let (lat, lon) = dem.geographic(x, y).ok_or(Error::Config {
                field: "site",
                message: "the DEM has no georeference: give the site's latitude and longitude".into(),
            })?;
            Site::on(sun_model.body(), lat, lon).map_err(|e| Error::Config { field: "site", message: e.to_string() })?
        }
    };
    if site.body() != sun_model.body() {
        return Err(Error::Config {
            field: "site",
            message: format!("a site on {} under the Sun of {}", site.body(), sun_model.body()),
        });
    }
    Ok(site)
}

/// The Sun and the Earth in the sky at `site` every Sun step over the span, directions
/// on the grid's axes, as slopes, headings and horizon sectors are.
fn sky_tables(
    dem: &Dem,
    config: &WorldConfig,
    sun_model: &impl SunModel,
    site: &Site,
) -> (Vec<GridSun>, Vec<EarthSky>) {
    let body = sun_model.body();
    let n = (config.span_s / config.sun_step_s).ceil() as usize + 2;
    // Every direction in the sky is kept on the grid's axes, as slopes, headings
    // and horizon sectors are: where the map's meridians are not its columns (a
    // polar map whose central meridian is not the site's) true azimuths turn by
    // the grid's convergence at the site.
    let projection = dem.georef().projection;
    let (sin_n, cos_n) = projection.true_north_on_grid_deg(site.lon_east_deg()).to_radians().sin_cos();
    let on_grid = |azimuth_deg: f64| projection.grid_azimuth_deg(azimuth_deg, site.lon_east_deg());
    let sun = (0..n)
        .map(|k| {
            let at = config.epoch + Duration::from_seconds(k as f64 * config.sun_step_s);
            let state = sun_model.sun(at);
            let p = state.at_site(site);
            let [e, nn, u] = p.direction_enu;
            GridSun {
                direction: GridSunDirection::new(on_grid(p.azimuth_deg), p.elevation_deg),
                enu: [e * cos_n + nn * sin_n, nn * cos_n - e * sin_n, u],
                beam_w_m2: config.atmosphere.beam_w_m2(p.elevation_deg, state.distance_au),
            }
        })
        .collect();
    let earth = (0..n)
        .map_while(|k| {
            let at = config.epoch + Duration::from_seconds(k as f64 * config.sun_step_s);
            let (azimuth_deg, elevation_deg) = body.earth(at)?.at_site(site);
            Some(EarthSky { azimuth_deg: on_grid(azimuth_deg), elevation_deg })
        })
        .collect();
    (sun, earth)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(v: [f64; 3]) -> [f64; 3] {
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        [v[0] / n, v[1] / n, v[2] / n]
    }

    #[test]
    fn the_attitude_change_bounds_how_far_any_vector_on_the_rover_moves_and_is_reached() {
        // Ground normals up to ~30° from vertical, in every direction; vectors on the
        // rover on a fine sphere grid.
        let normals: Vec<[f64; 3]> = (0..12)
            .flat_map(|k| {
                let az = f64::from(k) * 0.52;
                [0.02, 0.2, 0.55].map(|t: f64| unit([t * az.cos(), t * az.sin(), 1.0]))
            })
            .collect();
        let vectors: Vec<[f64; 3]> = (0..36)
            .flat_map(|i| {
                (1..18).map(move |j| {
                    let (az, po) = (f64::from(i) * 10f64.to_radians(), f64::from(j) * 10f64.to_radians());
                    [po.sin() * az.cos(), po.sin() * az.sin(), po.cos()]
                })
            })
            .collect();
        for &a in &normals {
            for &b in &normals {
                let bound = attitude_change(a, b);
                let mut largest = 0.0f64;
                for &v in &vectors {
                    let (ra, rb) = (SolarArray::tipped_normal_enu(v, a), SolarArray::tipped_normal_enu(v, b));
                    largest = largest
                        .max(((ra[0] - rb[0]).powi(2) + (ra[1] - rb[1]).powi(2) + (ra[2] - rb[2]).powi(2)).sqrt());
                }
                assert!(largest <= bound + 1e-12, "{a:?} {b:?}: {largest} > {bound}");
                // Reached to within the grid's spacing (10°): the bound is not loose.
                assert!(largest >= bound * 0.98 - 1e-12, "{a:?} {b:?}: {largest} vs {bound}");
            }
        }
        assert_eq!(attitude_change(normals[3], normals[3]), 0.0);
    }
}
