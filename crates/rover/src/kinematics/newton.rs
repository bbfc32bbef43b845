//! The cross-check: the full 3-D loop-closure chain solved by damped Newton steps,
//! independent of the planar decomposition's per-side split.

use areo_terrain::Ground;
use nalgebra::{SMatrix, SVector};

use super::{Anchor, Kinematics, Pose, WHEEL_SAMPLES};
use crate::params::{Layout, RoverParams};

/// The full 3-D solution of a damped Newton iteration, for cross-checking.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonPose {
    /// Rocker-pivot midpoint, map frame, m.
    pub body: [f64; 3],
    /// Body pitch, rad (nose up positive).
    pub pitch: f64,
    /// Body roll, rad (left up positive).
    pub roll: f64,
    /// Rocker angle relative to the body (left +ρ, right −ρ), rad.
    pub rocker: f64,
    /// Bogie angles relative to their rockers, left and right, rad (the bogie's forward
    /// end up positive).
    pub bogie: [f64; 2],
    /// Axle centres, left front, middle, rear, right front, middle, rear, map frame, m.
    pub axles: [[f64; 3]; 6],
    /// Largest |residual| at the solution, m.
    pub residual_m: f64,
    /// Iterations used.
    pub iterations: usize,
}

type Vec8 = SVector<f64, 8>;

/// Solves the full loop-closure system by damped Newton iterations from `start` (a
/// planar-decomposition pose, or `None` for the nominal pose at the terrain height):
/// unknowns body position (3), pitch, roll, rocker angle and both bogie angles; each
/// wheel a disc in the body's x–z plane touching the terrain (its rim sampled as in the
/// planar solver, so the wheels' sideways shift with roll is exact), and the anchor at
/// (x, y). The Jacobian is by central differences. `None` if it does not converge to
/// 1e-8 m in 60 iterations.
pub fn newton_pose(
    ground: &impl Ground,
    params: &RoverParams,
    x: f64,
    y: f64,
    heading: f64,
    start: Option<&Pose>,
) -> Option<NewtonPose> {
    let k = Kinematics::new(params);
    let r = params.wheel_radius_m;
    let (b_x, b_z) = (params.rocker_pivot_m.x, params.rocker_pivot_m.z);
    let rel = |px: f64, pz: f64| (px - b_x, pz - b_z);
    let a = params.axle_x_m;
    let p0 = rel(params.bogie_pivot_m.x, params.bogie_pivot_m.z);
    let f0 = rel(a.front, r);
    let m0 = rel(a.middle, r);
    let r0 = rel(a.rear, r);
    let bogie_front = params.layout() == Layout::BogieFront;
    let (fx, fy) = (heading.sin(), heading.cos());
    let (lx, ly) = (-heading.cos(), heading.sin());
    let half = params.track_m / 2.0;
    let chain = Chain { p0, f0, m0, r0, bogie_front, half, fwd: (fx, fy), left: (lx, ly) };
    let axles_of = |q: &Vec8| chain.axles(q);
    // Each wheel is a disc in the body's x–z plane; its residual is the smallest gap
    // between the disc's lower rim and the terrain (0 = touching), sampled as in the
    // planar solver.
    let residual = |q: &Vec8| -> Option<Vec8> {
        let ax = axles_of(q);
        let (sp, cp) = q[3].sin_cos();
        let (sr, cr) = q[4].sin_cos();
        let fwd_b = [cp * fx, cp * fy, sp];
        let up_b = [-cr * sp * fx - sr * lx, -cr * sp * fy - sr * ly, cr * cp];
        let mut f = Vec8::zeros();
        for i in 0..6 {
            let a = ax[i];
            let mut gap = f64::INFINITY;
            for j in 0..=WHEEL_SAMPLES {
                let (u, rise) = (k.u[j], k.rise[j]);
                let p = [0, 1, 2].map(|c| a[c] + u * fwd_b[c] - rise * up_b[c]);
                gap = gap.min(p[2] - ground.height(p[0], p[1])?);
            }
            f[i] = gap;
        }
        // The anchor: the middle wheels' contact lines under the axles (axle moved
        // r·sin ψ sideways, as the tilted wheel plane does in the planar solver).
        let bottom = |a: [f64; 3]| (a[0] + r * sr * lx, a[1] + r * sr * ly);
        let (ml, mr) = (bottom(ax[1]), bottom(ax[4]));
        let (ax_x, ax_y) = match k.anchor {
            Anchor::MiddleMidpoint => (0.5 * (ml.0 + mr.0), 0.5 * (ml.1 + mr.1)),
            Anchor::MiddleRight => mr,
            Anchor::MiddleLeft => ml,
        };
        f[6] = ax_x - x;
        f[7] = ax_y - y;
        Some(f)
    };
    let q = match start {
        Some(p) => start_of(p),
        None => {
            let z = ground.height(x, y)?;
            Vec8::from_column_slice(&[x, y, z + b_z, 0.0, 0.0, 0.0, 0.0, 0.0])
        }
    };
    let (q, residual_m, iterations) = damped_newton(residual, q)?;
    Some(NewtonPose {
        body: [q[0], q[1], q[2]],
        pitch: q[3],
        roll: q[4],
        rocker: q[5],
        bogie: [q[6], q[7]],
        axles: axles_of(&q),
        residual_m,
        iterations,
    })
}

/// The rover's chain as built, relative to the rocker pivot (x, z in the body's plane,
/// m): bogie pivot and the three axles, which end carries the bogie, half the track,
/// and the heading's forward and left directions on the map.
struct Chain {
    p0: (f64, f64),
    f0: (f64, f64),
    m0: (f64, f64),
    r0: (f64, f64),
    bogie_front: bool,
    half: f64,
    fwd: (f64, f64),
    left: (f64, f64),
}

impl Chain {
    /// The six axles on the map (left front, middle, rear, then right) for the unknowns
    /// q = (xB, yB, zB, pitch, roll, ρ, β_L, β_R).
    fn axles(&self, q: &Vec8) -> [[f64; 3]; 6] {
        let (sp, cp) = q[3].sin_cos();
        let (sr, cr) = q[4].sin_cos();
        let mut out = [[0.0; 3]; 6];
        for (side, (y_s, a_s, beta)) in [(self.half, q[5], q[6]), (-self.half, -q[5], q[7])].into_iter().enumerate() {
            let piv = rot(self.p0, a_s);
            let bogie = |v: (f64, f64)| {
                let d = rot((v.0 - self.p0.0, v.1 - self.p0.1), a_s + beta);
                (piv.0 + d.0, piv.1 + d.1)
            };
            // The chain as built, in the rover's own frame (no mirror image here, so the
            // planar solver's handling of a bogie-behind rover is checked independently).
            let wheels = if self.bogie_front {
                [bogie(self.f0), bogie(self.m0), rot(self.r0, a_s)]
            } else {
                [rot(self.f0, a_s), bogie(self.m0), bogie(self.r0)]
            };
            for (i, v) in wheels.into_iter().enumerate() {
                // Body frame (v.0, y_s, v.1): roll about x, then pitch (nose up), then yaw.
                let (bx, by, bz) = (v.0, y_s * cr - v.1 * sr, y_s * sr + v.1 * cr);
                let (px, pz) = (bx * cp - bz * sp, bx * sp + bz * cp);
                out[3 * side + i] =
                    [q[0] + self.fwd.0 * px + self.left.0 * by, q[1] + self.fwd.1 * px + self.left.1 * by, q[2] + pz];
            }
        }
        out
    }
}

/// `v` turned by `ang` radians in its plane.
fn rot(v: (f64, f64), ang: f64) -> (f64, f64) {
    let (s, c) = ang.sin_cos();
    (v.0 * c - v.1 * s, v.0 * s + v.1 * c)
}

/// The unknowns of a planar-decomposition pose.
fn start_of(p: &Pose) -> Vec8 {
    Vec8::from_column_slice(&[
        p.body[0],
        p.body[1],
        p.body[2],
        p.pitch,
        p.roll,
        0.5 * (p.left.rocker_pitch - p.right.rocker_pitch),
        p.left.bogie_angle,
        p.right.bogie_angle,
    ])
}

/// Damped Newton iterations on `residual` from `q`, the Jacobian by central
/// differences, each step halved until the residual falls: the solution, its largest
/// residual and the iterations, or `None` if it does not converge to 1e-8 in 60.
fn damped_newton(residual: impl Fn(&Vec8) -> Option<Vec8>, mut q: Vec8) -> Option<(Vec8, f64, usize)> {
    let mut f = residual(&q)?;
    for it in 0..60 {
        let norm = f.amax();
        if norm < 1e-8 {
            return Some((q, norm, it));
        }
        let mut jac = SMatrix::<f64, 8, 8>::zeros();
        for j in 0..8 {
            let h = 1e-7;
            let (mut qp, mut qm) = (q, q);
            qp[j] += h;
            qm[j] -= h;
            let col = (residual(&qp)? - residual(&qm)?) / (2.0 * h);
            jac.set_column(j, &col);
        }
        let step = jac.lu().solve(&(-f))?;
        let mut lambda = 1.0;
        loop {
            let trial = q + step * lambda;
            if let Some(ft) = residual(&trial)
                && ft.norm() < f.norm()
            {
                q = trial;
                f = ft;
                break;
            }
            lambda *= 0.5;
            if lambda < 1e-6 {
                return None;
            }
        }
    }
    None
}
