//! The rover's frames, and the conversions between its parameter types and nalgebra:
//! the one place where a body-frame point becomes a map point (parry's `math` module is
//! the model).
//!
//! Two frames, metres: the **map** frame (x east, y north, z up) and the **body** frame
//! about the body reference, the midpoint of the rocker pivots (x forward, y left,
//! z up). An [`Attitude`] — heading clockwise from north, pitch nose-up positive, roll
//! left-side-up positive, radians — turns one into the other: roll about the body x
//! axis, then pitch about y, then the turn to the heading.

use nalgebra::{Matrix3, Rotation3, Vector3};

use crate::params::BodyPoint;

impl From<BodyPoint> for Vector3<f64> {
    /// A body-frame point of a parameter file (x forward, y left, z up, m).
    fn from(p: BodyPoint) -> Vector3<f64> {
        Vector3::new(p.x, p.y, p.z)
    }
}

impl From<BodyPoint> for [f64; 3] {
    /// A body-frame point of a parameter file as (x forward, y left, z up), m.
    fn from(p: BodyPoint) -> [f64; 3] {
        [p.x, p.y, p.z]
    }
}

/// The rover body's orientation on the map, radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Attitude {
    /// Azimuth of the body x axis, clockwise from north.
    pub heading: f64,
    /// Elevation of the body x axis, nose up positive.
    pub pitch: f64,
    /// Roll about the body x axis, left side up positive.
    pub roll: f64,
}

impl Attitude {
    /// Horizontal unit vector along the heading (east, north).
    pub fn forward(&self) -> (f64, f64) {
        (self.heading.sin(), self.heading.cos())
    }

    /// A body-frame point `rel` (m) on the map, the body reference standing at
    /// `origin` (map, m). [`Attitude::map_to_body`] undoes it.
    pub fn body_to_map(&self, origin: [f64; 3], rel: [f64; 3]) -> [f64; 3] {
        let (fx, fy) = self.forward();
        let (lx, ly) = (-fy, fx);
        let (sp, cp) = self.pitch.sin_cos();
        let (sr, cr) = self.roll.sin_cos();
        let (bx, by, bz) = (rel[0], rel[1] * cr - rel[2] * sr, rel[1] * sr + rel[2] * cr);
        let (px, pz) = (bx * cp - bz * sp, bx * sp + bz * cp);
        [origin[0] + fx * px + lx * by, origin[1] + fy * px + ly * by, origin[2] + pz]
    }

    /// A map point `world` (m) in the body frame about a body reference at `origin`
    /// (map, m): the inverse of [`Attitude::body_to_map`].
    pub fn map_to_body(&self, origin: [f64; 3], world: [f64; 3]) -> [f64; 3] {
        let (fx, fy) = self.forward();
        let (lx, ly) = (-fy, fx);
        let (sp, cp) = self.pitch.sin_cos();
        let (sr, cr) = self.roll.sin_cos();
        let d = [world[0] - origin[0], world[1] - origin[1], world[2] - origin[2]];
        let (px, by, pz) = (d[0] * fx + d[1] * fy, d[0] * lx + d[1] * ly, d[2]);
        let (bx, bz) = (px * cp + pz * sp, -px * sp + pz * cp);
        let (ry, rz) = (by * cr + bz * sr, -by * sr + bz * cr);
        [bx, ry, rz]
    }

    /// The same turn as a rotation matrix (body → map), for callers working in
    /// nalgebra: columns are the body's forward, left and up axes on the map.
    pub fn rotation(&self) -> Rotation3<f64> {
        let (fx, fy) = self.forward();
        let heading = Matrix3::new(fx, -fy, 0.0, fy, fx, 0.0, 0.0, 0.0, 1.0);
        // Nose up is a negative turn about the body's left (y) axis.
        let pitch = Rotation3::from_axis_angle(&Vector3::y_axis(), -self.pitch);
        let roll = Rotation3::from_axis_angle(&Vector3::x_axis(), self.roll);
        Rotation3::from_matrix_unchecked(heading) * pitch * roll
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn near(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12)
    }

    #[test]
    fn each_angle_turns_the_axes_it_should() {
        let o = [10.0, 20.0, 5.0];
        let east = Attitude { heading: std::f64::consts::FRAC_PI_2, pitch: 0.0, roll: 0.0 };
        // Facing east, forward is +x and left is +y (north).
        assert!(near(east.body_to_map(o, [1.0, 0.0, 0.0]), [11.0, 20.0, 5.0]));
        assert!(near(east.body_to_map(o, [0.0, 1.0, 0.0]), [10.0, 21.0, 5.0]));
        // Facing north, pitched 90° nose up: forward points up.
        let up = Attitude { heading: 0.0, pitch: std::f64::consts::FRAC_PI_2, roll: 0.0 };
        assert!(near(up.body_to_map(o, [1.0, 0.0, 0.0]), [10.0, 20.0, 6.0]));
        // Rolled 90° left side up: left points up.
        let rolled = Attitude { heading: 0.0, pitch: 0.0, roll: std::f64::consts::FRAC_PI_2 };
        assert!(near(rolled.body_to_map(o, [0.0, 1.0, 0.0]), [10.0, 20.0, 6.0]));
    }

    #[test]
    fn the_matrix_the_formula_and_the_inverse_agree() {
        let o = [3.0, -4.0, 1.5];
        for k in 0..50 {
            let x = f64::from(k);
            let a = Attitude { heading: 0.37 * x, pitch: 0.9 * (0.21 * x).sin(), roll: 0.6 * (0.53 * x).cos() };
            let rel = [0.3 - 0.01 * x, 0.2 * (x * 0.7).sin(), -0.1 + 0.004 * x];
            let map = a.body_to_map(o, rel);
            let by_matrix = a.rotation() * Vector3::from(rel) + Vector3::from(o);
            assert!(near(map, by_matrix.into()), "attitude {a:?}");
            assert!(near(a.map_to_body(o, map), rel), "attitude {a:?}");
            // A rotation: lengths kept, determinant one.
            assert!((a.rotation().matrix().determinant() - 1.0).abs() < 1e-12);
        }
    }
}
