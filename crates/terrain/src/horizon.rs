//! Horizon maps and sunlight maps.
//!
//! A [`HorizonMap`] stores, per cell, the elevation angle of the terrain's horizon in K
//! equal azimuth sectors (16–360), two bytes per cell per sector. Whether the Sun is
//! occluded at any direction is then a lookup with linear interpolation between the
//! two nearest sector centres — which makes sequences of line-of-sight maps over a sol
//! cheap: one horizon map, then one lookup per cell per time step.
//!
//! Each sector's horizon comes from [`horizon_toward`] along its centre azimuth: upper
//! convex hulls along parallel lines, exact along each line. Planetary curvature
//! lowers an occluder at distance d by d²/2R. The lines are laid on the whole map's
//! lattice even when a window of it is computed, so that
//! [`crate::tiles::horizon_by_tiles`] gives the whole map's horizons tile by tile.
//!
//! **Error against each cell's own ray** (brute force on the triangulated surface,
//! `reference::horizon_on_triangles`, every cell of every sector centre, border
//! cells excluded; `tests/horizon_error.rs`): on the real Gale MOLA crop (463 m cells)
//! 99 % of cells within 1.83°, 99.9 % within 5.73°, the worst 18.97°; on synthesised
//! terrain 1.18°, 3.55°, 11.91°. The large errors are cells whose nearest occluder is a
//! cell or two away, where a ray line's terrain beside the own ray differs most. On
//! the border the own ray may leave the map at once (no horizon) while the ray line
//! beside it stays in. Tests assert 2°, 6° and 20°. This is an approximation, not an
//! exact horizon: `Method::OwnRay` (crate::shadow) is the exact one.

use rayon::prelude::*;

use crate::dem::{Dem, unit_normal};
use crate::error::{Error, Result};
use crate::ray_lines::LineGeometry;
use crate::shadow::Curvature;
use crate::slope::horn_gradient;

/// A sector to trace, its output, and the opposite sector's output when traced with it.
type SectorJob<'a> = (usize, &'a mut [u16], Option<&'a mut [u16]>);

/// Horizon elevation per cell and azimuth sector.
#[derive(Debug, Clone, PartialEq)]
pub struct HorizonMap {
    cols: usize,
    rows: usize,
    sectors: usize,
    /// Sector-major: `angles[s * cells + i]`.
    angles: Codes,
}

/// A horizon map's angles: two bytes each ([`encode`], 0.0027° steps) or one
/// ([`HorizonMap::narrowed`], [`NARROW_STEP_DEG`] steps).
#[derive(Debug, Clone, PartialEq)]
enum Codes {
    Wide(Vec<u16>),
    Narrow(Vec<u8>),
}

/// Degrees per step of a one-byte horizon: −90°..90° onto 0..255.
pub const NARROW_STEP_DEG: f64 = 180.0 / 255.0;

/// The most a one-byte angle differs from the two-byte one it was narrowed from,
/// degrees: half a step.
pub const NARROW_ERROR_DEG: f64 = NARROW_STEP_DEG / 2.0;

/// A two-byte code as the nearest one-byte code.
fn narrow(v: u16) -> u8 {
    // Both scales run from −90° to 90°: 65535 = 255 × 257.
    ((u32::from(v) + 128) / 257) as u8
}

fn decode_narrow(v: u8) -> f64 {
    f64::from(v) * NARROW_STEP_DEG - 90.0
}

impl Codes {
    #[inline]
    fn deg(&self, k: usize) -> f64 {
        match self {
            Codes::Wide(a) => decode(a[k]),
            Codes::Narrow(a) => decode_narrow(a[k]),
        }
    }
}

/// Degrees per step of an encoded horizon (code × this + [`CODE_OFFSET_DEG`]).
pub const CODE_STEP_DEG: f64 = 180.0 / 65535.0;
/// The elevation of code 0, degrees.
pub const CODE_OFFSET_DEG: f64 = -90.0;

/// −90°..90° onto 0..65535 (0.0027° steps).
pub(crate) fn encode(deg: f64) -> u16 {
    // Non-negative, so adding a half and truncating rounds (`round` is a libm call).
    ((deg.clamp(-90.0, 90.0) + 90.0) / 180.0 * 65535.0 + 0.5) as u16
}

fn decode(v: u16) -> f64 {
    f64::from(v) / 65535.0 * 180.0 - 90.0
}

impl HorizonMap {
    /// Bytes a horizon map of `sectors` sectors holds per cell at most (two bytes per
    /// angle; a narrowed map holds half), for memory estimates made before it is built.
    pub fn bytes_per_cell(sectors: usize) -> u64 {
        2 * sectors as u64
    }

    /// Computes the horizon in `sectors` sectors (16..=360) centred on azimuths
    /// k·360°/K, sectors in parallel (the result does not depend on the thread count).
    pub fn compute(dem: &Dem, sectors: usize, curvature: Curvature) -> Result<HorizonMap> {
        HorizonMap::compute_at(dem, sectors, curvature, (0, 0))
    }

    /// [`HorizonMap::compute`] of a window whose first cell is (`col`, `row`) of a larger
    /// map: the ray lines are laid where the whole map's lie, so that a cell whose
    /// horizon the window's terrain decides gets the whole map's value bit for bit.
    pub(crate) fn compute_at(
        dem: &Dem,
        sectors: usize,
        curvature: Curvature,
        origin: (usize, usize),
    ) -> Result<HorizonMap> {
        if !(16..=360).contains(&sectors) {
            return Err(Error::BadGrid(format!("{sectors} horizon sectors: allowed 16..=360")));
        }
        let cells = dem.cols() * dem.rows();
        let zn = Elevations::of(dem);
        // Each sector written in place; opposite sectors (when K is even) from one
        // trace of their common lines.
        let mut angles = vec![0u16; cells * sectors];
        let paired = sectors.is_multiple_of(2);
        let jobs = if paired { sectors / 2 } else { sectors };
        let mut outs: Vec<&mut [u16]> = angles.chunks_mut(cells.max(1)).collect();
        // (sector, its output, the opposite sector's output)
        let mut pairs: Vec<SectorJob<'_>> = Vec::with_capacity(jobs);
        if paired {
            let opposite = outs.split_off(jobs);
            for (s, (a, b)) in outs.into_iter().zip(opposite).enumerate() {
                pairs.push((s, a, Some(b)));
            }
        } else {
            for (s, a) in outs.into_iter().enumerate() {
                pairs.push((s, a, None));
            }
        }
        trace_sectors(dem, &zn, sectors, curvature, origin, pairs);
        Ok(HorizonMap { cols: dem.cols(), rows: dem.rows(), sectors, angles: Codes::Wide(angles) })
    }

    /// The map with one byte per angle instead of two: half the memory, each angle
    /// within half a step ([`HorizonMap::error_deg`], 0.353°) of this map's. For
    /// planners whose time resolution makes that error small (the Sun's elevation moves
    /// at most ¼° a minute on Mars); a polar Sun that skims the horizon all day needs
    /// the two-byte map.
    pub fn narrowed(&self) -> HorizonMap {
        let angles = match &self.angles {
            Codes::Wide(a) => Codes::Narrow(a.iter().map(|&v| narrow(v)).collect()),
            Codes::Narrow(a) => Codes::Narrow(a.clone()),
        };
        HorizonMap { cols: self.cols, rows: self.rows, sectors: self.sectors, angles }
    }

    /// This map raised, cell by cell and sector by sector, to the profiles given for
    /// some cells (degrees per sector, as [`HorizonMap::cell_profile`]): the upper
    /// envelope of several terrains' horizons, for a planner that must find a cell lit
    /// only when it is lit on each of them. A raised angle is rounded up to the map's
    /// encoding, so no angle ends below any profile's; a profile of the wrong length
    /// is skipped.
    pub fn raised(&self, profiles: impl IntoIterator<Item = (usize, Vec<f32>)>) -> HorizonMap {
        let cells = self.cols * self.rows;
        let mut map = self.clone();
        for (i, profile) in profiles {
            if i >= cells || profile.len() != self.sectors {
                continue;
            }
            for (s, &deg) in profile.iter().enumerate() {
                let k = s * cells + i;
                let up = (f64::from(deg).clamp(-90.0, 90.0) + 90.0) / 180.0;
                match &mut map.angles {
                    Codes::Wide(a) => a[k] = a[k].max((up * 65535.0).ceil().min(65535.0) as u16),
                    Codes::Narrow(a) => a[k] = a[k].max((up * 255.0).ceil().min(255.0) as u8),
                }
            }
        }
        map
    }

    /// Whether the map holds one byte per angle ([`HorizonMap::narrowed`]).
    pub fn is_narrow(&self) -> bool {
        matches!(self.angles, Codes::Narrow(_))
    }

    /// The most an angle can differ from the two-byte map's because of its encoding,
    /// degrees: half a one-byte step for a narrowed map, zero otherwise.
    pub fn error_deg(&self) -> f64 {
        if self.is_narrow() { NARROW_ERROR_DEG } else { 0.0 }
    }

    /// Sector `s`'s horizons as two-byte codes ([`encode`]), cell by cell (row-major).
    pub(crate) fn sector_codes(&self, s: usize) -> std::borrow::Cow<'_, [u16]> {
        let cells = self.cols * self.rows;
        match &self.angles {
            Codes::Wide(a) => std::borrow::Cow::Borrowed(&a[s * cells..(s + 1) * cells]),
            Codes::Narrow(a) => a[s * cells..(s + 1) * cells].iter().map(|&v| u16::from(v) * 257).collect(),
        }
    }

    /// The map of the window `cols` × `rows` from (`col0`, `row0`), horizons below
    /// `floor_deg` raised to it (None: kept).
    pub(crate) fn window(
        &self,
        (col0, row0, cols, rows): (usize, usize, usize, usize),
        floor_deg: Option<f64>,
    ) -> HorizonMap {
        let floor = floor_deg.map_or(0, encode);
        let mut angles = Vec::with_capacity(cols * rows * self.sectors);
        for s in 0..self.sectors {
            let codes = self.sector_codes(s);
            for r in row0..row0 + rows {
                angles.extend(codes[r * self.cols + col0..][..cols].iter().map(|c| (*c).max(floor)));
            }
        }
        let window = HorizonMap { cols, rows, sectors: self.sectors, angles: Codes::Wide(angles) };
        if self.is_narrow() { window.narrowed() } else { window }
    }

    /// The horizon of `dem` — the terrain a rover truly drives on, on this map's grid —
    /// where it differs from this map, cell by cell: the same trace as
    /// [`HorizonMap::compute`], run a few sectors at a time and compared with this map,
    /// so that a second full map is never held. Cells whose surroundings are the same
    /// on both get the same horizon bit for bit and are left out.
    pub fn changes(&self, dem: &Dem, curvature: Curvature) -> Result<HorizonChanges> {
        let cells = dem.cols() * dem.rows();
        if dem.cols() != self.cols || dem.rows() != self.rows {
            return Err(Error::BadGrid(format!(
                "{}×{} cells against a horizon map of {}×{}: they must share one grid",
                dem.cols(),
                dem.rows(),
                self.cols,
                self.rows
            )));
        }
        let sectors = self.sectors;
        let zn = Elevations::of(dem);
        let paired = sectors.is_multiple_of(2);
        let jobs = if paired { sectors / 2 } else { sectors };
        let per_job = if paired { 2 } else { 1 };
        // As many jobs at once as there are threads: each holds its sectors' cells.
        let batch = rayon::current_num_threads().max(1);
        let mut changed: Vec<(u32, u16, f64)> = Vec::new();
        let mut buffer = vec![0u16; cells * per_job * batch.min(jobs)];
        for first in (0..jobs).step_by(batch) {
            let n = batch.min(jobs - first);
            let mut outs: Vec<&mut [u16]> = buffer[..cells * per_job * n].chunks_mut(cells.max(1)).collect();
            let mut pairs: Vec<SectorJob<'_>> = Vec::with_capacity(n);
            let mut sector_of = Vec::with_capacity(n * per_job);
            for k in 0..n {
                let s = first + k;
                if paired {
                    let b = outs.pop().unwrap_or_default();
                    let a = outs.pop().unwrap_or_default();
                    pairs.push((s, a, Some(b)));
                } else {
                    let a = outs.pop().unwrap_or_default();
                    pairs.push((s, a, None));
                }
            }
            // Popped from the back: job k's outputs are the chunks counted from the end.
            pairs.reverse();
            for &(s, _, ref b) in &pairs {
                sector_of.push(s);
                if b.is_some() {
                    sector_of.push(s + jobs);
                }
            }
            trace_sectors(dem, &zn, sectors, curvature, (0, 0), pairs);
            for (chunk, &s) in buffer[..cells * per_job * n].chunks(cells.max(1)).zip(&sector_of) {
                // At the map's own precision: a narrowed map's truth differs where the
                // one-byte codes do.
                for (i, &code) in chunk.iter().enumerate() {
                    if let Some(deg) = self.differs(s, i, code) {
                        changed.push((i as u32, s as u16, deg));
                    }
                }
            }
        }
        Ok(self.profiles_of(changed))
    }

    /// Number of sectors.
    pub fn sectors(&self) -> usize {
        self.sectors
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        match &self.angles {
            Codes::Wide(a) => a.len() * 2,
            Codes::Narrow(a) => a.len(),
        }
    }

    /// Horizon elevation (degrees) of cell `i` at `azimuth_deg`, interpolated between
    /// sector centres.
    pub fn horizon_deg(&self, i: usize, azimuth_deg: f64) -> f64 {
        let cells = self.cols * self.rows;
        // Planners pass azimuths already in [0, 360): skip the fmod then.
        let az = if (0.0..360.0).contains(&azimuth_deg) { azimuth_deg } else { azimuth_deg.rem_euclid(360.0) };
        let pos = az / 360.0 * self.sectors as f64;
        // pos ≥ 0: truncation is the floor.
        let s0 = (pos as usize) % self.sectors;
        let s1 = (s0 + 1) % self.sectors;
        let t = pos - (pos as usize) as f64;
        let a = self.angles.deg(s0 * cells + i);
        let b = self.angles.deg(s1 * cells + i);
        a + (b - a) * t
    }

    /// Cell `i`'s horizon elevation in every sector, degrees (sector `k` centred on
    /// azimuth k·360°/K): what a rover senses of its own horizon.
    pub fn cell_profile(&self, i: usize) -> Vec<f32> {
        let cells = self.cols * self.rows;
        (0..self.sectors).map(|s| self.angles.deg(s * cells + i) as f32).collect()
    }

    /// The horizon elevation (degrees) of a per-sector profile (from
    /// [`HorizonMap::cell_profile`]) at `azimuth_deg`, interpolated as
    /// [`HorizonMap::horizon_deg`] does.
    pub fn profile_deg(profile: &[f32], azimuth_deg: f64) -> f64 {
        let n = profile.len();
        let pos = azimuth_deg.rem_euclid(360.0) / 360.0 * n as f64;
        let s0 = (pos as usize) % n;
        let s1 = (s0 + 1) % n;
        let t = pos - (pos as usize) as f64;
        let (a, b) = (f64::from(profile[s0]), f64::from(profile[s1]));
        a + (b - a) * t
    }

    /// Cast shadow for a source at (`azimuth_deg`, `elevation_deg`): true where the
    /// horizon is above the source.
    pub fn shadowed(&self, azimuth_deg: f64, elevation_deg: f64) -> Vec<bool> {
        (0..self.cols * self.rows).map(|i| elevation_deg < self.horizon_deg(i, azimuth_deg)).collect()
    }
}

/// The cells whose horizon on one terrain differs from a [`HorizonMap`] of another on
/// the same grid ([`HorizonMap::changes`]), with their whole profiles.
#[derive(Debug, Clone, Default)]
pub struct HorizonChanges {
    sectors: usize,
    profiles: std::collections::HashMap<u32, Box<[f32]>>,
}

impl HorizonChanges {
    /// Cell `i`'s profile (degrees per sector, as [`HorizonMap::cell_profile`]) where it
    /// differs from the reference map.
    pub fn profile(&self, i: usize) -> Option<&[f32]> {
        self.profiles.get(&(i as u32)).map(|p| &p[..])
    }

    /// How many cells differ.
    pub fn len(&self) -> usize {
        self.profiles.len()
    }

    /// Whether no cell differs.
    pub fn is_empty(&self) -> bool {
        self.profiles.is_empty()
    }

    /// Number of sectors.
    pub fn sectors(&self) -> usize {
        self.sectors
    }

    /// Bytes held (approximate).
    pub fn bytes(&self) -> usize {
        self.profiles.capacity() * (std::mem::size_of::<(u32, Box<[f32]>)>() + 1)
            + self.profiles.len() * self.sectors * 4
    }
}

/// Traces every (sector, output, opposite output) job in parallel (the result does not
/// depend on the thread count): each sector's horizons encoded into its output.
fn trace_sectors(
    dem: &Dem,
    zn: &Elevations,
    sectors: usize,
    curvature: Curvature,
    origin: (usize, usize),
    pairs: Vec<SectorJob<'_>>,
) {
    let (cols, rows) = (dem.cols(), dem.rows());
    let cells = cols * rows;
    // Encoded in the accumulator's own order (a loop the compiler vectorises), then
    // tiles transposed into place for column-major accumulators.
    let write = |acc: &Accumulator, scratch: &mut Vec<u16>, out: &mut [u16]| {
        if acc.transposed {
            scratch.resize(cells, 0);
            encode_all(&acc.cells, &zn.cols_first, scratch);
            for_each_tiled(cols, rows, |r, c| out[r * cols + c] = scratch[c * rows + r]);
        } else {
            encode_all(&acc.cells, &zn.rows_first, out);
        }
    };
    // Per-thread accumulators reused across sectors.
    pairs.into_par_iter().for_each_init(
        || (Accumulator::default(), Accumulator::default(), Vec::new()),
        |(toward, away, scratch), (s, out, opposite)| {
            let az = s as f64 * 360.0 / sectors as f64;
            match opposite {
                Some(opposite) => {
                    trace_lines(dem, zn, az, curvature, origin, Some(&mut *toward), Some(&mut *away), None);
                    write(toward, scratch, out);
                    write(away, scratch, opposite);
                }
                None => {
                    trace_lines(dem, zn, az, curvature, origin, Some(&mut *toward), None, None);
                    write(toward, scratch, out);
                }
            }
        },
    );
}

/// Per-cell horizon elevation (degrees) toward `azimuth_deg`; NaN on missing cells,
/// −90 where nothing lies toward that azimuth on the map.
///
/// Parallel lines toward the azimuth, a quarter cell apart, sample the terrain where they
/// cross grid lines (linear interpolation, as the ray-cast reference does). Along each
/// line, walking away from the azimuth, the upper convex hull of the samples seen so
/// far (heights lowered by s²/2R; a shear keeps the hull valid for every observer) gives
/// each observer's horizon by a binary search for the tangent. A cell takes the
/// horizons of the two lines straddling it, weighted by distance (lines a whole cell
/// apart miss narrow peaks between them: 1–2 % of cells disagree with a per-cell ray
/// cast at low Sun, against 0.1–0.2 % at a quarter cell).
pub fn horizon_toward(dem: &Dem, azimuth_deg: f64, curvature: Curvature) -> Vec<f64> {
    let mut acc = Accumulator::default();
    trace_lines(dem, &Elevations::of(dem), azimuth_deg, curvature, (0, 0), Some(&mut acc), None, None);
    let mut out = vec![0.0; dem.cols() * dem.rows()];
    acc.for_each_cell(dem.cols(), dem.rows(), |i, [sum, weight]| out[i] = finish(dem.valid_mask()[i], sum, weight));
    out
}

/// [`encode`]`(`[`finish`]`(..))` of every cell, in the accumulator's order; `zn`
/// (NaN where missing) in the same order. Branch-free, so that it vectorises.
fn encode_all(cells: &[[f32; 2]], zn: &[f32], out: &mut [u16]) {
    let n = out.len();
    let (cells, zn) = (&cells[..n], &zn[..n]);
    for i in 0..n {
        out[i] = encode_one(cells[i], zn[i]);
    }
}

/// One cell's code from its accumulated [sum, weight] and its elevation (NaN: missing).
#[inline(always)]
fn encode_one([sum, weight]: [f32; 2], z: f32) -> u16 {
    let deg = f64::from(crate::slope::fast_atan(sum / weight)).to_degrees();
    let deg = if weight > 0.0 { deg } else { -90.0 };
    encode(if z.is_nan() { f64::NAN } else { deg })
}

/// The horizon angle of one cell from its blended tangent.
fn finish(valid: bool, sum: f32, weight: f32) -> f64 {
    if !valid {
        f64::NAN
    } else if weight > 0.0 {
        f64::from(crate::slope::fast_atan(sum / weight)).to_degrees()
    } else {
        -90.0
    }
}

/// Parallel ray lines per cell width, and their spacing in cells.
const LINES_PER_CELL: i64 = 4;
const SPACING: f64 = 1.0 / LINES_PER_CELL as f64;

/// Elevations with missing cells as NaN (one test per sample instead of a mask lookup
/// per corner, and NaN carries through the interpolation), row-major and transposed:
/// lines that run down the rows walk the transposed copy, a page per sample otherwise.
struct Elevations {
    rows_first: Vec<f32>,
    cols_first: Vec<f32>,
}

/// Cells per side of the tiles that transposes copy: a tile's rows and columns all
/// stay in the TLB.
const TILE: usize = 64;

impl Elevations {
    fn of(dem: &Dem) -> Elevations {
        let rows_first: Vec<f32> =
            dem.elevations().iter().zip(dem.valid_mask()).map(|(&z, &v)| if v { z } else { f32::NAN }).collect();
        let (cols, rows) = (dem.cols(), dem.rows());
        let mut cols_first = vec![0f32; rows_first.len()];
        for_each_tiled(cols, rows, |r, c| cols_first[c * rows + r] = rows_first[r * cols + c]);
        Elevations { rows_first, cols_first }
    }
}

/// Calls `f(row, col)` for every cell of a cols × rows grid, tile by tile.
fn for_each_tiled(cols: usize, rows: usize, mut f: impl FnMut(usize, usize)) {
    for c0 in (0..cols).step_by(TILE) {
        for r0 in (0..rows).step_by(TILE) {
            for c in c0..(c0 + TILE).min(cols) {
                for r in r0..(r0 + TILE).min(rows) {
                    f(r, c);
                }
            }
        }
    }
}

/// Per-cell accumulators of one azimuth: the weighted sum of horizon tangents from the
/// lines straddling each cell, and the weights. Reused across sectors (large DEMs: no
/// fresh pages each time).
#[derive(Default)]
struct Accumulator {
    /// Column-major (cell (r, c) at c·rows + r), for lines that run down the rows.
    transposed: bool,
    /// Per cell, [sum, weight] side by side: an observer's update touches one cache
    /// line, not two (rows-dominant lines visit a new line per observer).
    cells: Vec<[f32; 2]>,
}

impl Accumulator {
    fn reset(&mut self, cells: usize, transposed: bool) {
        self.cells.clear();
        self.cells.resize(cells, [0.0; 2]);
        self.transposed = transposed;
    }

    /// Calls `f(i, [sum, weight])` for every cell, `i` its row-major index.
    fn for_each_cell(&self, cols: usize, rows: usize, mut f: impl FnMut(usize, [f32; 2])) {
        if self.transposed {
            for_each_tiled(cols, rows, |r, c| f(r * cols + c, self.cells[c * rows + r]));
        } else {
            for (i, &v) in self.cells.iter().enumerate() {
                f(i, v);
            }
        }
    }
}

/// One ray line's samples, in walking order: the sheared terrain height where the
/// line crosses each grid line (NaN: off the map or missing), and the observer cell
/// near each crossing with its sheared height and blending weight.
#[derive(Default)]
struct Line {
    x: Vec<f64>,
    h: Vec<f64>,
    cell: Vec<usize>,
    observer: Vec<f64>,
    w: Vec<f32>,
}

/// Traces the lines parallel to `azimuth_deg` once, accumulating the horizon toward
/// `azimuth_deg` into `toward` and toward the opposite azimuth into `away` (either may
/// be absent): both directions see the same samples, so they are computed once. The
/// family of lines depends only on the axis, not on which end is `azimuth_deg`, so a
/// sector's horizon is the same whether it is computed alone or with its opposite.
/// `zn` is [`Elevations::of`] the DEM; `origin`, the (column, row) of the DEM's first
/// cell in the map whose line family to follow.
#[allow(clippy::too_many_arguments)] // the family, its two directions and a part of it
fn trace_lines<'a>(
    dem: &Dem,
    zn: &Elevations,
    azimuth_deg: f64,
    curvature: Curvature,
    origin: (usize, usize),
    mut toward: Option<&'a mut Accumulator>,
    mut away: Option<&'a mut Accumulator>,
    mut part: Option<&mut changed::Part<'_>>,
) {
    let (cols, rows) = (dem.cols(), dem.rows());
    // n: cells along the dominant axis; t_len: cells across; shift: transverse index
    // change per step toward the azimuth.
    let LineGeometry { along_cols, n_lines: n, n_cells: t_len, step_m, shift, toward_higher_line: toward_higher } =
        LineGeometry::toward(dem, azimuth_deg);
    // Canonical walk: from dominant index 0 upward, away from the azimuth at that end.
    // If `azimuth_deg` lies toward the higher indices, it is the "away" direction of
    // the opposite azimuth (whose shift is negated).
    let shift = if toward_higher { -shift } else { shift };
    if toward_higher {
        std::mem::swap(&mut toward, &mut away);
    }
    let shift = if (shift - shift.round()).abs() < 1e-9 { shift.round() } else { shift };
    // Cell at (dominant j, transverse t) → flat index j·dj + t·dt, in the copy of the
    // elevations (and the accumulators' layout) where j runs along memory.
    let (zn, dj, dt) = if along_cols { (&zn.rows_first, 1, cols) } else { (&zn.cols_first, 1, rows) };
    let inv_r = 2.0 * curvature.inv_2r();
    let t_last = t_len as i64 - 1;
    for acc in [&mut toward, &mut away].into_iter().flatten() {
        acc.reset(cols * rows, !along_cols);
    }
    let span = shift * (n - 1) as f64;
    let first = (span.min(0.0)).floor() as i64 - 1;
    let last = ((t_len - 1) as f64 + span.max(0.0)).ceil() as i64 + 1;
    // The map's lines sit at t0 = q·SPACING at its dominant index 0; a window starting at
    // dominant J, transverse T follows them at t0 ≡ −T − shift·J (mod SPACING).
    let (big_j, big_t) = if along_cols { (origin.0, origin.1) } else { (origin.1, origin.0) };
    let phase = (-(big_t as f64) - shift * big_j as f64).rem_euclid(SPACING);
    let phase = if phase < 1e-9 || SPACING - phase < 1e-9 { 0.0 } else { phase };
    let (q_lo, q_hi) = if phase == 0.0 { (0, 0) } else { (1, 0) };
    let mut hull = Hull::with_capacity(n);
    let mut line = Line::default();
    let windows = part.as_deref().map(|p| p.windows(along_cols, (cols, rows), shift));
    for q in (first * LINES_PER_CELL - q_lo)..=(last * LINES_PER_CELL + q_hi) {
        let t0 = q as f64 * SPACING + phase;
        if windows.as_ref().is_some_and(|w| !w.traces(t0)) {
            continue;
        }
        // Only the steps where this line is on the map: −1 ≤ t0 − shift·j ≤ t_len.
        let (j_lo, j_hi) = if shift == 0.0 {
            if t0 < -1.0 || t0 > t_len as f64 { (1, 0) } else { (0, n - 1) }
        } else {
            let a = (t0 + 1.0) / shift;
            let b = (t0 - t_len as f64) / shift;
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            (lo.ceil().max(0.0) as usize, hi.floor().min((n - 1) as f64).max(-1.0) as isize as usize)
        };
        if j_hi < j_lo || j_hi == usize::MAX {
            continue;
        }
        line.sample(zn, t0, shift, j_lo..=j_hi, (dj, dt), t_last, step_m, inv_r);
        if line.x.is_empty() {
            continue;
        }
        if let Some(acc) = toward.as_deref_mut() {
            line.walk(&mut hull, acc, false, inv_r);
        }
        if let Some(acc) = away.as_deref_mut() {
            line.walk(&mut hull, acc, true, inv_r);
        }
        if let (Some(p), Some(w)) = (part.as_deref_mut(), &windows)
            && w.touches(t0)
        {
            p.reach(&line.cell);
        }
    }
}

impl Line {
    /// Samples the line t = t0 − shift·j over `js`.
    #[allow(clippy::too_many_arguments)] // the line's geometry, spelled out
    fn sample(
        &mut self,
        zn: &[f32],
        t0: f64,
        shift: f64,
        js: std::ops::RangeInclusive<usize>,
        (dj, dt): (usize, usize),
        t_last: i64,
        step_m: f64,
        inv_r: f64,
    ) {
        self.x.clear();
        self.h.clear();
        self.cell.clear();
        self.observer.clear();
        self.w.clear();
        for j in js {
            let t = t0 - shift * j as f64;
            if !(-1.0..=(t_last + 1) as f64).contains(&t) {
                continue;
            }
            let row = j * dj;
            let x = j as f64 * step_m;
            let drop = x * x * inv_r / 2.0;
            // The terrain where the line crosses this grid line, interpolated between
            // the two cells straddling it.
            let h = if t < -1e-9 || t > t_last as f64 + 1e-9 {
                f64::NAN
            } else {
                // t ≥ 0 here (up to 1e-9): truncation is the floor, without a libm call.
                let ti = (t.max(0.0) as i64).min(t_last);
                let w = (t - ti as f64).max(0.0);
                let z0 = f64::from(zn[row + ti as usize * dt]);
                if w < 1e-9 { z0 } else { z0 * (1.0 - w) + f64::from(zn[row + (ti + 1).min(t_last) as usize * dt]) * w }
            };
            // Observer: the cell within one line spacing of the crossing (with lines a
            // quarter cell apart, at most the nearest one). t ≥ −1, so the shifted
            // truncation is a rounding.
            let tc = (t + 1.5) as i64 - 1;
            let w = 1.0 - (t - tc as f64).abs() / SPACING;
            let (cell, observer) = if w > 1e-12 && tc >= 0 && tc <= t_last {
                let i = row + tc as usize * dt;
                (i, f64::from(zn[i]) - drop)
            } else {
                (usize::MAX, f64::NAN)
            };
            self.x.push(x);
            self.h.push(h - drop);
            self.cell.push(cell);
            self.observer.push(observer);
            self.w.push(w as f32);
        }
    }

    /// Walks the line (backward: from its far end, abscissae negated), keeping the upper
    /// convex hull of the samples passed; each observer's horizon is its tangent to the
    /// hull. The shear by x²/2R is the same either way; the slope correction is −x/R.
    fn walk(&self, hull: &mut Hull, acc: &mut Accumulator, backward: bool, inv_r: f64) {
        hull.clear();
        let n = self.x.len();
        for k in 0..n {
            let k = if backward { n - 1 - k } else { k };
            let x = if backward { -self.x[k] } else { self.x[k] };
            let p = (x, self.h[k]);
            let has_p = !p.1.is_nan();
            // Where pushing p will cut the hull: its tangent vertex, found from the end
            // (amortised O(1): every vertex passed over is popped below).
            let keep = if has_p { hull_keep(hull, p) } else { 0 };
            let oy = self.observer[k];
            if !oy.is_nan() {
                // A line that has seen nothing yet says nothing about the horizon.
                let slope =
                    if keep > 0 { Some(tangent_from(hull, x, oy, keep - 1, p.1)) } else { tangent(hull, x, oy) };
                if let Some(slope) = slope {
                    // Blend tangents; one arctangent per cell at the end.
                    let (i, w) = (self.cell[k], self.w[k]);
                    let c = &mut acc.cells[i];
                    c[0] += w * (slope - x * inv_r) as f32;
                    c[1] += w;
                }
            }
            if has_p {
                hull.truncate(keep);
                hull.push(p);
            }
        }
    }
}

/// An upper convex hull, left to right, its abscissae and heights apart: stored as
/// (x, y) pairs, the compiler pairs up each cross product's halves in vector registers
/// at opt-level 3, which lengthens the pop loop's chain (the whole horizon map took
/// 14 % longer than at opt-level 2).
#[derive(Default)]
struct Hull {
    x: Vec<f64>,
    y: Vec<f64>,
}

impl Hull {
    fn with_capacity(n: usize) -> Hull {
        Hull { x: Vec::with_capacity(n), y: Vec::with_capacity(n) }
    }
    fn len(&self) -> usize {
        self.x.len()
    }
    fn clear(&mut self) {
        self.x.clear();
        self.y.clear();
    }
    fn truncate(&mut self, n: usize) {
        self.x.truncate(n);
        self.y.truncate(n);
    }
    fn push(&mut self, (x, y): (f64, f64)) {
        self.x.push(x);
        self.y.push(y);
    }
    #[inline]
    fn at(&self, k: usize) -> (f64, f64) {
        (self.x[k], self.y[k])
    }
}

/// How many vertices of an upper convex hull stay when `p` is added at its right end:
/// the last one kept is the hull's tangent vertex seen from `p`.
fn hull_keep(hull: &Hull, p: (f64, f64)) -> usize {
    let mut keep = hull.len();
    while keep >= 2 {
        let (a, b) = (hull.at(keep - 2), hull.at(keep - 1));
        // b is kept only if it lies strictly above the segment a–p.
        let cross = (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0);
        if cross >= 0.0 {
            keep -= 1;
        } else {
            break;
        }
    }
    keep
}

/// [`tangent`] for an observer at the abscissa of a point `(ox, py)` whose tangent
/// vertex `kp` is known: the tangent vertex moves back along the hull as the
/// observer rises, so it is searched from `kp` — rightward over vertices that `py`'s
/// push removes anyway, leftward a few steps before falling back to bisection.
fn tangent_from(hull: &Hull, ox: f64, oy: f64, kp: usize, py: f64) -> f64 {
    let not_worse = |b: (f64, f64), a: (f64, f64)| (b.1 - oy) * (ox - a.0) >= (a.1 - oy) * (ox - b.0);
    let slope = |p: (f64, f64)| (p.1 - oy) / (ox - p.0);
    let mut k = kp;
    if oy <= py {
        while k + 1 < hull.len() && not_worse(hull.at(k + 1), hull.at(k)) {
            k += 1;
        }
        return slope(hull.at(k));
    }
    for _ in 0..8 {
        if k == 0 || not_worse(hull.at(k), hull.at(k - 1)) {
            return slope(hull.at(k));
        }
        k -= 1;
    }
    // Far back: bisect the prefix, where the answer now lies.
    let (mut lo, mut hi) = (0usize, k);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if not_worse(hull.at(mid + 1), hull.at(mid)) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    slope(hull.at(lo))
}

/// The largest slope (y − oy)/(ox − x) from an observer at (ox, oy), right of every
/// hull point, back to the hull; `None` for an empty hull.
fn tangent(hull: &Hull, ox: f64, oy: f64) -> Option<f64> {
    if hull.len() == 0 {
        return None;
    }
    let slope = |p: (f64, f64)| (p.1 - oy) / (ox - p.0);
    // slope(b) ≥ slope(a), without dividing (both run lengths are positive).
    let not_worse = |b: (f64, f64), a: (f64, f64)| (b.1 - oy) * (ox - a.0) >= (a.1 - oy) * (ox - b.0);
    // Along an upper hull the slope seen from the right rises, then falls: find the
    // first vertex not beaten by its right neighbour.
    let (mut lo, mut hi) = (0usize, hull.len() - 1);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if not_worse(hull.at(mid + 1), hull.at(mid)) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    Some(slope(hull.at(lo)))
}

/// Sunlight on every cell for one Sun direction: the Sun's elevation above the cell's
/// own ground plane (90° minus the incidence angle on the Horn normal), degrees —
/// TEMPEST's line-of-sight quantity — or NaN where the Sun is occluded by terrain or
/// below the ground plane, or the cell is missing.
pub fn sun_above_ground_deg(dem: &Dem, horizon: &HorizonMap, azimuth_deg: f64, elevation_deg: f64) -> Vec<f32> {
    let (gx, gy) = horn_gradient(dem);
    let (sa, ca) = azimuth_deg.to_radians().sin_cos();
    let (se, ce) = elevation_deg.to_radians().sin_cos();
    let sun = [ce * sa, ce * ca, se];
    (0..gx.len())
        .map(|i| {
            if !dem.valid_mask()[i] || elevation_deg < horizon.horizon_deg(i, azimuth_deg) {
                return f32::NAN;
            }
            let n = unit_normal(f64::from(gx[i]), f64::from(gy[i]));
            let cos_i = n[0] * sun[0] + n[1] * sun[1] + n[2] * sun[2];
            if cos_i > 0.0 { (90.0 - cos_i.clamp(-1.0, 1.0).acos().to_degrees()) as f32 } else { f32::NAN }
        })
        .collect()
}

/// Line-of-sight maps at regular times: for t = t0, t0 + step, … (< t1), the Sun's
/// direction `sun(t)` → (azimuth, elevation) degrees, and the map of
/// [`sun_above_ground_deg`]. The time unit is the caller's (seconds from a scenario
/// epoch, typically); areo-ephemeris supplies `sun`.
pub fn los_sequence(
    dem: &Dem,
    horizon: &HorizonMap,
    t0: f64,
    t1: f64,
    step: f64,
    sun: impl Fn(f64) -> (f64, f64),
) -> Vec<(f64, Vec<f32>)> {
    let mut out = Vec::new();
    if !(step > 0.0) {
        return out;
    }
    let mut t = t0;
    while t < t1 {
        let (az, el) = sun(t);
        out.push((t, sun_above_ground_deg(dem, horizon, az, el)));
        t += step;
    }
    out
}

mod changed;

#[cfg(test)]
mod tests;
