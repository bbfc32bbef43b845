//! Cast shadows from a source at infinity (the Sun), by one sweep along the source's
//! azimuth: O(cells) per map, not a ray per cell; and shadow maps (cast shadow plus
//! slopes facing away).
//!
//! [`cast_shadows`] sweeps the DEM's triangulated surface (see [`crate::tin`]). It is
//! not exact everywhere: against each cell's own ray on the same surface (brute force,
//! [`crate::tin::horizon_on_triangles`]; `tests/horizon_error.rs`) on the real
//! 897 × 897 Gale MOLA map, 0 cells differ at 270°/5° and 90°/10° (cardinal
//! azimuths), 0.007 % at 315°/15° and 0.004 % at 135°/20° (diagonals), 0.028 % at
//! 200°/8° and 0.113 % at 250°/2°; on synthesised craters and hills (30 m cells, every
//! 15° of azimuth) 0 at cardinal azimuths, at most 0.100 % at a Sun 5° or 15° up and
//! 0.142 % at 2°. A [`ShadowMap`] also darkens cells whose own slope
//! faces away from the Sun (`facing_away`, from the Horn normal): at a low Sun these are
//! many more than the cast-shadow disagreements, and are not cast shadows.
//! [`cast_shadows_fast`], described here, is about 1.4× faster and approximate:
//! the grid is walked line by line away from the source, the lines being columns or
//! rows, whichever the source direction crosses faster. For each cell, the ray toward
//! the source crosses the previous (sun-ward) line at a fractional position; there the
//! terrain, and the shadow envelope (the highest shadow ray passing over that point),
//! are interpolated linearly between the two cells straddling the crossing. The
//! envelope then descends to the cell at tan(elevation) per metre. The elevation is the
//! source's elevation above each cell's own horizontal, and with planetary curvature an
//! occluder at distance d sits d²/2R lower as seen from the cell, so over a step of L
//! metres an envelope that left its occluder D metres back sinks a further
//! ((D + L)² − D²)/2R. A cell is in cast shadow when the envelope passes above it.
//! Terrain beyond the DEM's edge never shadows, so the sun-side border is lit.
//!
//! Interpolating the envelope between neighbouring rays approximates each cell's own
//! ray; disagreements with an exact per-cell ray cast are confined to grazing
//! incidence (the tests count them).

use crate::dem::Dem;
use crate::lines::{LineGeometry, Lines};
use crate::slope::horn_gradient;

/// Whether shadows account for the surface curving away.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Curvature {
    /// A flat world.
    Flat,
    /// A sphere of this radius, m.
    Sphere {
        /// Radius, m.
        radius_m: f64,
    },
}

impl Curvature {
    /// The curvature of the DEM's reference body (its mean radius).
    pub fn of(dem: &Dem) -> Curvature {
        Curvature::Sphere { radius_m: dem.georef().body.mean_radius_m() }
    }

    /// 1/2R (0 for a flat world): an occluder at distance d sits d²·(1/2R) lower.
    pub(crate) fn inv_2r(self) -> f64 {
        match self {
            Curvature::Flat => 0.0,
            Curvature::Sphere { radius_m } => 0.5 / radius_m,
        }
    }
}

/// The lighting of every cell for one source direction.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadowMap {
    /// Cast shadow: terrain between the cell and the source.
    pub cast: Vec<bool>,
    /// The cell's own slope faces away (incidence on the Horn normal ≥ 90°).
    pub facing_away: Vec<bool>,
    /// Cells with data.
    pub valid: Vec<bool>,
}

impl ShadowMap {
    /// Direct sun on cell `i`: valid, not cast-shadowed and not facing away.
    pub fn direct_sun(&self, i: usize) -> bool {
        self.valid[i] && !self.cast[i] && !self.facing_away[i]
    }

    /// Fraction of valid cells in direct sun.
    pub fn lit_fraction(&self) -> f64 {
        let valid = self.valid.iter().filter(|v| **v).count();
        let lit = (0..self.cast.len()).filter(|&i| self.direct_sun(i)).count();
        lit as f64 / valid.max(1) as f64
    }

    /// As bytes: 1 in direct sun, 0 shadowed, 255 no data.
    pub fn to_u8(&self) -> Vec<u8> {
        (0..self.cast.len()).map(|i| if !self.valid[i] { 255 } else { u8::from(self.direct_sun(i)) }).collect()
    }
}

/// The shadow map for a source at `azimuth_deg` (clockwise from north) and
/// `elevation_deg` above the local horizontal.
pub fn shadow_map(dem: &Dem, azimuth_deg: f64, elevation_deg: f64, curvature: Curvature) -> ShadowMap {
    shadow_map_from(dem, azimuth_deg, elevation_deg, cast_shadows(dem, azimuth_deg, elevation_deg, curvature))
}

/// [`shadow_map`] around a cast-shadow map from either sweep ([`cast_shadows`] or
/// [`crate::tin::cast_shadows_exact`]) for the same source direction.
pub fn shadow_map_from(dem: &Dem, azimuth_deg: f64, elevation_deg: f64, cast: Vec<bool>) -> ShadowMap {
    let valid = dem.valid_mask().to_vec();
    let (gx, gy) = horn_gradient(dem);
    let (sa, ca) = azimuth_deg.to_radians().sin_cos();
    let (se, ce) = elevation_deg.to_radians().sin_cos();
    let sun = [ce * sa, ce * ca, se];
    let facing_away = gx
        .iter()
        .zip(&gy)
        .map(|(&x, &y)| {
            let n = crate::dem::unit_normal(f64::from(x), f64::from(y));
            !(n[0] * sun[0] + n[1] * sun[1] + n[2] * sun[2] > 0.0)
        })
        .collect();
    ShadowMap { cast, facing_away, valid }
}

/// Samples per cell along each line (cells plus interpolated points between them).
const SUB: usize = 2;

/// Cast shadow only (true = shadowed) for a source at `azimuth_deg` (clockwise from
/// north) and `elevation_deg`, swept on the DEM's triangulated surface
/// ([`crate::tin::cast_shadows_exact`]); its disagreement with each cell's own ray is
/// in the module docs.
pub fn cast_shadows(dem: &Dem, azimuth_deg: f64, elevation_deg: f64, curvature: Curvature) -> Vec<bool> {
    crate::tin::cast_shadows_exact(dem, azimuth_deg, elevation_deg, curvature)
}

/// Cast shadow only (true = shadowed), by the fast sweep of the module's description:
/// terrain sampled where rays cross one family of grid lines, each ray's envelope
/// interpolated from its neighbours line after line. Agrees with [`cast_shadows`]
/// but where the Sun grazes the terrain (98.9–100 % of cells in the tests).
pub fn cast_shadows_fast(dem: &Dem, azimuth_deg: f64, elevation_deg: f64, curvature: Curvature) -> Vec<bool> {
    let (cols, rows) = (dem.cols(), dem.rows());
    if elevation_deg <= 0.0 {
        // Below the local horizontal the source is behind the surface everywhere.
        return vec![true; cols * rows];
    }
    // Line geometry: a line is a column or a row; `step` is the metres travelled toward
    // the source from one line to the next, `shift` the fractional offset of the
    // crossing along the line.
    let LineGeometry { along_cols, n_lines, n_cells, step_m, shift, toward_higher_line } =
        LineGeometry::toward(dem, azimuth_deg);
    // Lines are read and written through blocks (columns would otherwise touch a page
    // per cell); heights arrive as NaN where missing.
    let mut lines = Lines::new(dem, along_cols);
    let mut heights = vec![0f64; n_cells];
    let mut marks = vec![false; n_cells];
    let tan_e = elevation_deg.to_radians().tan();
    let inv_2r = curvature.inv_2r();
    let mut shadow = vec![false; cols * rows];
    // Envelope of the previous line: ray height above the reference surface and the
    // distance back to the ray's source.
    // Each line is sampled at its cells and at SUB − 1 points between each pair
    // (terrain interpolated): interpolating the envelope over short gaps keeps it close
    // to each cell's own ray. Agreement with per-cell ray casts at a Sun 8° up: 98.8 %
    // with SUB = 1, 99.7 % with 2 (~95 M cells/s), 99.8 % with 3 (~60 M), 99.85 % with
    // 4 (~45 M); the disagreements are all within 1° of grazing.
    let nv = SUB * (n_cells - 1) + 1;
    let shift = SUB as f64 * shift;
    let mut prev_h = vec![f64::NEG_INFINITY; nv];
    let mut prev_d = vec![0f64; nv];
    let mut cur_h = vec![0f64; nv];
    let mut cur_d = vec![0f64; nv];
    // Lines nearest the source first.
    let order: Box<dyn Iterator<Item = usize>> =
        if toward_higher_line { Box::new((0..n_lines).rev()) } else { Box::new(0..n_lines) };
    // Directions a hair off an axis would otherwise straddle two cells with a weight of
    // 1e-16 and lose the border cell's neighbour.
    let shift = if (shift - shift.round()).abs() < 1e-9 { shift.round() } else { shift };
    let base = shift.floor();
    let frac = shift - base;
    let base = base as isize;
    let mut first = true;
    for line in order {
        lines.read(line, &mut heights);
        marks.fill(false);
        for k in 0..nv {
            let (cell, zc) = if k % SUB == 0 {
                let h = heights[k / SUB];
                (Some(k / SUB), if h.is_nan() { f64::NEG_INFINITY } else { h })
            } else {
                let (a, b) = (heights[k / SUB], heights[k / SUB + 1]);
                let t = (k % SUB) as f64 / SUB as f64;
                // NaN (a missing end) fails the comparison: no terrain there.
                let zc = if !a.is_nan() && !b.is_nan() { a * (1.0 - t) + b * t } else { f64::NEG_INFINITY };
                (None, zc)
            };
            // The envelope arriving from the sun-ward line.
            let (mut h_in, mut d_in) = (f64::NEG_INFINITY, 0.0);
            if !first {
                let k0 = k as isize + base;
                let k1 = k0 + 1;
                let get = |kk: isize| -> Option<(f64, f64)> {
                    (kk >= 0 && (kk as usize) < nv).then(|| (prev_h[kk as usize], prev_d[kk as usize]))
                };
                let (h, d) = match (get(k0), get(k1)) {
                    (Some((h0, d0)), Some((h1, d1))) => {
                        if frac == 0.0 {
                            (h0, d0)
                        } else if h0.is_finite() && h1.is_finite() {
                            (h0 + (h1 - h0) * frac, d0 + (d1 - d0) * frac)
                        } else if h0 > h1 {
                            (h0, d0)
                        } else {
                            (h1, d1)
                        }
                    }
                    (Some(a), None) if frac == 0.0 => a,
                    // The ray leaves the map: nothing beyond the edge shadows.
                    _ => (f64::NEG_INFINITY, 0.0),
                };
                if h.is_finite() {
                    h_in = h - step_m * tan_e - (2.0 * d * step_m + step_m * step_m) * inv_2r;
                    d_in = d + step_m;
                }
            }
            if zc >= h_in {
                cur_h[k] = zc;
                cur_d[k] = 0.0;
            } else {
                if let Some(c) = cell {
                    marks[c] = !heights[c].is_nan();
                }
                cur_h[k] = h_in;
                cur_d[k] = d_in;
            }
        }
        lines.write(line, &marks, &mut shadow);
        std::mem::swap(&mut prev_h, &mut cur_h);
        std::mem::swap(&mut prev_d, &mut cur_d);
        first = false;
    }
    lines.finish(&mut shadow);
    shadow
}

/// Reference of [`cast_shadows_fast`]: one ray per cell, marched toward the source across every grid line it
/// crosses, with the terrain interpolated linearly along the crossed line and the
/// same curvature drop. O(cells × length); for tests and validation.
pub fn cast_shadows_by_rays(dem: &Dem, azimuth_deg: f64, elevation_deg: f64, curvature: Curvature) -> Vec<bool> {
    if elevation_deg <= 0.0 {
        return vec![true; dem.cols() * dem.rows()];
    }
    horizon_by_rays(dem, azimuth_deg, curvature).into_iter().map(|h| h > elevation_deg).collect()
}

/// Per cell, the elevation angle (degrees) of the highest terrain seen toward
/// `azimuth_deg` along the cell's own ray (−90 where nothing rises, NaN on missing
/// cells): a cell is in cast shadow from a source at that azimuth exactly when the
/// source's elevation is below this angle. The brute-force reference of the sweep.
pub fn horizon_by_rays(dem: &Dem, azimuth_deg: f64, curvature: Curvature) -> Vec<f64> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_vertical_wall_casts_a_shadow_h_over_tan_e_long() {
        // A 20 m wall along x = 50 on flat ground; Sun in the east at 30°.
        let (h, e) = (20.0, 30.0f64);
        let dem = Dem::from_fn(200, 20, 1.0, 1.0, |x, _| if (50.0..51.0).contains(&x) { h } else { 0.0 }).unwrap();
        let s = cast_shadows_fast(&dem, 270.0, e, Curvature::Flat);
        let row = 10;
        let len = (51..200).take_while(|&c| s[row * 200 + c]).count() as f64;
        let expect = h / e.to_radians().tan();
        assert!((len - expect).abs() <= 1.0, "shadow {len} m, expected {expect:.1} m");
        // Nothing on the sun side.
        assert!((0..50).all(|c| !s[row * 200 + c]));
    }

    #[test]
    #[allow(clippy::print_stderr)] // the agreement figures are the point of the test
    fn sweep_agrees_with_per_cell_rays_on_rough_terrain() {
        let dem = crate::synth::rough_test_terrain(120, 90, 7, 40.0, 4);
        for (az, el) in [(90.0, 20.0), (135.0, 10.0), (200.0, 35.0), (300.0, 8.0), (10.0, 15.0), (45.0, 3.0)] {
            let sweep = cast_shadows_fast(&dem, az, el, Curvature::Flat);
            let horizon = horizon_by_rays(&dem, az, Curvature::Flat);
            let (mut differ, mut not_grazing) = (0, 0);
            for (s, h) in sweep.iter().zip(&horizon) {
                if *s != (*h > el) {
                    differ += 1;
                    // Grazing: the terrain's horizon is within a degree of the Sun.
                    if (h - el).abs() > 1.0 {
                        not_grazing += 1;
                    }
                }
            }
            let agree = 1.0 - differ as f64 / sweep.len() as f64;
            eprintln!(
                "az {az:5.1} el {el:4.1}: {differ} of {} cells differ ({:.3} % agree), {not_grazing} not grazing",
                sweep.len(),
                100.0 * agree
            );
            assert!(agree >= 0.995, "az {az} el {el}: only {:.2} % agree", 100.0 * agree);
            assert!(
                not_grazing as f64 <= 0.001 * sweep.len() as f64,
                "az {az} el {el}: {not_grazing} disagreements away from grazing"
            );
        }
    }

    #[test]
    fn a_distant_peak_below_the_curved_horizon_casts_no_shadow() {
        // A 1000 m peak 100 km west of a 0 m plain, Sun in the west at 0.3°: on a flat
        // world the peak's shadow reaches 1000/tan(0.3°) ≈ 191 km; on Mars the surface
        // drops d²/2R ≈ 1.47 km at 100 km, hiding the peak.
        let dem = Dem::from_fn(1101, 3, 100.0, 100.0, |x, _| if x < 100.0 { 1000.0 } else { 0.0 }).unwrap();
        let target = 2 * 1101 + 1000; // 100 km east of the peak, middle row... row 2
        let flat = cast_shadows_fast(&dem, 270.0, 0.3, Curvature::Flat);
        let curved = cast_shadows_fast(&dem, 270.0, 0.3, Curvature::Sphere { radius_m: 3_389_500.0 });
        assert!(flat[target], "flat world: in the peak's shadow");
        assert!(!curved[target], "curved world: the peak is below the horizon");
        let reference = cast_shadows_by_rays(&dem, 270.0, 0.3, Curvature::Sphere { radius_m: 3_389_500.0 });
        assert!(!reference[target]);
    }

    #[test]
    fn sun_side_border_is_lit_and_low_sun_faces() {
        let dem = Dem::from_fn(30, 30, 1.0, 1.0, |x, y| (x * 0.7).sin() * 5.0 + (y * 0.3).cos() * 5.0).unwrap();
        for s in [cast_shadows(&dem, 0.0, 5.0, Curvature::Flat), cast_shadows_fast(&dem, 0.0, 5.0, Curvature::Flat)] {
            assert!((0..30).all(|c| !s[c]), "the northern border faces a northern Sun unobstructed");
        }
        let m = shadow_map(&dem, 0.0, -1.0, Curvature::Flat);
        assert_eq!(m.lit_fraction(), 0.0);
    }
}
