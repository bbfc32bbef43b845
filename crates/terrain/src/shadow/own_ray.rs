//! [`Method::OwnRay`](super::Method::OwnRay): every cell decided by its own ray from its
//! centre toward the Sun, on the triangulated surface, at about the cost of a trace.
//!
//! A cell is in cast shadow when some point of its own ray lies below the surface.
//! Marching that ray across every triangle edge it meets is exact (terrain minus ray
//! height is piecewise linear along it) but costs the ray's length per cell. Cell
//! centres are vertices, so every cell's ray meets the same sequence of crossings at
//! the same offsets ([`Crossings`]); what lets almost every cell stop after one step,
//! without giving up exactness, is proof either way:
//!
//! - **Lit, by a certified upper bound** ([`Bands`]): rays laid one per cell width and
//!   sheared so that each meets the next line exactly at another cut the map into
//!   bands that run on as bands, never widening. One trace bounds the shadow height over
//!   each band from the terrain where its two edge rays cross triangle edges and the
//!   vertices inside it. Once a cell's ray clears the bound of the band it runs in,
//!   nothing further along can reach it.
//! - **Shadowed, by a witness**: a point of the cell's own ray below the terrain. The
//!   first step is taken for a whole line at once (vectorised); then the crossing that
//!   shadowed the previous cell on the line, and the crossings near the occluders of
//!   the two cells the ray passes between one line toward the Sun, are tried.
//! - Otherwise the ray is marched, crossing by crossing, skipping the stretches where
//!   it passes over blocks of terrain lower than itself ([`Blocks`], 8 × 8 and
//!   64 × 64 cells), until one of the two holds or it leaves the map.
//!
//! Every decision is made on the cell's own ray: the result is the brute force's
//! (`reference::horizon_on_triangles`) up to the rounding of the last bit,
//! and the tests compare them cell for cell, on the Gale MOLA map and on synthesised
//! terrain, at every azimuth tried. Curvature lowers a distant occluder by d²/2R; the
//! bounds are computed for a flat world, which only loosens them (still upper bounds),
//! while the rays apply it exactly.

use crate::dem::Dem;
use crate::ray_lines::LineGeometry;
use crate::shadow::Curvature;

/// Crossings closer than this (in cells) to a vertex are that vertex, as in the
/// reference.
const EPS: f64 = 1e-9;
/// Missing (−∞) lines before line 0 and positions either side of each line: every vertex a
/// crossing inside the map reaches lands in the grid or in this margin.
const PAD_LINES: usize = 1;
const PAD_POS: usize = 5;

/// Cast shadow (true = shadowed) decided by each cell's own ray; see the module docs.
pub(crate) fn cast(dem: &Dem, azimuth_deg: f64, elevation_deg: f64, curvature: Curvature) -> Vec<bool> {
    debug_assert!(elevation_deg > 0.0, "the door (`cast_shadows`) answers a Sun at or below the horizon");
    let view = SunView::new(dem, azimuth_deg);
    let tan_e = elevation_deg.to_radians().tan();
    let crossings = Crossings::new(&view, tan_e, curvature.inv_2r());
    let mut bands = Bands::new(&view, tan_e);
    let fine = Blocks::new(&view, 8);
    let blocks = [fine.coarser(8), fine];
    let n_pos = view.n_pos;
    let mut shadow_lines = vec![false; view.n_lines * n_pos];
    let mut first = vec![f64::NEG_INFINITY; n_pos];
    let step1 = &crossings.list[..crossings.ends[1]];
    // Per cell of the previous line (one step toward the Sun) and of this one: the line
    // step at which its ray met the terrain (0: lit). A neighbour's occluder is the
    // first place to look for a cell's own.
    let (mut met_sun, mut met_here) = (vec![0u32; n_pos], vec![0u32; n_pos]);
    let last_step = crossings.ends.len() - 1;
    let mut open = vec![false; n_pos];
    for line in 0..view.n_lines {
        bands.push_line(&view);
        first_step(&view, step1, line, &mut first);
        let out = &mut shadow_lines[line * n_pos..(line + 1) * n_pos];
        let heights = &view.z[view.slot(line, 0)..][..n_pos];
        // Whole-line passes first: shadowed within the first step, and — among the
        // rest — lit by the bound of the band each ray runs in one line on. `open`
        // marks the cells neither settles.
        for (((o, met), z0), h1) in out.iter_mut().zip(met_here.iter_mut()).zip(heights).zip(&first) {
            *o = *h1 > f64::from(*z0);
            *met = u32::from(*o);
        }
        let rise = crossings.rise[1];
        if line == 0 {
            // Nothing lies beyond the sun-most line.
            open.fill(false);
        } else {
            let (bounds, from) = bands.line_after_one_step(line);
            for (p, ((u, o), z0)) in open.iter_mut().zip(out.iter()).zip(heights).enumerate() {
                let z0 = f64::from(*z0);
                // Off the band lattice's slots nothing bounds the ray: it is lit.
                let bound = bounds.get(p.wrapping_add_signed(from)).copied().unwrap_or(f64::NEG_INFINITY);
                *u = !*o && z0 != f64::NEG_INFINITY && z0 + rise < bound;
            }
        }
        // The last shadow witness on this line: the next cell tries it first.
        let mut witness: Option<usize> = None;
        for pos in 0..n_pos {
            if !open[pos] {
                continue;
            }
            let z0 = f64::from(heights[pos]);
            let ray = Ray::new(&view, line, pos, z0);
            let hit = |e: &usize| ray.reaches(&crossings.list[*e]) && ray.above(&view, &crossings.list[*e]);
            // Witnesses: the last cell marched into shadow on this line, then the
            // occluders of the two cells either side of the ray one line toward the
            // Sun, a step further on.
            let q = pos as isize + crossings.whole[1];
            let sunward = [q, q + 1].into_iter().filter(|q| *q >= 0 && (*q as usize) < n_pos).flat_map(|q| {
                let m = met_sun[q as usize] as usize;
                if m == 0 { 0..0 } else { crossings.ends[m - 1]..crossings.ends[(m + 2).min(last_step)] }
            });
            let found =
                witness.into_iter().chain(sunward).find(hit).or_else(|| ray.march(&view, &crossings, &bands, &blocks));
            if let Some(e) = found {
                witness = Some(e);
                met_here[pos] = crossings.list[e].step;
                out[pos] = true;
            }
        }
        std::mem::swap(&mut met_sun, &mut met_here);
    }
    view.to_grid(&shadow_lines)
}

/// The first line step of every cell's ray on `line` at once: the highest crossing
/// above the ray's rise (−∞ if none; missing terrain never counts). Cell centres are
/// vertices, so every cell meets the same crossings at the same offsets, and the loop
/// runs down contiguous slices.
fn first_step(view: &SunView, step1: &[Crossing], line: usize, out: &mut [f64]) {
    let n = out.len();
    out.fill(f64::NEG_INFINITY);
    let base = view.slot(line, 0) as isize;
    for x in step1 {
        let a = &view.z[(base + x.a) as usize..][..n];
        let b = &view.z[(base + x.b) as usize..][..n];
        let (u, drop) = (x.u, x.drop);
        if u < EPS {
            for (o, a) in out.iter_mut().zip(a) {
                let v = f64::from(*a) - drop;
                *o = if v > *o { v } else { *o };
            }
        } else if u > 1.0 - EPS {
            for (o, b) in out.iter_mut().zip(b) {
                let v = f64::from(*b) - drop;
                *o = if v > *o { v } else { *o };
            }
        } else {
            for ((o, a), b) in out.iter_mut().zip(a).zip(b) {
                let (a, b) = (f64::from(*a), f64::from(*b));
                // −∞ (missing) at either end gives NaN or −∞: never above.
                let v = a + (b - a) * u - drop;
                *o = if v > *o { v } else { *o };
            }
        }
    }
}

/// The DEM seen from the Sun: line 0 the row or column nearest it, positions along each
/// line, heights f32 with −∞ where missing, in a padded line-major copy so that a ray's
/// crossings read neighbouring memory.
struct SunView {
    z: Vec<f32>,
    width: usize,
    n_lines: usize,
    n_pos: usize,
    layout: Layout,
    /// Positions moved per line stepped toward the Sun (|shift| ≤ 1).
    shift: f64,
    /// Metres along the ray per line stepped.
    step_m: f64,
    /// +1 if the surface's diagonals join (line, pos) to (line + 1, pos + 1), −1 if to
    /// (line + 1, pos − 1).
    diagonal: isize,
}

impl SunView {
    fn new(dem: &Dem, azimuth_deg: f64) -> SunView {
        let g = LineGeometry::toward(dem, azimuth_deg);
        // Directions a hair off an axis or a diagonal would otherwise straddle two cells
        // with a weight of 1e-16.
        let shift = if (g.shift - g.shift.round()).abs() < 1e-9 { g.shift.round() } else { g.shift };
        let width = g.n_cells + 2 * PAD_POS;
        let layout = Layout {
            n_lines: g.n_lines,
            n_pos: g.n_cells,
            cols: dem.cols(),
            along_cols: g.along_cols,
            reversed: g.toward_higher_line,
        };
        let mut z = vec![f32::NEG_INFINITY; (g.n_lines + PAD_LINES) * width];
        let (elev, valid) = (dem.elevations(), dem.valid_mask());
        let value = |cell: usize| if valid[cell] { elev[cell] } else { f32::NEG_INFINITY };
        layout.gather(&mut z[PAD_LINES * width..], width, PAD_POS, value);
        SunView {
            z,
            width,
            n_lines: g.n_lines,
            n_pos: g.n_cells,
            layout,
            shift,
            step_m: g.step_m,
            // The surface's diagonals join each quad's south-west and north-east
            // corners (column + row constant); seen from the Sun that is one of two
            // ways, depending on which way the lines run.
            diagonal: if g.toward_higher_line { 1 } else { -1 },
        }
    }

    #[inline]
    fn slot(&self, line: usize, pos: usize) -> usize {
        view_slot(self.width, line, pos)
    }

    /// Line-major results back into the DEM's row-major order.
    fn to_grid(&self, lines: &[bool]) -> Vec<bool> {
        let mut out = vec![false; lines.len()];
        self.layout.scatter(lines, &mut out);
        out
    }
}

/// Which DEM cell each (line, pos) is.
#[derive(Debug, Clone, Copy)]
struct Layout {
    n_lines: usize,
    n_pos: usize,
    cols: usize,
    /// Lines are the DEM's columns (else its rows).
    along_cols: bool,
    /// Line 0 is the DEM's last column or row.
    reversed: bool,
}

impl Layout {
    /// The DEM's column or row of a line (and back: the map is its own inverse).
    #[inline]
    fn line_of(&self, l: usize) -> usize {
        if self.reversed { self.n_lines - 1 - l } else { l }
    }

    /// Fills `dst` line by line, (line, pos) at `line·stride + offset + pos`, with
    /// `value(DEM cell)`. Columns are copied 64 at a time, so that each row of the
    /// DEM is read in runs rather than a page per cell.
    fn gather<T>(&self, dst: &mut [T], stride: usize, offset: usize, value: impl Fn(usize) -> T) {
        if !self.along_cols {
            for line in 0..self.n_lines {
                let r = self.line_of(line);
                for (pos, d) in dst[line * stride + offset..][..self.n_pos].iter_mut().enumerate() {
                    *d = value(r * self.cols + pos);
                }
            }
            return;
        }
        // Blocks of 64 columns × 8 rows: each column's 8 values land side by side.
        const B: usize = 64;
        const R: usize = 8;
        for c0 in (0..self.n_lines).step_by(B) {
            let c1 = (c0 + B).min(self.n_lines);
            for r0 in (0..self.n_pos).step_by(R) {
                let r1 = (r0 + R).min(self.n_pos);
                for c in c0..c1 {
                    let line = &mut dst[self.line_of(c) * stride + offset..][r0..r1];
                    for (k, d) in line.iter_mut().enumerate() {
                        *d = value((r0 + k) * self.cols + c);
                    }
                }
            }
        }
    }

    /// The inverse of [`Layout::gather`] for line-major `src` (stride n_pos).
    fn scatter<T: Copy>(&self, src: &[T], out: &mut [T]) {
        let n_pos = self.n_pos;
        if !self.along_cols {
            for line in 0..self.n_lines {
                let r = self.line_of(line);
                out[r * self.cols..][..n_pos].copy_from_slice(&src[line * n_pos..][..n_pos]);
            }
            return;
        }
        const B: usize = 64;
        for c0 in (0..self.n_lines).step_by(B) {
            let c1 = (c0 + B).min(self.n_lines);
            for r in 0..n_pos {
                let row = &mut out[r * self.cols..][..self.cols];
                for c in c0..c1 {
                    row[c] = src[self.line_of(c) * n_pos + r];
                }
            }
        }
    }
}

#[inline]
fn view_slot(width: usize, line: usize, pos: usize) -> usize {
    (line + PAD_LINES) * width + pos + PAD_POS
}

/// Where a ray from a cell centre crosses an edge of the triangulated surface, relative
/// to the cell: the same for every cell, since cell centres are vertices.
#[derive(Debug, Clone, Copy)]
struct Crossing {
    /// Lines travelled toward the Sun (> 0).
    tau: f64,
    /// The edge's ends, as offsets into [`SunView::z`] from the cell's slot.
    a: isize,
    b: isize,
    /// Fraction of the way from `a` to `b`.
    u: f64,
    /// The line step it falls in: 1 for tau in (0, 1], and so on.
    step: u32,
    /// How far the ray has risen above the cell's height by then, m: distance·tan e,
    /// plus d²/2R for the surface curving away below it.
    drop: f64,
}

/// Every edge crossing of a ray, in order along it, and where each line step's
/// crossings end.
struct Crossings {
    list: Vec<Crossing>,
    /// `list[..ends[m]]` are the crossings up to and including line m (ends[0] = 0).
    ends: Vec<usize>,
    /// Per line step m: how far the ray has risen (m·step·tan e, flat).
    rise: Vec<f64>,
    /// Per line step m: m·shift split into whole and fractional parts (hot loops avoid
    /// floor, which is a libm call on baseline x86-64).
    whole: Vec<isize>,
    frac: Vec<f64>,
}

impl Crossings {
    fn new(view: &SunView, tan_e: f64, inv_2r: f64) -> Crossings {
        let (shift, w) = (view.shift, view.width as isize);
        let n = view.n_lines;
        let mut list = Vec::new();
        let mut push = |tau: f64, a: (isize, isize), b: (isize, isize), u: f64| {
            let s = tau * view.step_m;
            // Offsets: toward the Sun is toward lower lines.
            list.push(Crossing {
                tau,
                step: (tau - EPS).ceil().max(1.0) as u32,
                a: -a.0 * w + a.1,
                b: -b.0 * w + b.1,
                u,
                drop: s * tan_e + s * s * inv_2r,
            });
        };
        // The lines themselves: at line m the ray is m·shift along.
        for m in 1..=n {
            let x = m as f64 * shift;
            let f = x.floor();
            push(m as f64, (m as isize, f as isize), (m as isize, f as isize + 1), x - f);
        }
        // Edges across the lines (position constant): where the ray's position passes
        // a whole number j.
        if shift != 0.0 {
            let sign = shift.signum() as isize;
            for j in 1.. {
                let tau = j as f64 / shift.abs();
                if tau > n as f64 {
                    break;
                }
                let fl = tau.floor();
                let l = fl as isize;
                // On a line, the edge crossing is a vertex the line's own crossing
                // already tests.
                if tau - fl >= EPS {
                    push(tau, (l, j * sign), (l + 1, j * sign), tau - fl);
                }
            }
        }
        // Diagonals: where position − diagonal·line passes a whole number.
        let rate = shift + view.diagonal as f64;
        if rate.abs() > EPS {
            let sign = rate.signum() as isize;
            let d = view.diagonal;
            for j in 1.. {
                let tau = j as f64 / rate.abs();
                if tau > n as f64 {
                    break;
                }
                let fl = tau.floor();
                let l = fl as isize;
                if tau - fl >= EPS {
                    push(tau, (l, j * sign - d * l), (l + 1, j * sign - d * (l + 1)), tau - fl);
                }
            }
        }
        list.sort_by(|a, b| a.tau.total_cmp(&b.tau));
        let mut ends = vec![0; n + 1];
        let mut e = 0;
        for (m, end) in ends.iter_mut().enumerate().skip(1) {
            while e < list.len() && list[e].tau <= m as f64 + EPS {
                e += 1;
            }
            *end = e;
        }
        let rise = (0..=n).map(|m| m as f64 * view.step_m * tan_e).collect();
        let whole: Vec<isize> = (0..=n).map(|m| (m as f64 * shift).floor() as isize).collect();
        let frac = (0..=n).map(|m| m as f64 * shift - whole[m] as f64).collect();
        Crossings { list, ends, rise, whole, frac }
    }
}

/// One cell's ray.
struct Ray {
    slot: usize,
    line: usize,
    pos: usize,
    z0: f64,
    /// Lines the ray travels before it leaves the map (a crossing further is outside).
    exit: f64,
}

impl Ray {
    fn new(view: &SunView, line: usize, pos: usize, z0: f64) -> Ray {
        let mut exit = line as f64 + EPS;
        if view.shift > 0.0 {
            exit = exit.min(((view.n_pos - 1 - pos) as f64 + EPS) / view.shift);
        } else if view.shift < 0.0 {
            exit = exit.min((pos as f64 + EPS) / -view.shift);
        }
        Ray { slot: view.slot(line, pos), line, pos, z0, exit }
    }

    #[inline]
    fn reaches(&self, x: &Crossing) -> bool {
        x.tau < self.exit
    }

    /// The surface at crossing `x` stands above the ray there.
    #[inline]
    fn above(&self, view: &SunView, x: &Crossing) -> bool {
        let za = f64::from(view.z[(self.slot as isize + x.a) as usize]);
        let zb = f64::from(view.z[(self.slot as isize + x.b) as usize]);
        // As the reference: a crossing on a vertex is that vertex (its other end may be
        // missing); between two ends, a missing one (−∞) gives NaN or −∞, never above.
        let h = if x.u < EPS {
            za
        } else if x.u > 1.0 - EPS {
            zb
        } else {
            za + (zb - za) * x.u
        };
        h - x.drop > self.z0
    }

    /// Marches the ray line step by line step: the crossing that stands above it
    /// (shadowed), or None once the band bound shows nothing further can, or the
    /// ray has left the map.
    fn march(&self, view: &SunView, crossings: &Crossings, bands: &Bands, blocks: &[Blocks; 2]) -> Option<usize> {
        // The first step has been taken for the whole line (`first_step`).
        let mut m = 1;
        let last = crossings.ends.len() - 1;
        while m < last {
            if m as f64 > self.exit {
                return None;
            }
            let h = self.z0 + crossings.rise[m];
            if h >= bands.bound(self.line, self.pos, m) {
                return None;
            }
            // Skip every whole line step inside a block no higher than the ray.
            if let Some(to) = blocks.iter().find_map(|b| b.skip(self, m, h, crossings)) {
                m = to.min(last);
                continue;
            }
            for e in crossings.ends[m]..crossings.ends[m + 1] {
                let x = &crossings.list[e];
                if !self.reaches(x) {
                    return None;
                }
                if self.above(view, x) {
                    return Some(e);
                }
            }
            m += 1;
        }
        None
    }
}

/// The highest vertex over blocks of `size` × `size` (lines × positions), with a
/// one-cell halo so that every triangle reaching into a block is counted: a ray whose
/// height clears a block's maximum passes it in the light.
struct Blocks {
    max: Vec<f32>,
    size: usize,
    n_pos_blocks: usize,
    n_line_blocks: usize,
    shift: f64,
    /// 1/|shift| (∞ along an axis).
    inv_shift: f64,
}

impl Blocks {
    fn new(view: &SunView, size: usize) -> Blocks {
        let (n_lines, n_pos) = (view.n_lines, view.n_pos);
        let (nl, np) = (n_lines.div_ceil(size), n_pos.div_ceil(size));
        // Per line, the maximum over each block's positions and halo.
        let mut per_line = vec![f32::NEG_INFINITY; n_lines * np];
        for line in 0..n_lines {
            let z = &view.z[view.slot(line, 0)..][..n_pos];
            for (bp, o) in per_line[line * np..(line + 1) * np].iter_mut().enumerate() {
                let (a, b) = ((bp * size).saturating_sub(1), ((bp + 1) * size + 1).min(n_pos));
                *o = z[a..b].iter().fold(f32::NEG_INFINITY, |m, v| if *v > m { *v } else { m });
            }
        }
        let mut max = vec![f32::NEG_INFINITY; nl * np];
        for bl in 0..nl {
            let (a, b) = ((bl * size).saturating_sub(1), ((bl + 1) * size + 1).min(n_lines));
            for line in a..b {
                for (o, v) in max[bl * np..(bl + 1) * np].iter_mut().zip(&per_line[line * np..(line + 1) * np]) {
                    *o = if *v > *o { *v } else { *o };
                }
            }
        }
        Blocks { max, size, n_pos_blocks: np, n_line_blocks: nl, shift: view.shift, inv_shift: 1.0 / view.shift.abs() }
    }

    /// Coarser blocks from these: each the maximum of `k` × `k` of them (their halos
    /// cover the coarser block's).
    fn coarser(&self, k: usize) -> Blocks {
        let (nl, np) = (self.n_line_blocks.div_ceil(k), self.n_pos_blocks.div_ceil(k));
        let mut max = vec![f32::NEG_INFINITY; nl * np];
        for bl in 0..self.n_line_blocks {
            for bp in 0..self.n_pos_blocks {
                let v = self.max[bl * self.n_pos_blocks + bp];
                let o = &mut max[(bl / k) * np + bp / k];
                *o = if v > *o { v } else { *o };
            }
        }
        Blocks { max, size: self.size * k, n_pos_blocks: np, n_line_blocks: nl, ..*self }
    }

    /// The ray at line step `m` (on its line `line − m`), `h` metres up: if the block it
    /// enters next lies wholly below `h`, the last whole line step before it leaves the
    /// block.
    #[inline]
    fn skip(&self, ray: &Ray, m: usize, h: f64, crossings: &Crossings) -> Option<usize> {
        let line = ray.line - m;
        if line == 0 {
            return None;
        }
        // The ray is at position x = whole + frac on its line.
        let whole = ray.pos as isize + crossings.whole[m];
        let frac = crossings.frac[m];
        let size = self.size as isize;
        // The block holding the ray's next stretch: toward lower lines, and along the
        // positions in the direction it moves (a ray on a block's edge moving down
        // belongs to the block below).
        let bl = (line - 1) / self.size;
        let bp = if self.shift < 0.0 && frac == 0.0 && whole.rem_euclid(size) == 0 {
            whole.div_euclid(size) - 1
        } else {
            whole.div_euclid(size)
        };
        if bp < 0 || bp as usize >= self.n_pos_blocks {
            return None;
        }
        if f64::from(self.max[bl * self.n_pos_blocks + bp as usize]) > h {
            return None;
        }
        let along = (line - bl * self.size) as f64;
        let x = whole as f64 + frac;
        let across = if self.shift > 0.0 {
            ((bp + 1) as f64 * self.size as f64 - x) * self.inv_shift
        } else if self.shift < 0.0 {
            (x - (bp * size) as f64) * self.inv_shift
        } else {
            f64::INFINITY
        };
        // Truncation is floor here: both are positive.
        let to = m + along.min(across) as usize;
        (to > m).then_some(to)
    }
}

/// Upper bounds on shadow height over *bands*. Rays parallel to the Sun's are laid one
/// per position, sheared so that each meets the next line toward the Sun exactly at
/// another: on line ℓ they sit at φ_ℓ + j, φ_ℓ = frac(−ℓ·shift). The band between rays j
/// and j + 1 therefore runs on as one band of the next line, never widening. Its bound
/// — the highest z − tan e·d over the band beyond the line, d measured along the rays
/// from the line (flat world) — is the most of: the band's stretch of the line itself,
/// the terrain where its two edge rays cross triangle edges before the next line, and
/// the next line's bound one step lower. Terrain minus tan e·d is linear on each piece
/// of triangle inside the band, so those points are where it peaks.
struct Bands {
    /// Per line, band j at slot j + 1 for j in −1..=n_pos.
    b: Vec<f64>,
    width: usize,
    /// Per line: the rays sit on whole positions (φ = 0).
    zero_phase: Vec<bool>,
    /// Per line ℓ: the sum over lines 1..=ℓ of how far the band index moves from a line
    /// to the next toward the Sun.
    prefix: Vec<isize>,
    /// Scratch, per ray of a line: terrain under it, highest edge crossing.
    e: Vec<f64>,
    r: Vec<f64>,
    /// tan e per line step, m.
    line_drop: f64,
}

impl Bands {
    fn new(view: &SunView, tan_e: f64) -> Bands {
        let (n_lines, n) = (view.n_lines, view.n_pos);
        Bands {
            b: Vec::with_capacity(n_lines * (n + 2)),
            width: n + 2,
            zero_phase: Vec::with_capacity(n_lines),
            prefix: Vec::with_capacity(n_lines),
            e: vec![f64::NEG_INFINITY; n + 3],
            r: vec![f64::NEG_INFINITY; n + 3],
            line_drop: view.step_m * tan_e,
        }
    }

    /// The ray lattice's phase on `line`: rays at φ + j.
    fn phase(line: usize, shift: f64) -> f64 {
        let phi = (-(line as f64) * shift).rem_euclid(1.0);
        if (1e-9..=1.0 - 1e-9).contains(&phi) { phi } else { 0.0 }
    }

    /// Adds the bounds of the next line's bands (lines go away from the Sun, each after
    /// the one before it). Done line by line inside the cell loop, so that a line's
    /// bounds are still in cache when its cells first read them.
    fn push_line(&mut self, view: &SunView) {
        let line = self.zero_phase.len();
        let (n, shift, width) = (view.n_pos, view.shift, self.width);
        let phi = Bands::phase(line, shift);
        self.zero_phase.push(phi == 0.0);
        let (e, r) = (&mut self.e, &mut self.r);
        let here = &view.z[view.slot(line, 0) - PAD_POS..][..n + 2 * PAD_POS];
        // Rays j = −1..=n + 1: the terrain under them on the line (e), and the highest
        // edge crossing before the next line (r), per ray at slot j + 1, which reads
        // positions j and j + 1: here[j + PAD_POS].
        fn at(v: &[f32], dp: isize, len: usize) -> &[f32] {
            &v[(PAD_POS as isize - 1 + dp) as usize..][..len]
        }
        let (z0, z1) = (at(here, 0, n + 3), at(here, 1, n + 3));
        for ((o, a), c) in e.iter_mut().zip(z0).zip(z1) {
            let (a, c) = (f64::from(*a), f64::from(*c));
            *o = if phi == 0.0 { a } else { a + (c - a) * phi };
        }
        r.fill(f64::NEG_INFINITY);
        if line > 0 {
            let sun = &view.z[view.slot(line - 1, 0) - PAD_POS..][..n + 2 * PAD_POS];
            for x in strip_crossings(phi, shift, view.diagonal, self.line_drop) {
                let (za, zb) = (at(here, x.a, n + 3), at(sun, x.b, n + 3));
                for ((o, a), c) in r.iter_mut().zip(za).zip(zb) {
                    let (a, c) = (f64::from(*a), f64::from(*c));
                    let v = a + (c - a) * x.u - x.drop;
                    *o = if v > *o { v } else { *o };
                }
            }
        }
        let start = self.b.len();
        self.b.resize(start + width, f64::NEG_INFINITY);
        let (done, out) = self.b.split_at_mut(start);
        // Band j (slot j + 1) lies between rays j and j + 1 (slots j + 1, j + 2);
        // inside its stretch of the line, vertex j + 1 when the rays are off the
        // vertices.
        let inner = at(here, 1, n + 3);
        // NaN (an edge with a missing end: no surface there) never wins.
        let top = |v: f64, c: f64| if c > v { c } else { v };
        let parts = out.iter_mut().zip(e.windows(2)).zip(r.windows(2)).zip(inner);
        if phi != 0.0 {
            for (((o, e), r), z) in parts {
                *o = top(top(top(top(f64::NEG_INFINITY, e[0]), e[1]), top(r[0], r[1])), f64::from(*z));
            }
        } else {
            for (((o, e), r), _) in parts {
                *o = top(top(top(f64::NEG_INFINITY, e[0]), e[1]), top(r[0], r[1]));
            }
        }
        if line == 0 {
            self.prefix.push(0);
            return;
        }
        // Ray j here is ray j + shift_j on the next line toward the Sun.
        let shift_j = (phi + shift - Bands::phase(line - 1, shift)).round() as isize;
        self.prefix.push(self.prefix[line - 1] + shift_j);
        let prev = &done[start - width..];
        // Slots whose band continues on the map's stretch of the next line.
        let lo = (-shift_j).max(0) as usize;
        let hi = (width as isize - shift_j).clamp(0, width as isize) as usize;
        if lo < hi {
            let from = &prev[(lo as isize + shift_j) as usize..(hi as isize + shift_j) as usize];
            for (o, p) in out[lo..hi].iter_mut().zip(from) {
                *o = top(*o, p - self.line_drop);
            }
        }
    }

    /// For the cells of `line` (≥ 1): the bounds of the line one step toward the Sun,
    /// and the offset from a cell's position to the band its ray runs in there (a
    /// position p reads `bounds[p + offset]`, if it is there).
    fn line_after_one_step(&self, line: usize) -> (&[f64], isize) {
        let j0 = -isize::from(!self.zero_phase[line]);
        let from = j0 + self.prefix[line] - self.prefix[line - 1] + 1;
        (&self.b[(line - 1) * self.width..][..self.width], from)
    }

    /// The bound of the band holding the own ray of cell (`line`, `pos`) on the line
    /// `m` steps toward the Sun; −∞ off the map.
    #[inline]
    fn bound(&self, line: usize, pos: usize, m: usize) -> f64 {
        // On its own line the cell sits inside band pos − 1 (or on ray pos).
        let j0 = pos as isize - isize::from(!self.zero_phase[line]);
        let j = j0 + self.prefix[line] - self.prefix[line - m];
        let slot = j + 1;
        if slot < 0 || slot as usize >= self.width {
            return f64::NEG_INFINITY;
        }
        self.b[(line - m) * self.width + slot as usize]
    }
}

/// A crossing of a band's edge ray with a triangle edge between its line and the next:
/// ends `a` on the line and `b` on the next, as position offsets from the ray's cell.
struct StripCrossing {
    a: isize,
    b: isize,
    u: f64,
    drop: f64,
}

/// The crossings strictly between two lines of a ray at fractional position `f` past
/// a vertex: edges across the lines (position constant) and diagonals.
fn strip_crossings(f: f64, shift: f64, diagonal: isize, line_drop: f64) -> Vec<StripCrossing> {
    let mut out = Vec::new();
    let mut add = |tau: f64, a: isize, b: isize| {
        if tau > EPS && tau < 1.0 - EPS {
            out.push(StripCrossing { a, b, u: tau, drop: tau * line_drop });
        }
    };
    if shift != 0.0 {
        for q in -1..=2isize {
            add((q as f64 - f) / shift, q, q);
        }
    }
    let rate = shift + diagonal as f64;
    if rate.abs() > EPS {
        for k in -2..=3isize {
            add((k as f64 - f) / rate, k, k - diagonal);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::horizon_on_triangles;

    fn differ(dem: &Dem, az: f64, el: f64, curvature: Curvature) -> usize {
        let own = cast(dem, az, el, curvature);
        let truth = horizon_on_triangles(dem, az, curvature);
        own.iter().zip(&truth).filter(|(s, h)| h.is_finite() && **s != (**h > el)).count()
    }

    #[test]
    fn every_cell_as_its_own_ray_says_at_every_azimuth() {
        let dem = crate::synth::rough_test_terrain(70, 50, 9, 40.0, 4);
        for k in 0..48 {
            let az = k as f64 * 7.5 + 0.3 * (k % 3) as f64;
            for el in [2.0, 8.0, 25.0] {
                assert_eq!(differ(&dem, az, el, Curvature::Flat), 0, "az {az} el {el}");
            }
        }
    }

    #[test]
    fn missing_cells_curvature_and_narrow_maps() {
        // Holes: a missing end never casts a shadow, as in the reference.
        let dem = crate::synth::rough_test_terrain(40, 33, 4, 60.0, 3);
        let valid: Vec<bool> = (0..40 * 33).map(|i| i % 17 != 3 && !(300..340).contains(&i)).collect();
        let dem = dem.with_mask(valid).unwrap();
        for az in [0.0, 45.0, 90.0, 123.0, 200.0, 291.0] {
            assert_eq!(differ(&dem, az, 6.0, Curvature::Flat), 0, "holes, az {az}");
            assert_eq!(differ(&dem, az, 1.0, Curvature::Sphere { radius_m: 20_000.0 }), 0, "curved, az {az}");
        }
        // One row, one column.
        for (c, r) in [(50, 1), (1, 50), (2, 2)] {
            let dem = Dem::from_fn(c, r, 3.0, 2.0, |x, y| (x * 0.3).sin() * 9.0 + y).unwrap();
            for az in [10.0, 90.0, 180.0, 260.0] {
                assert_eq!(differ(&dem, az, 4.0, Curvature::Flat), 0, "{c}x{r} az {az}");
            }
        }
    }

    #[test]
    fn band_bounds_hold_over_every_ray_inside_the_band() {
        // The bound a cell's march reads at each step against brute force along its own
        // ray and along parallel rays elsewhere in its band.
        let dem = crate::synth::rough_test_terrain(30, 24, 2, 50.0, 3);
        for az in [0.0, 30.0, 45.0, 77.0, 135.0, 250.0, 333.0] {
            let view = SunView::new(&dem, az);
            let tan_e = 0.1;
            let mut bands = Bands::new(&view, tan_e);
            for _ in 0..view.n_lines {
                bands.push_line(&view);
            }
            for line in 1..view.n_lines {
                let phi = (-(line as f64) * view.shift).rem_euclid(1.0);
                for pos in 0..view.n_pos {
                    for m in 1..=line {
                        let bound = bands.bound(line, pos, m);
                        // The band: from the ray at or below the cell to the next one up.
                        let below = if bands.zero_phase[line] { 0.0 } else { phi - 1.0 };
                        for k in 0..=10 {
                            let off = below + k as f64 * 0.1;
                            let worst = brute_ray(&view, line, pos as f64 + off, m, tan_e);
                            assert!(
                                worst <= bound + 1e-6,
                                "az {az}: ({line}, {pos}) step {m} offset {off:.2}: {worst} above {bound}"
                            );
                        }
                    }
                }
            }
        }
    }

    /// The highest z − tan e·(d − d_m) along a ray from (line, x), from line step `m`
    /// on, sampling the triangulated surface densely.
    fn brute_ray(view: &SunView, line: usize, x: f64, m: usize, tan_e: f64) -> f64 {
        let mut worst = f64::NEG_INFINITY;
        for k in (m * 40)..=(line * 40) {
            let tau = k as f64 / 40.0;
            let (l, p) = (line as f64 - tau, x + tau * view.shift);
            if p < 0.0 || p > (view.n_pos - 1) as f64 {
                continue;
            }
            if let Some(h) = surface(view, l, p) {
                worst = worst.max(h - (tau - m as f64) * view.step_m * tan_e);
            }
        }
        worst
    }

    /// The triangulated surface at fractional (line, pos).
    fn surface(view: &SunView, l: f64, p: f64) -> Option<f64> {
        let (l0, p0) = (l.floor(), p.floor());
        let (fl, fp) = (l - l0, p - p0);
        let z = |dl: usize, dp: usize| {
            let (ll, pp) = (l0 as usize + dl, p0 as usize + dp);
            if ll >= view.n_lines || pp >= view.n_pos {
                return f64::NAN;
            }
            f64::from(view.z[view.slot(ll, pp)])
        };
        // Diagonal +1 joins (l, p)–(l+1, p+1); −1 joins (l, p+1)–(l+1, p).
        let h = if view.diagonal > 0 {
            if fp >= fl {
                z(0, 0) + (z(0, 1) - z(0, 0)) * fp + (z(1, 1) - z(0, 1)) * fl
            } else {
                z(0, 0) + (z(1, 0) - z(0, 0)) * fl + (z(1, 1) - z(1, 0)) * fp
            }
        } else if fp + fl <= 1.0 {
            z(0, 0) + (z(0, 1) - z(0, 0)) * fp + (z(1, 0) - z(0, 0)) * fl
        } else {
            z(1, 1) + (z(1, 0) - z(1, 1)) * (1.0 - fp) + (z(0, 1) - z(1, 1)) * (1.0 - fl)
        };
        (!h.is_nan()).then_some(h)
    }
}
