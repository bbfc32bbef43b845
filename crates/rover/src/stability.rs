//! Tip-over stability: the force-angle measure of Papadopoulos & Rey (ICRA 1996;
//! Vehicle System Dynamics 33(1), 2000).
//!
//! The wheel contacts' convex hull (projected along gravity, ordered clockwise seen from
//! above) gives the tip-over axes. For each axis, the net force on the vehicle other
//! than the ground reactions (quasi-statically m·g plus any external load) is reduced
//! to its component normal to the axis, an external moment adds an equivalent force,
//! and the signed angle between that force and the axis normal through the centre of
//! mass is the axis' margin: positive is stable, zero is tipping.
//!
//! Farritor et al. report the margin normalised by its flat-ground value. Two
//! readings exist; [`Normalisation`] chooses: per axis, S = min_i θ_i / θ_i^flat (the
//! default: lateral and longitudinal axes share a 0–1 scale), or global,
//! S = min_i θ_i / min_i θ_i^flat.

use nalgebra::Vector3;

/// How margins are normalised by their flat-ground values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Normalisation {
    /// S = min over axes of θ_i / θ_i^flat.
    #[default]
    PerAxis,
    /// S = (min θ_i) / (min θ_i^flat).
    Global,
}

/// Most contacts [`force_angle`] takes (six wheels and room for an arm or a belly).
pub const MAX_CONTACTS: usize = 8;

/// The force-angle margins of one configuration (fixed capacity: no allocation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceAngle {
    hull: [Vector3<f64>; MAX_CONTACTS],
    angles: [f64; MAX_CONTACTS],
    len: usize,
}

impl ForceAngle {
    /// The support polygon's vertices (contact points), clockwise seen from above.
    pub fn hull(&self) -> &[Vector3<f64>] {
        &self.hull[..self.len]
    }

    /// Signed angle per tip-over axis (edge i runs from `hull[i]` to `hull[i+1]`), rad.
    pub fn angles(&self) -> &[f64] {
        &self.angles[..self.len]
    }

    /// The smallest angle and its axis.
    pub fn critical(&self) -> Option<(usize, f64)> {
        self.angles().iter().copied().enumerate().min_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// The outward horizontal normal of axis i (unit, perpendicular to the edge and to
    /// `down`, pointing away from the polygon).
    pub fn outward(&self, i: usize, down: Vector3<f64>) -> Vector3<f64> {
        let (p, q) = (self.hull[i], self.hull[(i + 1) % self.len]);
        // Clockwise seen from above, the inside is on the right of p → q and the
        // outside on the left: up × (q − p).
        let up = -down.normalize();
        up.cross(&(q - p)).try_normalize(1e-15).unwrap_or_else(Vector3::zeros)
    }
}

/// The force-angle margins for contacts `points` (m), centre of mass `cg` (m), net
/// force `force` (N, e.g. m·g as a vector) and net moment about the CG `moment` (N·m).
/// Gravity's direction is taken from `force` for the projection. `None` when the
/// contacts do not span a polygon or there are more than [`MAX_CONTACTS`].
pub fn force_angle(
    points: &[Vector3<f64>],
    cg: Vector3<f64>,
    force: Vector3<f64>,
    moment: Vector3<f64>,
) -> Option<ForceAngle> {
    let down = force.try_normalize(1e-12)?;
    let (hull, n) = hull_clockwise(points, down)?;
    let mut angles = [0.0; MAX_CONTACTS];
    for i in 0..n {
        let (p, q) = (hull[i], hull[(i + 1) % n]);
        let a = (q - p).normalize();
        let proj = |v: Vector3<f64>| v - a * a.dot(&v);
        let l = proj(q - cg);
        let f = proj(force);
        let n_i = a * a.dot(&moment);
        let l_hat = l.normalize();
        let f_star = f + l_hat.cross(&n_i) / l.norm();
        let f_hat = f_star.try_normalize(1e-15)?;
        let theta = f_hat.dot(&l_hat).clamp(-1.0, 1.0).acos();
        let sigma = if l_hat.cross(&f_hat).dot(&a) < 0.0 { 1.0 } else { -1.0 };
        angles[i] = sigma * theta;
    }
    Some(ForceAngle { hull, angles, len: n })
}

/// The normalised margin S of `now` against the flat-ground configuration `flat` (the
/// same contacts in the same order, so axis i matches axis i).
pub fn normalised_margin(now: &ForceAngle, flat: &ForceAngle, how: Normalisation) -> Option<f64> {
    if now.len != flat.len || now.len == 0 {
        return None;
    }
    match how {
        Normalisation::PerAxis => now.angles().iter().zip(flat.angles()).map(|(a, f)| a / f).min_by(f64::total_cmp),
        Normalisation::Global => Some(now.critical()?.1 / flat.critical()?.1),
    }
}

/// Convex hull of `points` projected on the plane normal to `down`, clockwise seen from
/// above (looking along `down`), collinear points dropped; the 3-D points are kept.
fn hull_clockwise(points: &[Vector3<f64>], down: Vector3<f64>) -> Option<([Vector3<f64>; MAX_CONTACTS], usize)> {
    let n = points.len();
    if !(3..=MAX_CONTACTS).contains(&n) {
        return None;
    }
    // A right-handed basis (e1, e2, up) with up = −down.
    let up = -down;
    let seed = if up.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    let e1 = (seed - up * up.dot(&seed)).normalize();
    let e2 = up.cross(&e1);
    let mut pts = [(0.0, 0.0, 0usize); MAX_CONTACTS];
    for (i, p) in points.iter().enumerate() {
        pts[i] = (p.dot(&e1), p.dot(&e2), i);
    }
    let pts = &mut pts[..n];
    pts.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
    let cross = |o: (f64, f64, usize), a: (f64, f64, usize), b: (f64, f64, usize)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    // Andrew's monotone chain, counter-clockwise in (e1, e2) seen from above.
    let mut chain = [(0.0, 0.0, 0usize); 2 * MAX_CONTACTS];
    let mut k = 0;
    for &p in pts.iter() {
        while k >= 2 && cross(chain[k - 2], chain[k - 1], p) <= 1e-12 {
            k -= 1;
        }
        chain[k] = p;
        k += 1;
    }
    let lower = k + 1;
    for &p in pts.iter().rev().skip(1) {
        while k >= lower && cross(chain[k - 2], chain[k - 1], p) <= 1e-12 {
            k -= 1;
        }
        chain[k] = p;
        k += 1;
    }
    // The last point repeats the first.
    let m = k - 1;
    if m < 3 {
        return None;
    }
    // Clockwise seen from above.
    let mut hull = [Vector3::zeros(); MAX_CONTACTS];
    for (j, c) in chain[..m].iter().rev().enumerate() {
        hull[j] = points[c.2];
    }
    Some((hull, m))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// LSR-1 contacts on flat ground (rover frame): x ∈ {0.4, 0, −0.4}, y = ±0.3.
    fn contacts() -> Vec<Vector3<f64>> {
        let mut v = Vec::new();
        for x in [0.4, 0.0, -0.4] {
            for y in [0.3, -0.3] {
                v.push(Vector3::new(x, y, 0.0));
            }
        }
        v
    }

    fn gravity_tilted(roll_deg: f64, pitch_deg: f64) -> Vector3<f64> {
        // The rover on a slope: gravity seen in the rover frame.
        let (r, p) = (roll_deg.to_radians(), pitch_deg.to_radians());
        Vector3::new(-p.sin(), r.sin() * p.cos(), -r.cos() * p.cos()) * 7.0 * 9.81
    }

    fn margin(roll: f64, pitch: f64, cg: Vector3<f64>) -> f64 {
        let flat =
            force_angle(&contacts(), Vector3::new(0.0, 0.0, 0.25), gravity_tilted(0.0, 0.0), Vector3::zeros()).unwrap();
        let now = force_angle(&contacts(), cg, gravity_tilted(roll, pitch), Vector3::zeros()).unwrap();
        normalised_margin(&now, &flat, Normalisation::PerAxis).unwrap()
    }

    #[test]
    fn flat_ground_angles_match_the_geometry() {
        let fa =
            force_angle(&contacts(), Vector3::new(0.0, 0.0, 0.25), gravity_tilted(0.0, 0.0), Vector3::zeros()).unwrap();
        assert_eq!(fa.hull().len(), 4, "middle wheels lie on the side edges");
        let mut deg: Vec<f64> = fa.angles().iter().map(|a| a.to_degrees()).collect();
        deg.sort_by(f64::total_cmp);
        // Lateral atan(0.30/0.25) = 50.19°, longitudinal atan(0.40/0.25) = 57.99°.
        for (got, want) in deg.iter().zip([50.19, 50.19, 57.99, 57.99]) {
            assert!((got - want).abs() < 0.01, "{got} vs {want}");
        }
        assert!((margin(0.0, 0.0, Vector3::new(0.0, 0.0, 0.25)) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn side_and_fore_slopes_reduce_the_margin_linearly() {
        // T5: lateral, S = 1 − φ/50.19°; T6: longitudinal, S = 1 − θ/57.99°.
        let cg = Vector3::new(0.0, 0.0, 0.25);
        for (phi, want) in [(10.0, 0.801), (20.0, 0.602), (30.0, 0.402), (40.0, 0.203)] {
            assert!((margin(phi, 0.0, cg) - want).abs() < 1e-3, "roll {phi}: {}", margin(phi, 0.0, cg));
        }
        for (theta, want) in [(20.0, 0.655), (30.0, 0.483), (40.0, 0.310)] {
            assert!((margin(0.0, theta, cg) - want).abs() < 1e-3, "pitch {theta}: {}", margin(0.0, theta, cg));
        }
        assert!(margin(55.0, 0.0, cg) < 0.0, "past 50.19° the rover tips");
    }

    #[test]
    fn invariants_and_the_arm_cg_shift() {
        let cg = Vector3::new(0.0, 0.0, 0.25);
        let g = gravity_tilted(12.0, -7.0);
        let base = force_angle(&contacts(), cg, g, Vector3::zeros()).unwrap().critical().unwrap().1;
        // Reordering the contacts, scaling m·g, and a yaw plus translation change nothing.
        let mut shuffled = contacts();
        shuffled.rotate_left(3);
        assert!((force_angle(&shuffled, cg, g, Vector3::zeros()).unwrap().critical().unwrap().1 - base).abs() < 1e-12);
        assert!(
            (force_angle(&contacts(), cg, g * 3.7, Vector3::zeros()).unwrap().critical().unwrap().1 - base).abs()
                < 1e-12
        );
        let yaw = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), 0.7);
        let shift = Vector3::new(5.0, -2.0, 1.0);
        let moved: Vec<_> = contacts().iter().map(|p| yaw * p + shift).collect();
        let moved_g = yaw * g;
        let m = force_angle(&moved, yaw * cg + shift, moved_g, Vector3::zeros()).unwrap().critical().unwrap().1;
        assert!((m - base).abs() < 1e-12);
        // T8: extending the arm moves the CG forward by 0.069 m: the rear axis' flat
        // angle grows from 57.99° to 61.94°, the front one shrinks to 52.94°.
        let fa = force_angle(&contacts(), Vector3::new(0.069, 0.0, 0.25), gravity_tilted(0.0, 0.0), Vector3::zeros())
            .unwrap();
        let mut deg: Vec<f64> = fa.angles().iter().map(|a| a.to_degrees()).collect();
        deg.sort_by(f64::total_cmp);
        assert!((deg[2] - 52.94).abs() < 0.02 && (deg[3] - 61.94).abs() < 0.02, "{deg:?}");
    }

    #[test]
    fn global_and_per_axis_readings_differ_as_documented() {
        let cg = Vector3::new(0.0, 0.0, 0.25);
        let flat = force_angle(&contacts(), cg, gravity_tilted(0.0, 0.0), Vector3::zeros()).unwrap();
        // A 30° fore slope: per axis 1 − 30/57.99 = 0.483; global 27.99°/50.19° = 0.558.
        let now = force_angle(&contacts(), cg, gravity_tilted(0.0, 30.0), Vector3::zeros()).unwrap();
        assert!((normalised_margin(&now, &flat, Normalisation::PerAxis).unwrap() - 0.483).abs() < 1e-3);
        assert!((normalised_margin(&now, &flat, Normalisation::Global).unwrap() - 27.99 / 50.19).abs() < 1e-3);
    }
}
