//! [`Method::Sheared`](super::Method::Sheared): a trace of sheared rays on the
//! triangulated surface, approximate off the cardinal azimuths.
//!
//! Rays run toward the Sun three to a cell width, sheared so that each meets the
//! previous line exactly at one of its rays: each ray's envelope is exact, never
//! interpolated from step to step, and testing a ray where it crosses triangle edges is
//! exact because terrain minus ray height is piecewise linear along it. A cell's own
//! ray is tested back to the previous line; beyond it, the two rays beside the cell
//! (up to a third of a cell away) lend it their occluding triangles, moved sideways
//! onto its ray. That lending is the approximation: the measured disagreement with
//! each cell's own ray is in [`crate::shadow`]'s docs.

use crate::dem::Dem;
use crate::ray_lines::{LineGeometry, Lines};
use crate::shadow::Curvature;

/// Trace rays per cell width. A cell's envelope beyond its first step comes from the
/// rays beside it, at most a third of a cell away (agreement with per-cell rays at a
/// Sun 8–15° up: 99.81–99.83 % with 2, 99.89–99.94 % with 3, 99.93 % with 4).
const RAYS: usize = 3;

/// A point where a ray, stepping from one ray line to the next toward the source,
/// crosses a triangle edge between the two lines: a grid line of the other family or a
/// cell diagonal. Offsets are along the lines from the ray's cell `floor(q)`; line 0 is
/// the ray's own line, line 1 the sun-ward one.
#[derive(Debug, Clone, Copy)]
struct EdgeCrossing {
    /// Fraction of the step toward the sun-ward line.
    u: f64,
    /// The edge's ends: cell `a` of line 0 and cell `b` of line 1.
    a: isize,
    b: isize,
    /// The triangles either side of the crossing, along the lines: each one's slope
    /// along the lines is that of its side lying on a line, from cell k to k + 1:
    /// (line, k) to the left (decreasing position) and to the right.
    left: (usize, isize),
    right: (usize, isize),
    /// Metres back from the ray's point on its line.
    dist: f64,
    /// How far a shadow ray from the crossing sinks by the time it reaches the line, m.
    drop: f64,
}

/// At most one grid line and two diagonals lie between two lines along a ray.
const MAX_CROSSINGS: usize = 3;

/// The edge crossings between two lines of a ray whose position along its line has
/// fractional part `phi`, first; the unused slots after them sink infinitely, so they
/// never occlude.
fn edge_crossings(
    phi: f64,
    shift: f64,
    sigma: isize,
    step_m: f64,
    tan_e: f64,
    inv_2r: f64,
) -> [EdgeCrossing; MAX_CROSSINGS] {
    const EPS: f64 = 1e-9;
    // The lines bounding the strip, lower and higher index.
    let (lo, hi) = if sigma > 0 { (0, 1) } else { (1, 0) };
    let unused = EdgeCrossing { u: 0.5, a: 0, b: 0, left: (0, 0), right: (0, 0), dist: 0.0, drop: f64::INFINITY };
    let mut out = [unused; MAX_CROSSINGS];
    let mut n = 0;
    let mut add = |u: f64, a: isize, b: isize, diagonal: bool| {
        if u > EPS && u < 1.0 - EPS && n < MAX_CROSSINGS {
            let dist = u * step_m;
            // In the strip, a triangle below the diagonal (fractions across and along
            // summing under 1) has its along-line side on the lower line.
            let (left, right) = if diagonal {
                let k = (phi + shift * u).floor() as isize;
                ((lo, k), (hi, k))
            } else {
                ((hi, a - 1), (lo, a))
            };
            out[n] = EdgeCrossing { u, a, b, left, right, dist, drop: dist * tan_e + dist * dist * inv_2r };
            n += 1;
        }
    };
    // The other family's grid lines: the position q + shift·u passes an integer.
    if shift != 0.0 {
        for delta in -1..=2isize {
            add((delta as f64 - phi) / shift, delta, delta, false);
        }
    }
    // Diagonals (line + position constant): q + (σ + shift)·u passes an integer.
    let rate = sigma as f64 + shift;
    if rate.abs() > EPS {
        for delta in -2..=3isize {
            add((delta as f64 - phi) / rate, delta, delta - sigma, true);
        }
    }
    out
}

/// NaN cells either side of each line's buffers: every offset a crossing or a slope
/// reaches from a cell of the line lands inside them.
const PAD: usize = 4;
/// "No envelope" slots either side of each phase's rays: a ray's predecessor, and the
/// rays beside a cell, lie at most two slots past either end.
const EDGE: usize = 3;

/// One line: heights (NaN where missing) and the slope from each cell to the next, per
/// cell (0 where either end is missing: a missing neighbour lends no shadow sideways),
/// both padded: cell k at `PAD + k`.
struct LineBuf {
    z: Vec<f64>,
    slope: Vec<f64>,
}

impl LineBuf {
    fn new(n_cells: usize) -> LineBuf {
        LineBuf { z: vec![f64::NAN; n_cells + 2 * PAD], slope: vec![0.0; n_cells + 2 * PAD] }
    }

    /// Line `line`'s heights at `PAD + k`, and the slopes.
    fn load(&mut self, lines: &mut Lines<'_>, line: usize) {
        let n = self.z.len() - 2 * PAD;
        lines.read(line, &mut self.z[PAD..PAD + n]);
        for (s, w) in self.slope.iter_mut().zip(self.z.windows(2)) {
            let v = w[1] - w[0];
            *s = if v.is_nan() { 0.0 } else { v };
        }
    }
}

/// Envelopes of a line's rays: the highest shadow ray over each ray's point (a height;
/// −∞ if none), the distance back to the terrain that cast it, and that terrain's
/// slopes along the lines to either side, per cell (a parallel ray a little to the
/// side meets the same triangle there, so its envelope is about h + slope·offset).
/// Ray m = RAYS·j + p sits at slot p·stride + EDGE + j: each phase p is one contiguous
/// run, with the same geometry for all its rays, that the compiler can vectorise.
struct Envelopes {
    h: Vec<f64>,
    d: Vec<f64>,
    left: Vec<f64>,
    right: Vec<f64>,
    stride: usize,
}

impl Envelopes {
    fn new(n_cells: usize) -> Envelopes {
        let stride = n_cells + 2 * EDGE + 2;
        let n = RAYS * stride;
        Envelopes { h: vec![f64::NEG_INFINITY; n], d: vec![0.0; n], left: vec![0.0; n], right: vec![0.0; n], stride }
    }

    /// Clears the slots after phase p's `n` rays.
    fn end_phase(&mut self, p: usize, n: usize) {
        let from = p * self.stride + EDGE + n;
        self.h[from..from + EDGE].fill(f64::NEG_INFINITY);
        self.left[from..from + EDGE].fill(0.0);
        self.right[from..from + EDGE].fill(0.0);
    }
}

/// Cast shadow (true = shadowed) on the triangulated surface, by a trace.
///
/// The terrain is the DEM's triangulated surface: cell centres joined by the grid lines
/// and by each quad's south-west–north-east diagonal (parry3d's `HeightField` split).
/// Along a ray, terrain minus ray height is then piecewise linear, so testing the ray
/// where it crosses triangle edges is exact. Rays run toward the source `RAYS` to a cell
/// width, sheared so that each ray meets the previous line exactly at one of its rays:
/// each ray's envelope is exact, never interpolated from step to step. A cell's own
/// ray is tested exactly back to the previous line; beyond it, each of the two rays
/// beside it lends its occluding triangle, moved sideways onto the cell's ray.
pub(crate) fn cast(dem: &Dem, azimuth_deg: f64, elevation_deg: f64, curvature: Curvature) -> Vec<bool> {
    debug_assert!(elevation_deg > 0.0, "the door (`cast_shadows`) answers a Sun at or below the horizon");
    let geometry = LineGeometry::toward(dem, azimuth_deg);
    let (along_cols, n_lines, n_cells, toward_higher_line) =
        (geometry.along_cols, geometry.n_lines, geometry.n_cells, geometry.toward_higher_line);
    let trace = Trace::new(&geometry, elevation_deg, curvature);
    let mut shadow = vec![false; dem.cols() * dem.rows()];
    let mut prev = Envelopes::new(n_cells);
    let mut cur = Envelopes::new(n_cells);
    // The envelopes arriving from sun-ward, before each ray's own line joins them.
    let mut arriving = Envelopes::new(n_cells);
    let mut here = LineBuf::new(n_cells);
    let mut sun = LineBuf::new(n_cells);
    let mut line_shadow = vec![false; n_cells];
    let mut lines_io = Lines::new(dem, along_cols);
    let mut scratch = vec![0f64; n_cells + 1];
    let mut prev_phi = 0.0;
    // Lines nearest the source first.
    let order: Box<dyn Iterator<Item = usize>> =
        if toward_higher_line { Box::new((0..n_lines).rev()) } else { Box::new(0..n_lines) };
    for (i, line) in order.enumerate() {
        std::mem::swap(&mut here, &mut sun);
        here.load(&mut lines_io, line);
        // Rays sit at phi + m·ds along the line (phi < ds); a ray at q here was at
        // q + shift on the previous line.
        let ds = trace.ds;
        let mut phi = (-(i as f64) * trace.shift).rem_euclid(ds);
        if phi < 1e-9 || ds - phi < 1e-9 {
            phi = 0.0;
        }
        let n = (((n_cells - 1) as f64 - phi) / ds + 1e-9).floor() as usize + 1;
        let offset = ((phi + trace.shift - prev_phi) / ds).round() as isize;
        for p in 0..RAYS {
            let lines = (&here, &sun);
            let n_p = trace.phase(p, (phi, n, offset), lines, &prev, (&mut cur, &mut arriving), &mut scratch);
            cur.end_phase(p, n_p);
            arriving.end_phase(p, n_p);
        }
        if i > 0 {
            trace.decide(phi, (&here, &sun), &arriving, &mut scratch, &mut line_shadow);
        }
        lines_io.write(line, &line_shadow, &mut shadow);
        std::mem::swap(&mut prev, &mut cur);
        prev_phi = phi;
    }
    lines_io.finish(&mut shadow);
    shadow
}

/// What every line of one trace shares: the step toward the source and what a ray
/// drops over it, the rays' spacing, and the crossings of a cell's own ray.
struct Trace {
    /// The change in position along the lines from one line to the next toward the
    /// source, cells.
    shift: f64,
    /// +1 when the source lies toward higher line indices, else −1.
    sigma: isize,
    /// Metres travelled toward the source from one line to the next.
    step_m: f64,
    tan_e: f64,
    inv_2r: f64,
    /// How far a ray sinks over one step, m (elevation and curvature).
    line_drop: f64,
    /// The curvature's extra drop per metre already travelled, per step.
    curve_per_d: f64,
    /// The rays' spacing along a line, cells.
    ds: f64,
    n_cells: usize,
    /// A cell's own ray: its position is whole, so one set of crossings serves all.
    cell_crossings: [EdgeCrossing; MAX_CROSSINGS],
    /// `shift`'s whole and fractional parts.
    s_whole: isize,
    s_frac: f64,
    /// A cell's ray meets the previous line at k + shift, inside it for k in
    /// `k_lo..k_hi`.
    k_lo: usize,
    k_hi: usize,
}

impl Trace {
    fn new(g: &LineGeometry, elevation_deg: f64, curvature: Curvature) -> Trace {
        // Directions a hair off an axis or a diagonal would otherwise straddle two cells
        // with a weight of 1e-16 and lose the border cell's neighbour.
        let shift = if (g.shift - g.shift.round()).abs() < 1e-9 { g.shift.round() } else { g.shift };
        let (n_cells, step_m) = (g.n_cells, g.step_m);
        let sigma: isize = if g.toward_higher_line { 1 } else { -1 };
        let tan_e = elevation_deg.to_radians().tan();
        let inv_2r = curvature.inv_2r();
        let k_lo = ((-shift - 1e-9).ceil().max(0.0) as usize).min(n_cells);
        Trace {
            shift,
            sigma,
            step_m,
            tan_e,
            inv_2r,
            line_drop: step_m * tan_e + step_m * step_m * inv_2r,
            curve_per_d: 2.0 * step_m * inv_2r,
            ds: 1.0 / RAYS as f64,
            n_cells,
            cell_crossings: edge_crossings(0.0, shift, sigma, step_m, tan_e, inv_2r),
            s_whole: shift.floor() as isize,
            s_frac: shift - shift.floor(),
            k_lo,
            k_hi: (((n_cells - 1) as f64 - shift + 1e-9).floor() + 1.0).clamp(k_lo as f64, n_cells as f64) as usize,
        }
    }

    /// Advances phase `p` of a line's rays (rays m = RAYS·j + p at j + f, all with the
    /// same crossings) from the previous line's envelopes `prev` into `cur`, and the
    /// envelopes arriving before the line joins them into `arriving`; `phi` places the
    /// line's rays, `n` counts them, `offset` maps them to the previous line's. Returns
    /// the phase's ray count.
    fn phase(
        &self,
        p: usize,
        (phi, n, offset): (f64, usize, isize),
        (here, sun): (&LineBuf, &LineBuf),
        prev: &Envelopes,
        (cur, arriving): (&mut Envelopes, &mut Envelopes),
        scratch: &mut [f64],
    ) -> usize {
        let Trace { shift, sigma, step_m, tan_e, inv_2r, line_drop, curve_per_d, ds, .. } = *self;
        let lines = [here, sun];
        // Phase p: rays m = RAYS·j + p at j + f, all with the same crossings.
        let f = phi + p as f64 * ds;
        let n_p = if n > p { (n - p - 1) / RAYS + 1 } else { 0 };
        let crossings = edge_crossings(f, shift, sigma, step_m, tan_e, inv_2r);
        // The same ray on the previous line: phase pp, slot j + jshift.
        let (pp, jshift) =
            ((p as isize + offset).rem_euclid(RAYS as isize), (p as isize + offset).div_euclid(RAYS as isize));
        let from = (pp as usize * prev.stride) as isize + EDGE as isize + jshift;
        let from = from as usize;
        let (ph, pd, pl, pr_) = (
            &prev.h[from..from + n_p],
            &prev.d[from..from + n_p],
            &prev.left[from..from + n_p],
            &prev.right[from..from + n_p],
        );
        let at = |v, off: isize| run(v, PAD as isize + off, n_p);
        let z0 = at(&here.z, 0);
        let z1 = at(&here.z, 1);
        let s_m1 = at(&here.slope, -1);
        let s_0 = at(&here.slope, 0);
        let ca: [&[f64]; MAX_CROSSINGS] = std::array::from_fn(|c| at(&here.z, crossings[c].a));
        let cb: [&[f64]; MAX_CROSSINGS] = std::array::from_fn(|c| at(&sun.z, crossings[c].b));
        let cl: [&[f64]; MAX_CROSSINGS] =
            std::array::from_fn(|c| at(&lines[crossings[c].left.0].slope, crossings[c].left.1));
        let cr: [&[f64]; MAX_CROSSINGS] =
            std::array::from_fn(|c| at(&lines[crossings[c].right.0].slope, crossings[c].right.1));
        // The ray's own line: it casts the envelope from here on if it rises above
        // what arrives.
        let (here_h, here_l): (&[f64], &[f64]) = if f < 1e-9 {
            (z0, s_m1)
        } else {
            let buf = &mut scratch[..n_p];
            for ((b, a), c) in buf.iter_mut().zip(z0).zip(z1) {
                *b = lerp(*a, *c, f);
            }
            (&scratch[..n_p], s_0)
        };
        let inputs = RayInputs {
            prev: [ph, pd, pl, pr_],
            here: [here_h, here_l, s_0],
            crossings: std::array::from_fn(|c| [ca[c], cb[c], cl[c], cr[c]]),
            x: crossings,
            line_drop,
            curve_per_d,
            step_m,
        };
        let o = p * cur.stride + EDGE;
        let used = crossings.iter().filter(|x| x.drop.is_finite()).count();
        let run_phase = match used {
            0 => advance_rays::<0>,
            1 => advance_rays::<1>,
            2 => advance_rays::<2>,
            _ => advance_rays::<3>,
        };
        run_phase(
            &inputs,
            &mut cur.h[o..o + n_p],
            &mut cur.d[o..o + n_p],
            &mut cur.left[o..o + n_p],
            &mut cur.right[o..o + n_p],
            &mut arriving.h[o..o + n_p],
            &mut arriving.left[o..o + n_p],
            &mut arriving.right[o..o + n_p],
        );
        n_p
    }

    /// Decides the cells of the line `here` (with `sun` the line before it): each
    /// cell's own ray back to the previous line, exactly, the edges it crosses on the
    /// way, then the occluders of the rays either side (`arriving`), moved sideways
    /// onto it.
    fn decide(
        &self,
        phi: f64,
        (here, sun): (&LineBuf, &LineBuf),
        arriving: &Envelopes,
        scratch: &mut [f64],
        line_shadow: &mut [bool],
    ) {
        let Trace { line_drop, ds, n_cells, ref cell_crossings, s_whole, s_frac, k_lo, k_hi, .. } = *self;
        // The rays either side of cell k: m0 = RAYS·k + below, a fraction w of a
        // ray spacing (in cells) above it; the same for every cell of the line.
        let below: isize = if phi > 0.0 { -1 } else { 0 };
        let w = if phi > 0.0 { ds - phi } else { 0.0 };
        let ray_slot = |m0: isize| {
            let (p, j) = (m0.rem_euclid(RAYS as isize) as usize, m0.div_euclid(RAYS as isize));
            ((p * arriving.stride) as isize + EDGE as isize + j + k_lo as isize) as usize
        };
        let len = k_hi - k_lo;
        let (bs, as_) = (ray_slot(below), ray_slot(below + 1));
        let (bh, br) = (&arriving.h[bs..bs + len], &arriving.right[bs..bs + len]);
        let (ah, al) = (&arriving.h[as_..as_ + len], &arriving.left[as_..as_ + len]);
        // A cell exactly on a ray takes that ray's envelope alone.
        let above_gap = if w > 1e-9 { ds - w } else { f64::INFINITY };
        let at = |v, off: isize| run(v, (PAD + k_lo) as isize + off, len);
        let zc = at(&here.z, 0);
        let (n0, n1) = (at(&sun.z, s_whole), at(&sun.z, s_whole + 1));
        let ca: [&[f64]; MAX_CROSSINGS] = std::array::from_fn(|c| at(&here.z, cell_crossings[c].a));
        let cb: [&[f64]; MAX_CROSSINGS] = std::array::from_fn(|c| at(&sun.z, cell_crossings[c].b));
        // The cell's own ray back to the previous line, exactly; the edges it
        // crosses on the way; then the occluders of the rays on either side,
        // moved sideways onto it.
        let h = &mut scratch[..len];
        if s_frac < 1e-9 {
            for (h, a) in h.iter_mut().zip(n0) {
                *h = a - line_drop;
            }
        } else {
            for ((h, a), b) in h.iter_mut().zip(n0).zip(n1) {
                *h = lerp(*a, *b, s_frac) - line_drop;
            }
        }
        for c in 0..MAX_CROSSINGS {
            let x = &cell_crossings[c];
            if x.drop.is_finite() {
                cross_height(h, ca[c], cb[c], x);
            }
        }
        lend(h, bh, br, w);
        if above_gap.is_finite() {
            lend(h, ah, al, -above_gap);
        }
        for ((o, z), h) in line_shadow[k_lo..k_hi].iter_mut().zip(zc).zip(h.iter()) {
            *o = z < h;
        }
        // Cells whose ray leaves the map before the previous line: only the edges
        // crossed on the way out.
        for k in (0..k_lo).chain(k_hi..n_cells) {
            let mut h = f64::NEG_INFINITY;
            for c in cell_crossings {
                let t = lerp(
                    here.z[(PAD as isize + k as isize + c.a) as usize],
                    sun.z[(PAD as isize + k as isize + c.b) as usize],
                    c.u,
                ) - c.drop;
                h = if t > h { t } else { h };
            }
            line_shadow[k] = here.z[PAD + k] < h;
        }
    }
}

/// What one phase of a line's rays reads, each slice one value per ray: the same rays'
/// envelopes on the previous line (height, distance, slopes left and right), the rays'
/// own terrain (height, slopes), and per edge crossing its two ends and the slopes of
/// the triangles either side.
struct RayInputs<'a> {
    prev: [&'a [f64]; 4],
    here: [&'a [f64]; 3],
    crossings: [[&'a [f64]; 4]; MAX_CROSSINGS],
    x: [EdgeCrossing; MAX_CROSSINGS],
    line_drop: f64,
    curve_per_d: f64,
    step_m: f64,
}

/// One phase of a line's rays: the envelope arriving from sun-ward (`a*`: the previous
/// line's, one step lower, raised to any edge crossing's shadow above it) and the one
/// leaving (`c*`: the ray's own terrain where it rises to the arriving one). Every
/// output a separate slice: the compiler then knows they alias nothing and
/// vectorises the loop.
#[allow(clippy::too_many_arguments)]
fn advance_rays<const N: usize>(
    inp: &RayInputs<'_>,
    ch: &mut [f64],
    cd: &mut [f64],
    cl: &mut [f64],
    cr: &mut [f64],
    ah: &mut [f64],
    al: &mut [f64],
    ar: &mut [f64],
) {
    let n = ch.len();
    let (cd, cl, cr, ah, al, ar) = (&mut cd[..n], &mut cl[..n], &mut cr[..n], &mut ah[..n], &mut al[..n], &mut ar[..n]);
    let [ph, pd, pl, pr] = inp.prev.map(|v| &v[..n]);
    let [here, here_l, here_r] = inp.here.map(|v| &v[..n]);
    // The phase's N crossings (the rest of the slots are unused).
    let cs: [[&[f64]; 4]; N] = std::array::from_fn(|c| inp.crossings[c].map(|v| &v[..n]));
    let xs: [EdgeCrossing; N] = std::array::from_fn(|c| inp.x[c]);
    let (line_drop, curve_per_d, step_m) = (inp.line_drop, inp.curve_per_d, inp.step_m);
    for j in 0..n {
        let mut h = ph[j] - line_drop - curve_per_d * pd[j];
        let mut d = pd[j] + step_m;
        let (mut l, mut r) = (pl[j], pr[j]);
        for (c, x) in cs.iter().zip(&xs) {
            let t = lerp(c[0][j], c[1][j], x.u) - x.drop;
            // NaN (a missing end) never wins.
            let win = t > h;
            h = if win { t } else { h };
            d = if win { x.dist } else { d };
            l = if win { c[2][j] } else { l };
            r = if win { c[3][j] } else { r };
        }
        (ah[j], al[j], ar[j]) = (h, l, r);
        // NaN (missing) terrain never rises to the envelope.
        let own = here[j] >= h;
        ch[j] = if own { here[j] } else { h };
        cd[j] = if own { 0.0 } else { d };
        cl[j] = if own { here_l[j] } else { l };
        cr[j] = if own { here_r[j] } else { r };
    }
}

/// Raises heights to an edge crossing's shadow where it is higher; `za`, `zb`: the
/// edge's ends per ray.
fn cross_height(h: &mut [f64], za: &[f64], zb: &[f64], x: &EdgeCrossing) {
    let n = h.len();
    let (za, zb) = (&za[..n], &zb[..n]);
    for j in 0..n {
        let t = lerp(za[j], zb[j], x.u) - x.drop;
        h[j] = if t > h[j] { t } else { h[j] };
    }
}

/// Raises heights to a neighbouring ray's envelope moved `offset` cells sideways along
/// its occluding triangle.
fn lend(h: &mut [f64], eh: &[f64], slope: &[f64], offset: f64) {
    let n = h.len();
    let (eh, slope) = (&eh[..n], &slope[..n]);
    for j in 0..n {
        let t = eh[j] + slope[j] * offset;
        h[j] = if t > h[j] { t } else { h[j] };
    }
}

/// `len` values of `v` from `start` (not negative).
#[inline]
fn run(v: &[f64], start: isize, len: usize) -> &[f64] {
    &v[start as usize..start as usize + len]
}

/// Linear interpolation; NaN (missing) if either end is.
#[inline]
fn lerp(a: f64, b: f64, t: f64) -> f64 {
    a + (b - a) * t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::horizon_on_triangles;

    #[test]
    #[allow(clippy::print_stderr)] // the agreement figures are the point of the test
    fn the_swept_method_agrees_with_per_cell_rays_on_rough_terrain() {
        let dem = crate::synth::rough_test_terrain(120, 90, 7, 40.0, 4);
        let (mut differ_all, mut cells_all) = (0, 0);
        for (az, el) in
            [(90.0, 20.0), (135.0, 10.0), (200.0, 35.0), (300.0, 8.0), (10.0, 15.0), (45.0, 3.0), (250.0, 12.0)]
        {
            let trace = cast(&dem, az, el, Curvature::Flat);
            let horizon = horizon_on_triangles(&dem, az, Curvature::Flat);
            let (mut differ, mut worst) = (0, 0f64);
            for (s, h) in trace.iter().zip(&horizon) {
                if h.is_nan() {
                    continue;
                }
                if *s != (*h > el) {
                    differ += 1;
                    worst = worst.max((h - el).abs());
                }
            }
            eprintln!(
                "az {az:5.1} el {el:4.1}: {differ} of {} cells differ, at most {worst:.2}° from grazing",
                trace.len()
            );
            // The rays beside a cell lend it their occluders; they miss only where the
            // terrain's horizon is within a degree and a half of the Sun.
            assert!(worst <= 1.5, "az {az} el {el}: a disagreement {worst:.2}° from grazing");
            differ_all += differ;
            cells_all += trace.len();
        }
        let agree = 1.0 - differ_all as f64 / cells_all as f64;
        assert!(agree >= 0.999, "only {:.3} % agree", 100.0 * agree);
    }

    #[test]
    fn along_axes_and_diagonals_the_sweep_is_exact() {
        // There every ray meets the previous line at a cell: nothing is borrowed from
        // neighbouring rays.
        let dem = crate::synth::rough_test_terrain(60, 60, 3, 40.0, 4);
        for (az, el) in [(0.0, 10.0), (90.0, 5.0), (135.0, 12.0), (225.0, 7.0), (315.0, 20.0)] {
            let trace = cast(&dem, az, el, Curvature::Flat);
            let horizon = horizon_on_triangles(&dem, az, Curvature::Flat);
            for (i, (s, h)) in trace.iter().zip(&horizon).enumerate() {
                assert_eq!(*s, *h > el, "az {az}: cell {i}, horizon {h}");
            }
        }
    }

    #[test]
    fn a_vertical_wall_and_a_curved_horizon() {
        let (h, e) = (20.0, 30.0f64);
        let dem = Dem::from_fn(200, 20, 1.0, 1.0, |x, _| if (50.0..51.0).contains(&x) { h } else { 0.0 }).unwrap();
        let s = cast(&dem, 270.0, e, Curvature::Flat);
        let len = (51..200).take_while(|&c| s[10 * 200 + c]).count() as f64;
        assert!((len - h / e.to_radians().tan()).abs() <= 1.0, "shadow {len} m");
        assert!((0..50).all(|c| !s[10 * 200 + c]));
        // A 1000 m peak 100 km west, Sun at 0.3°: hidden by the curvature of Mars.
        let dem = Dem::from_fn(1101, 3, 100.0, 100.0, |x, _| if x < 100.0 { 1000.0 } else { 0.0 }).unwrap();
        let target = 2 * 1101 + 1000;
        assert!(cast(&dem, 270.0, 0.3, Curvature::Flat)[target]);
        assert!(!cast(&dem, 270.0, 0.3, Curvature::Sphere { radius_m: 3_389_500.0 })[target]);
        let truth = horizon_on_triangles(&dem, 270.0, Curvature::Sphere { radius_m: 3_389_500.0 });
        assert!(truth[target] < 0.3);
    }
}
