//! Slope, aspect and normals by Horn's method (Horn 1981), with separate dx and dy as
//! gdaldem and GRASS `r.slope.aspect` use them.
//!
//! For cell e with neighbours
//! ```text
//!   a b c      (north)
//!   d e f
//!   g h i      (south)
//! ```
//! ∂z/∂x = ((c + 2f + i) − (a + 2d + g)) / 8dx and ∂z/∂y (north) = ((a + 2b + c) −
//! (g + 2h + i)) / 8dy. Slope = atan |∇z|; aspect = the azimuth of steepest descent,
//! clockwise from north (a slope facing east has aspect 90°); flat cells have aspect NaN.
//!
//! Edges and nodata: a neighbour off the grid or missing is extrapolated linearly
//! through the centre from the opposite neighbour (2e − opposite), which keeps planes
//! exact at edges and beside holes; if the opposite is missing too, the centre value is
//! used. A missing centre cell gives NaN.

use rayon::prelude::*;

use crate::dem::Dem;

/// Slope, aspect and gradient grids of a DEM (row-major like the DEM; NaN where
/// undefined).
#[derive(Debug, Clone, PartialEq)]
pub struct SlopeAspect {
    /// Slope, degrees.
    pub slope_deg: Vec<f32>,
    /// Aspect, degrees clockwise from north; NaN on flat or missing cells.
    pub aspect_deg: Vec<f32>,
    /// ∂z/∂x (east).
    pub dzdx: Vec<f32>,
    /// ∂z/∂y (north).
    pub dzdy: Vec<f32>,
}

impl SlopeAspect {
    /// Upward unit normal of cell `i` (NaN on missing cells).
    pub fn normal(&self, i: usize) -> [f64; 3] {
        crate::dem::unit_normal(f64::from(self.dzdx[i]), f64::from(self.dzdy[i]))
    }
}

/// Horn gradient at every cell, in parallel by rows (identical for any thread count:
/// each cell depends only on its inputs).
pub fn horn_gradient(dem: &Dem) -> (Vec<f32>, Vec<f32>) {
    let (cols, rows) = (dem.cols(), dem.rows());
    let z = dem.elevations();
    let valid = dem.valid_mask();
    let (kx, ky) = (1.0 / (8.0 * dem.dx()), 1.0 / (8.0 * dem.dy()));
    let mut gx = vec![0f32; cols * rows];
    let mut gy = vec![0f32; cols * rows];
    let all_valid = valid.iter().all(|v| *v);
    gx.par_chunks_mut(cols).zip(gy.par_chunks_mut(cols)).enumerate().for_each(|(r, (rx, ry))| {
        // Interior cells of a DEM without holes: the plain stencil, no neighbour tests.
        let fast = all_valid && r > 0 && r + 1 < rows && cols >= 3;
        if fast {
            let (up, mid, down) =
                (&z[(r - 1) * cols..r * cols], &z[r * cols..(r + 1) * cols], &z[(r + 1) * cols..(r + 2) * cols]);
            let (kx, ky) = (kx as f32, ky as f32);
            for c in 1..cols - 1 {
                let (a, b, cc) = (up[c - 1], up[c], up[c + 1]);
                let (d, f) = (mid[c - 1], mid[c + 1]);
                let (g, h, i) = (down[c - 1], down[c], down[c + 1]);
                rx[c] = ((cc + 2.0 * f + i) - (a + 2.0 * d + g)) * kx;
                ry[c] = ((a + 2.0 * b + cc) - (g + 2.0 * h + i)) * ky;
            }
        }
        let general: Box<dyn Iterator<Item = usize>> =
            if fast { Box::new([0, cols - 1].into_iter()) } else { Box::new(0..cols) };
        for c in general {
            let centre = r * cols + c;
            if !valid[centre] {
                rx[c] = f32::NAN;
                ry[c] = f32::NAN;
                continue;
            }
            let e = f64::from(z[centre]);
            // The 3×3 neighbourhood, None where off the grid or missing.
            let get = |dc: isize, dr: isize| -> Option<f64> {
                let (cc, rr) = (c as isize + dc, r as isize + dr);
                if cc < 0 || rr < 0 || cc >= cols as isize || rr >= rows as isize {
                    return None;
                }
                let i = rr as usize * cols + cc as usize;
                valid[i].then(|| f64::from(z[i]))
            };
            let n = |dc: isize, dr: isize| -> f64 {
                get(dc, dr).unwrap_or_else(|| get(-dc, -dr).map_or(e, |opposite| 2.0 * e - opposite))
            };
            let (a, b, cc) = (n(-1, -1), n(0, -1), n(1, -1));
            let (d, f) = (n(-1, 0), n(1, 0));
            let (g, h, i) = (n(-1, 1), n(0, 1), n(1, 1));
            rx[c] = (((cc + 2.0 * f + i) - (a + 2.0 * d + g)) * kx) as f32;
            ry[c] = (((a + 2.0 * b + cc) - (g + 2.0 * h + i)) * ky) as f32;
        }
    });
    (gx, gy)
}

/// Slope and aspect of every cell.
pub fn slope_aspect(dem: &Dem) -> SlopeAspect {
    let (dzdx, dzdy) = horn_gradient(dem);
    let mut slope_deg = vec![0f32; dzdx.len()];
    let mut aspect_deg = vec![0f32; dzdx.len()];
    slope_deg.par_chunks_mut(4096).zip(aspect_deg.par_chunks_mut(4096)).enumerate().for_each(|(chunk, (ss, aa))| {
        let off = chunk * 4096;
        let (gxs, gys) = (&dzdx[off..off + ss.len()], &dzdy[off..off + ss.len()]);
        for (((s, a), &gx), &gy) in ss.iter_mut().zip(aa.iter_mut()).zip(gxs).zip(gys) {
            *s = fast_atan((gx * gx + gy * gy).sqrt()).to_degrees();
            // Downslope direction (−gx east, −gy north) as an azimuth.
            let az = fast_atan2(-gx, -gy).to_degrees();
            let az = if az < 0.0 { az + 360.0 } else { az };
            *a = if gx == 0.0 && gy == 0.0 { f32::NAN } else { az };
        }
    });
    SlopeAspect { slope_deg, aspect_deg, dzdx, dzdy }
}

/// atan to within ~1e-7 rad: reduce |x| to [0, 1] (atan x = π/2 − atan 1/x), then to
/// [−tan 15°, tan 15°] (atan t = π/6 + atan((√3t − 1)/(√3 + t))), where six terms of the
/// Taylor series leave an error below 3e-9. Written without branches (both sides of
/// each reduction are computed and selected) so that loops over grids vectorise;
/// libm's atan is the bottleneck otherwise.
#[inline]
pub(crate) fn fast_atan(x: f32) -> f32 {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_6};
    const SQRT_3: f32 = 1.732_050_8;
    const TAN_15: f32 = 0.267_949_2;
    let ax = x.abs();
    let invert = ax > 1.0;
    let t = if invert { 1.0 / ax } else { ax };
    let shifted = t > TAN_15;
    let u = if shifted { (SQRT_3 * t - 1.0) / (SQRT_3 + t) } else { t };
    let offset = if shifted { FRAC_PI_6 } else { 0.0 };
    let u2 = u * u;
    let series = u * (1.0 - u2 * (1.0 / 3.0 - u2 * (1.0 / 5.0 - u2 * (1.0 / 7.0 - u2 * (1.0 / 9.0 - u2 / 11.0)))));
    let r = offset + series;
    let r = if invert { FRAC_PI_2 - r } else { r };
    let r = r.copysign(x);
    if x.is_nan() { x } else { r }
}

/// atan2(y, x) from [`fast_atan`], branch-free in the same way.
#[inline]
fn fast_atan2(y: f32, x: f32) -> f32 {
    use std::f32::consts::{FRAC_PI_2, PI};
    let ay = y.abs();
    let ax = x.abs();
    // atan of the smaller over the larger keeps the argument in [0, 1].
    let swap = ay > ax;
    let (num, den) = if swap { (ax, ay) } else { (ay, ax) };
    let a = fast_atan(if den == 0.0 { 0.0 } else { num / den });
    let a = if swap { FRAC_PI_2 - a } else { a };
    let a = if x < 0.0 { PI - a } else { a };
    a.copysign(y)
}

#[cfg(test)]
mod tests {
    #[test]
    fn fast_arctangents_are_accurate() {
        let mut worst = 0f32;
        for i in -20_000..=20_000 {
            let x = i as f32 * 0.003;
            worst = worst.max((super::fast_atan(x) - x.atan()).abs());
            for y in [-3.0f32, -0.5, 0.0, 0.7, 5.0] {
                worst = worst.max((super::fast_atan2(y, x) - y.atan2(x)).abs());
            }
        }
        assert!(worst < 1e-5, "{worst}");
    }

    use super::*;

    fn check_plane(gx: f64, gy: f64, dx: f64, dy: f64) {
        let dem = Dem::from_fn(7, 5, dx, dy, |x, y| 100.0 + gx * x + gy * y).unwrap();
        let sa = slope_aspect(&dem);
        let slope = (gx * gx + gy * gy).sqrt().atan().to_degrees();
        let aspect = (-gx).atan2(-gy).to_degrees().rem_euclid(360.0);
        for r in 1..4 {
            for c in 1..6 {
                let i = dem.index(c, r);
                assert!((f64::from(sa.slope_deg[i]) - slope).abs() < 1e-3, "slope {} vs {slope}", sa.slope_deg[i]);
                assert!((f64::from(sa.aspect_deg[i]) - aspect).abs() < 1e-3, "aspect {} vs {aspect}", sa.aspect_deg[i]);
            }
        }
    }

    #[test]
    fn tilted_planes_with_unequal_cells() {
        check_plane(0.3, 0.0, 10.0, 20.0); // rises east: faces west, 270°
        check_plane(0.0, -0.2, 10.0, 20.0); // falls north: faces north, 0°
        check_plane(-0.1, -0.1, 461.0, 463.06); // faces north-east, 45°
        check_plane(0.4, 0.25, 3.0, 1.0);
    }

    #[test]
    fn paraboloid_slope_matches_the_analytic_gradient() {
        // z = a x² + b y²: Horn's stencil is exact for quadratics in each direction.
        let (a, b) = (0.002, 0.005);
        let (dx, dy) = (2.0, 3.0);
        let dem = Dem::from_fn(21, 15, dx, dy, |x, y| a * (x - 20.0).powi(2) + b * (y - 22.5).powi(2)).unwrap();
        let sa = slope_aspect(&dem);
        for r in 1..14 {
            for c in 1..20 {
                let (x, y) = dem.cell_center(c, r);
                let (gx, gy) = (2.0 * a * (x - 20.0), 2.0 * b * (y - 22.5));
                let i = dem.index(c, r);
                assert!((f64::from(sa.dzdx[i]) - gx).abs() < 1e-5 && (f64::from(sa.dzdy[i]) - gy).abs() < 1e-5);
                let slope = gx.hypot(gy).atan().to_degrees();
                assert!((f64::from(sa.slope_deg[i]) - slope).abs() < 1e-3);
            }
        }
    }

    #[test]
    fn flat_cells_have_no_aspect_and_edges_are_one_sided() {
        let flat = Dem::from_fn(4, 4, 1.0, 1.0, |_, _| 5.0).unwrap();
        let sa = slope_aspect(&flat);
        assert!(sa.slope_deg.iter().all(|s| *s == 0.0));
        assert!(sa.aspect_deg.iter().all(|a| a.is_nan()));
        // Extrapolated neighbours keep a plane exact on the edges, corners and next to
        // a hole.
        let ramp = Dem::from_fn(5, 5, 1.0, 2.0, |x, y| x - 0.5 * y).unwrap();
        let mut mask = vec![true; 25];
        mask[ramp.index(2, 2)] = false;
        let holed = ramp.clone().with_mask(mask).unwrap();
        let sa = slope_aspect(&holed);
        for (c, r) in [(0, 2), (2, 0), (4, 4), (0, 0), (1, 2), (3, 3)] {
            let i = ramp.index(c, r);
            assert!((sa.dzdx[i] - 1.0).abs() < 1e-5 && (sa.dzdy[i] + 0.5).abs() < 1e-5, "({c},{r})");
        }
        assert!(sa.slope_deg[ramp.index(2, 2)].is_nan());
    }
}
