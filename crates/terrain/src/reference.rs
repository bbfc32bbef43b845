//! Brute-force references: one ray per cell, marched to the map's edge, with no
//! trace, no shared state between cells and no early exit. Slow (O(cells × length)) and
//! plain on purpose; the tests hold every [`Method`](crate::shadow::Method) of [`crate::shadow`] and the
//! horizon maps against them.
//!
//! - [`horizon_on_triangles`] / [`cast_shadows`]: each cell's own ray on the
//!   triangulated surface (cell centres joined by grid lines and each quad's
//!   south-west–north-east diagonal), tested at every edge it crosses: exact for that
//!   surface, and the definition [`Method::OwnRay`](crate::shadow::Method::OwnRay) reproduces.
//! - [`horizon_on_grid_lines`] / [`cast_shadows_on_grid_lines`]: the coarser surface
//!   [`Method::Interpolated`](crate::shadow::Method::Interpolated) samples.
//! - [`cast_shadows_parry`]: parry3d ray casts against a `HeightField`, independent of
//!   this crate's ray marching.

use parry3d::query::{Ray, RayCast};
use rayon::prelude::*;

use crate::dem::Dem;
use crate::error::Result;
use crate::los::Field;
use crate::shadow::{Curvature, GridSunDirection};

/// Cast shadow (true = shadowed) by each cell's own ray on the triangulated surface:
/// [`horizon_on_triangles`] above the Sun.
pub fn cast_shadows(dem: &Dem, sun: GridSunDirection, curvature: Curvature) -> Vec<bool> {
    if sun.elevation_deg <= 0.0 {
        return vec![true; dem.cols() * dem.rows()];
    }
    horizon_on_triangles(dem, sun.azimuth_deg, curvature).into_iter().map(|h| h > sun.elevation_deg).collect()
}

/// How close to a vertex, in edge fractions, a crossing counts as the vertex itself.
const EPS: f64 = 1e-9;

/// The surface on an edge between two vertices of heights `a` and `b`, a fraction `t`
/// from the first (a vertex's own height within [`EPS`] of it).
fn on_edge(a: f64, b: f64, t: f64) -> f64 {
    if t < EPS {
        a
    } else if t > 1.0 - EPS {
        b
    } else {
        a + (b - a) * t
    }
}

/// Per cell, the elevation angle (degrees) of the highest terrain seen toward
/// `azimuth_deg` along the cell's own ray (−90 where nothing rises, NaN on missing
/// cells): a cell is in cast shadow from a source at that azimuth exactly when the
/// source's elevation is below this angle. The ray is tested wherever it crosses an
/// edge of the triangulated surface (both families of grid lines and the cell
/// diagonals): exact for that surface. O(cells × length): the brute-force reference of every
/// [`Method`](crate::shadow::Method).
pub fn horizon_on_triangles(dem: &Dem, azimuth_deg: f64, curvature: Curvature) -> Vec<f64> {
    let (cols, rows) = (dem.cols() as i64, dem.rows() as i64);
    let a = azimuth_deg.to_radians();
    let snap = |v: f64| if v.abs() < 1e-12 { 0.0 } else { v };
    let (pc, pr) = (snap(a.sin() / dem.dx()), snap(-a.cos() / dem.dy()));
    let inv_2r = curvature.inv_2r();
    let at = |c: i64, r: i64| -> f64 {
        if c < 0 || r < 0 || c >= cols || r >= rows {
            return f64::NAN;
        }
        dem.z(c as usize, r as usize).map_or(f64::NAN, f64::from)
    };
    let inside =
        |fc: f64, fr: f64| fc > -EPS && fr > -EPS && fc < (cols - 1) as f64 + EPS && fr < (rows - 1) as f64 + EPS;
    // Each cell's ray reads only the DEM and writes only its own cell, so rows can run
    // in parallel.
    let ray = |c: i64, r: i64| -> f64 {
        let z0 = at(c, r);
        if z0.is_nan() {
            return f64::NAN;
        }
        let mut best = -90f64;
        let mut see = |s: f64, h: f64| {
            if !h.is_nan() {
                best = best.max(((h - s * s * inv_2r - z0) / s).atan().to_degrees());
            }
        };
        // Each family of edges: the ray's coordinate `rate·s` along it passes the
        // integers j = 1, 2, … at s = j/|rate|.
        for family in 0..3 {
            let rate = [pc, pr, pc + pr][family];
            if rate.abs() < 1e-12 {
                continue;
            }
            for j in 1.. {
                let s = j as f64 / rate.abs();
                let (fc, fr) = (c as f64 + pc * s, r as f64 + pr * s);
                if !inside(fc, fr) {
                    break;
                }
                let h = match family {
                    0 => {
                        let cc = c + j * rate.signum() as i64;
                        let r0 = fr.floor().max(0.0) as i64;
                        on_edge(at(cc, r0), at(cc, r0 + 1), fr - r0 as f64)
                    }
                    1 => {
                        let rr = r + j * rate.signum() as i64;
                        let c0 = fc.floor().max(0.0) as i64;
                        on_edge(at(c0, rr), at(c0 + 1, rr), fc - c0 as f64)
                    }
                    _ => {
                        let sum = c + r + j * rate.signum() as i64;
                        let c0 = fc.floor().max(0.0) as i64;
                        on_edge(at(c0, sum - c0), at(c0 + 1, sum - c0 - 1), fc - c0 as f64)
                    }
                };
                see(s, h);
            }
        }
        best
    };
    let mut out = vec![f64::NAN; (cols * rows) as usize];
    out.par_chunks_mut(cols as usize).enumerate().for_each(|(r, row)| {
        for (c, h) in row.iter_mut().enumerate() {
            *h = ray(c as i64, r as i64);
        }
    });
    out
}

/// Cast shadow on the grid-line surface (see [`horizon_on_grid_lines`]): the reference
/// of [`Method::Interpolated`](crate::shadow::Method::Interpolated), which samples that
/// surface. O(cells × length).
pub fn cast_shadows_on_grid_lines(dem: &Dem, sun: GridSunDirection, curvature: Curvature) -> Vec<bool> {
    if sun.elevation_deg <= 0.0 {
        return vec![true; dem.cols() * dem.rows()];
    }
    horizon_on_grid_lines(dem, sun.azimuth_deg, curvature).into_iter().map(|h| h > sun.elevation_deg).collect()
}

/// Per cell, the elevation angle (degrees) of the highest terrain seen toward
/// `azimuth_deg` along the cell's own ray (−90 where nothing rises, NaN on missing
/// cells): a cell is in cast shadow from a source at that azimuth exactly when the
/// source's elevation is below this angle. The ray is marched across the grid lines
/// of one family (columns or rows, whichever it crosses faster), the terrain
/// interpolated linearly along each crossed line: a coarser surface than the triangles.
pub fn horizon_on_grid_lines(dem: &Dem, azimuth_deg: f64, curvature: Curvature) -> Vec<f64> {
    let (cols, rows) = (dem.cols(), dem.rows());
    let a = azimuth_deg.to_radians();
    let (pc, pr) = (a.sin() / dem.dx(), -a.cos() / dem.dy());
    let snap = |v: f64| if v.abs() < 1e-12 { 0.0 } else { v };
    let (pc, pr) = (snap(pc), snap(pr));
    let along_cols = pc.abs() >= pr.abs();
    let inv_2r = curvature.inv_2r();
    let mut out = vec![f64::NAN; cols * rows];
    for r in 0..rows {
        for c in 0..cols {
            let Some(z0) = dem.z(c, r) else { continue };
            let z0 = f64::from(z0);
            let (step_m, dc, dr) = if along_cols {
                (1.0 / pc.abs(), pc.signum(), pr / pc.abs())
            } else {
                (1.0 / pr.abs(), pc / pr.abs(), pr.signum())
            };
            let mut best = -90f64;
            let mut k = 1.0;
            loop {
                let (fc, fr) = (c as f64 + dc * k, r as f64 + dr * k);
                if fc < -1e-9 || fr < -1e-9 || fc > (cols - 1) as f64 + 1e-9 || fr > (rows - 1) as f64 + 1e-9 {
                    break;
                }
                let interp = |a: Option<f32>, b: Option<f32>, t: f64| match (a, b) {
                    (Some(a), Some(b)) => f64::from(a) + (f64::from(b) - f64::from(a)) * t,
                    (Some(a), _) if t < 1e-9 => f64::from(a),
                    _ => f64::NEG_INFINITY,
                };
                let h = if along_cols {
                    let r0 = fr.floor().max(0.0) as usize;
                    interp(
                        dem.z(fc.round() as usize, r0),
                        dem.z(fc.round() as usize, (r0 + 1).min(rows - 1)),
                        fr - r0 as f64,
                    )
                } else {
                    let c0 = fc.floor().max(0.0) as usize;
                    interp(
                        dem.z(c0, fr.round() as usize),
                        dem.z((c0 + 1).min(cols - 1), fr.round() as usize),
                        fc - c0 as f64,
                    )
                };
                let d = step_m * k;
                if h.is_finite() {
                    best = best.max(((h - d * d * inv_2r - z0) / d).atan().to_degrees());
                }
                k += 1.0;
            }
            out[r * cols + c] = best;
        }
    }
    out
}

/// Cast shadows by one parry3d ray per cell toward the Sun: a reference written
/// independently of this crate's ray marching, on the same triangles (parry3d's
/// `HeightField`). Flat world only; parry3d works in f32, and its rays start a
/// thousandth of a cell aside (its traversal loses rays along vertex rows), so it
/// parts from [`cast_shadows`] where the Sun grazes the terrain.
pub fn cast_shadows_parry(dem: &Dem, sun: GridSunDirection) -> Result<Vec<bool>> {
    let (azimuth_deg, elevation_deg) = (sun.azimuth_deg, sun.elevation_deg);
    let (cx, cy) = dem.cell_center(dem.cols() / 2, dem.rows() / 2);
    let field = Field::new(dem, cx, cy, 0.0, Curvature::Flat)?;
    let (sa, ca) = azimuth_deg.to_radians().sin_cos();
    let (se, ce) = elevation_deg.to_radians().sin_cos();
    if elevation_deg <= 0.0 {
        return Ok(vec![true; dem.cols() * dem.rows()]);
    }
    // Horizontal distances: to the first grid-line crossing, and far enough to leave the map.
    // Half of it: parry3d misses hits from origins exactly on vertex lines, and the
    // terrain between a cell centre and that crossing is the cell's own facet.
    let skip = 0.01 * (dem.dx() / sa.abs().max(1e-12)).min(dem.dy() / ca.abs().max(1e-12));
    let reach = (dem.cols() as f64 * dem.dx()).hypot(dem.rows() as f64 * dem.dy()) * 2.0;
    let mut out = vec![false; dem.cols() * dem.rows()];
    for r in 0..dem.rows() {
        for c in 0..dem.cols() {
            let Some(z) = dem.z(c, r) else { continue };
            let (x, y) = dem.cell_center(c, r);
            // Start toward the first grid-line crossing, where the trace's occluders
            // begin: the cell's own slope (facing away from the Sun) is not a cast shadow.
            // The ray of a point a thousandth of a cell to the side, on the ground there:
            // parry3d's traversal loses rays that run exactly along vertex rows or
            // through vertices. Toward the map's middle, so that rays from border cells
            // stay on the map.
            let side = (ca, -sa);
            let to_mid = (cx - x, cy - y);
            let sign = if side.0 * to_mid.0 + side.1 * to_mid.1 >= 0.0 { 1.0 } else { -1.0 };
            let j = 0.001 * dem.dx().min(dem.dy()) * sign;
            let (x, y) = (x + side.0 * j, y + side.1 * j);
            let z = dem.height(x, y).unwrap_or(f64::from(z));
            let start = (x + skip * sa, y + skip * ca, z + skip * se / ce);
            let end = (x + reach * sa, y + reach * ca, z + reach * se / ce);
            let (pa, pb) = (field.local(start.0, start.1, start.2), field.local(end.0, end.1, end.2));
            let hit = field.shape.cast_local_ray(&Ray::new(pa, pb - pa), 1.0, false);
            out[dem.index(c, r)] = hit.is_some();
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::{Method, cast_shadows as cast};

    #[test]
    #[allow(clippy::print_stderr)] // the agreement figures are the point of the test
    fn the_methods_agree_with_parry_ray_casts() {
        let dem = crate::synth::rough_test_terrain(100, 80, 11, 30.0, 3);
        let (mut own_differ, mut cells) = (0, 0);
        for (az, el) in [(90.0, 15.0), (200.0, 25.0), (315.0, 10.0), (300.0, 8.0), (10.0, 15.0), (135.0, 5.0)] {
            let sun = GridSunDirection::new(az, el);
            let parry = cast_shadows_parry(&dem, sun).unwrap();
            let own = cast(&dem, sun, Curvature::Flat, Method::OwnRay);
            let fast = cast(&dem, sun, Curvature::Flat, Method::Interpolated);
            let horizon = horizon_on_triangles(&dem, az, Curvature::Flat);
            let (mut differ, mut worst) = (0, 0f64);
            for i in 0..parry.len() {
                if own[i] != parry[i] {
                    differ += 1;
                    worst = worst.max((horizon[i] - el).abs());
                }
            }
            let fast_differ = fast.iter().zip(&parry).filter(|(a, b)| a != b).count();
            eprintln!(
                "az {az} el {el}: own ray vs parry3d {differ} of {} differ (at most {worst:.3}° from grazing); interpolated vs parry3d {fast_differ}",
                parry.len()
            );
            // The same triangles: they part only where the Sun grazes the terrain
            // (parry3d works in f32, and its rays start a thousandth of a cell aside and
            // a hundredth of a step along, so they miss the cell's own steepest facet).
            assert!(worst <= 1.5, "az {az}: a disagreement {worst:.3}° from grazing");
            // The interpolated trace samples a coarser surface, and blurs far shadows.
            assert!(fast_differ as f64 / parry.len() as f64 <= 0.015, "az {az}: {fast_differ} differ");
            own_differ += differ;
            cells += parry.len();
        }
        let agree = 1.0 - own_differ as f64 / cells as f64;
        eprintln!("own ray vs parry3d over all: {:.4} % agree", 100.0 * agree);
        assert!(agree >= 0.999, "only {:.3} % agree with parry3d", 100.0 * agree);
    }
}
