//! Surface-to-surface line of sight and viewsheds, by ray casts against a parry3d
//! `HeightField` (two triangles per quad of cell centres) — also behind
//! `reference::cast_shadows_parry`.
//!
//! parry3d works in f32, so the height field is re-centred on the map's middle and on
//! the observer's height: projected coordinates of 8e6 m would have 0.5 m steps.
//! Planetary curvature lowers every cell by d²/2R, d its distance from the observer.

use parry3d::math::Vector;
use parry3d::query::{Ray, RayCast};
use parry3d::shape::HeightField;
use parry3d::utils::Array2;

use crate::dem::Dem;
use crate::error::{Error, Result};
use crate::shadow::Curvature;

/// A DEM as a parry3d height field seen from one point, with the frame conversions.
pub(crate) struct Field {
    pub(crate) shape: HeightField,
    /// How far to step off a ray's origin: parry3d's height-field traversal misses
    /// everything when a ray starts exactly on a vertex column (cell centres are
    /// vertices here, and observers stand on them).
    nudge_m: f64,
    x_mid: f64,
    y_mid: f64,
    z_ref: f64,
}

impl Field {
    /// The DEM with heights lowered by curvature as seen from (ox, oy).
    pub(crate) fn new(dem: &Dem, ox: f64, oy: f64, z_ref: f64, curvature: Curvature) -> Result<Field> {
        let (cols, rows) = (dem.cols(), dem.rows());
        if cols < 2 || rows < 2 {
            return Err(Error::BadGrid("line of sight needs at least 2 x 2 cells".into()));
        }
        let inv_2r = curvature.inv_2r();
        let (x_first, y_first) = dem.cell_center(0, 0);
        let (x_last, y_last) = dem.cell_center(cols - 1, rows - 1);
        let (x_mid, y_mid) = ((x_first + x_last) / 2.0, (y_first + y_last) / 2.0);
        // Column-major, rows along parry's z (south), columns along x (east). Missing
        // cells sink far below so they never block, and so does a border of one cell
        // around the map: parry3d misses hits exactly on its height field's boundary,
        // where rays leaving the map cross the edge cells' terrain.
        let mut data = Vec::with_capacity((cols + 2) * (rows + 2));
        for c in 0..cols + 2 {
            for r in 0..rows + 2 {
                let h = if (1..=cols).contains(&c) && (1..=rows).contains(&r) {
                    let (x, y) = dem.cell_center(c - 1, r - 1);
                    let d2 = (x - ox).powi(2) + (y - oy).powi(2);
                    dem.z(c - 1, r - 1).map_or(-1.0e6, |z| f64::from(z) - z_ref - d2 * inv_2r)
                } else {
                    -1.0e6
                };
                data.push(h as f32);
            }
        }
        let scale = Vector::new(((cols + 1) as f64 * dem.dx()) as f32, 1.0, ((rows + 1) as f64 * dem.dy()) as f32);
        let nudge_m = 0.0001 * dem.dx().min(dem.dy());
        Ok(Field {
            shape: HeightField::new(Array2::new(rows + 2, cols + 2, data), scale),
            nudge_m,
            x_mid,
            y_mid,
            z_ref,
        })
    }

    pub(crate) fn local(&self, x: f64, y: f64, z: f64) -> Vector {
        Vector::new((x - self.x_mid) as f32, (z - self.z_ref) as f32, (self.y_mid - y) as f32)
    }

    /// Whether the segment from a to b (map coordinates and heights) clears the terrain,
    /// ignoring the last `tail_m` metres before b (the target's own ground).
    fn clear(&self, a: (f64, f64, f64), b: (f64, f64, f64), tail_m: f64) -> bool {
        let (pa, pb) = (self.local(a.0, a.1, a.2), self.local(b.0, b.1, b.2));
        let dir = pb - pa;
        let len = f64::from(dir.length());
        if len == 0.0 {
            return true;
        }
        let start = (self.nudge_m / len).min(0.5) as f32;
        let max_toi = ((len - tail_m) / len).max(0.0) as f32;
        if max_toi <= start {
            return true;
        }
        // Also off the vertex rows by a hundredth of a cell: parry3d's traversal loses
        // rays that run exactly along them.
        let origin = pa + dir * start + Vector::new(0.0, 0.0, self.nudge_m as f32);
        self.shape.cast_local_ray(&Ray::new(origin, dir), max_toi - start, false).is_none()
    }
}

/// Whether a point `a_height_m` above the ground at (ax, ay) sees a point
/// `b_height_m` above the ground at (bx, by); `None` if either is off the map or on
/// missing data.
pub fn line_of_sight(dem: &Dem, a: (f64, f64, f64), b: (f64, f64, f64), curvature: Curvature) -> Result<Option<bool>> {
    let (Some(za), Some(zb)) = (dem.height(a.0, a.1), dem.height(b.0, b.1)) else { return Ok(None) };
    let za = za + a.2;
    let field = Field::new(dem, a.0, a.1, za, curvature)?;
    let d2 = (b.0 - a.0).powi(2) + (b.1 - a.1).powi(2);
    let inv_2r = curvature.inv_2r();
    let zb = zb + b.2 - d2 * inv_2r;
    Ok(Some(field.clear((a.0, a.1, za), (b.0, b.1, zb), 0.5 * dem.dx().min(dem.dy()))))
}

/// The cells seen from a point `height_m` above the ground at (x, y) (a lander's
/// antenna, a relay): true where the cell centre, on the ground, is visible.
pub fn viewshed(dem: &Dem, x: f64, y: f64, height_m: f64, curvature: Curvature) -> Result<Vec<bool>> {
    let Some(z0) = dem.height(x, y) else {
        return Err(Error::BadGrid(format!("the observer ({x}, {y}) is off the map or on missing data")));
    };
    let eye = z0 + height_m;
    let field = Field::new(dem, x, y, eye, curvature)?;
    let inv_2r = curvature.inv_2r();
    let tail = 0.5 * dem.dx().min(dem.dy());
    let mut out = vec![false; dem.cols() * dem.rows()];
    for r in 0..dem.rows() {
        for c in 0..dem.cols() {
            let Some(z) = dem.z(c, r) else { continue };
            let (cx, cy) = dem.cell_center(c, r);
            let d2 = (cx - x).powi(2) + (cy - y).powi(2);
            let target = (cx, cy, f64::from(z) - d2 * inv_2r);
            out[dem.index(c, r)] = field.clear((x, y, eye), target, tail);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wall_hides_what_lies_behind_it() {
        let dem = Dem::from_fn(80, 9, 1.0, 1.0, |x, _| if (50.0..51.0).contains(&x) { 10.0 } else { 0.0 }).unwrap();
        let seen = viewshed(&dem, 10.5, 4.5, 2.0, Curvature::Flat).unwrap();
        let row = 4 * 80;
        assert!((0..50).all(|c| seen[row + c]), "in front of the wall");
        assert!((52..80).all(|c| !seen[row + c]), "behind the wall");
        assert_eq!(line_of_sight(&dem, (10.5, 4.5, 2.0), (70.5, 4.5, 0.0), Curvature::Flat).unwrap(), Some(false));
        // A mast above the wall's line: from 2 m at x=10 over a 10 m wall at x=50 the
        // sight line rises 0.2 m/m, so at x=70 it passes 14 m up.
        assert_eq!(line_of_sight(&dem, (10.5, 4.5, 2.0), (70.5, 4.5, 15.0), Curvature::Flat).unwrap(), Some(true));
        assert_eq!(line_of_sight(&dem, (10.5, 4.5, 2.0), (700.0, 4.5, 0.0), Curvature::Flat).unwrap(), None);
    }

    #[test]
    fn curvature_hides_the_far_plain() {
        // 2 m above a plain, the horizon of a 3389.5 km sphere is √(2·2·R) ≈ 3.68 km away.
        let dem = Dem::from_fn(100, 3, 100.0, 100.0, |_, _| 0.0).unwrap();
        let seen = viewshed(&dem, 50.0, 150.0, 2.0, Curvature::Sphere { radius_m: 3_389_500.0 }).unwrap();
        let row = 100;
        assert!(seen[row + 30], "3 km: visible");
        assert!(!seen[row + 45], "4.5 km: below the horizon");
        let flat = viewshed(&dem, 50.0, 150.0, 2.0, Curvature::Flat).unwrap();
        assert!(flat[row + 99]);
    }
}
