//! Shaded relief: a DEM as a picture lit from a Sun direction, with cells in cast
//! shadow darkened, as RGB bytes for any image writer.

use crate::Dem;
use crate::slope::SlopeAspect;

/// Grey hillshade lit from (`azimuth_deg`, `elevation_deg`) — the usual
/// cos z·cos s + sin z·sin s·cos(az − aspect) — with cells in cast shadow darkened
/// and missing cells magenta, as RGB bytes row by row.
pub fn hillshade_rgb(
    dem: &Dem,
    slope: &SlopeAspect,
    shadowed: Option<&[bool]>,
    azimuth_deg: f64,
    elevation_deg: f64,
) -> Vec<u8> {
    let zen = (90.0 - elevation_deg.max(1.0)).to_radians();
    let az = azimuth_deg.to_radians();
    let mut rgb = Vec::with_capacity(dem.cols() * dem.rows() * 3);
    for i in 0..dem.cols() * dem.rows() {
        if !dem.valid_mask()[i] {
            rgb.extend_from_slice(&[255, 0, 255]);
            continue;
        }
        let s = f64::from(slope.slope_deg[i]).to_radians();
        let asp = f64::from(slope.aspect_deg[i]);
        let asp = if asp.is_nan() { 0.0 } else { asp.to_radians() };
        let mut v = zen.cos() * s.cos() + zen.sin() * s.sin() * (az - asp).cos();
        v = v.clamp(0.0, 1.0);
        let g = if shadowed.is_some_and(|sh| sh[i]) { 25.0 + 50.0 * v } else { 60.0 + 195.0 * v };
        let g = g as u8;
        // A faint warm tint for sunlit ground, cool for shadow.
        if shadowed.is_some_and(|sh| sh[i]) {
            rgb.extend_from_slice(&[g, g, g.saturating_add(25)]);
        } else {
            rgb.extend_from_slice(&[g.saturating_add(10), g, g.saturating_sub(10)]);
        }
    }
    rgb
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::slope::slope_aspect;

    #[test]
    fn flat_ground_under_a_45_degree_sun_is_lit_at_cos_45() {
        let mut z = vec![0.0_f32; 9];
        z[8] = f32::NAN;
        let dem = Dem::new(3, 3, 1.0, 1.0, 0.0, 3.0, z).unwrap();
        let sa = slope_aspect(&dem);
        let mut shadowed = vec![false; 9];
        shadowed[2] = true;
        let rgb = hillshade_rgb(&dem, &sa, Some(&shadowed), 135.0, 45.0);
        // cos 45° = 0.7071: lit grey 60 + 195·0.7071 = 197, shadowed 25 + 50·0.7071 = 60.
        assert_eq!(&rgb[0..3], &[207, 197, 187]);
        assert_eq!(&rgb[6..9], &[60, 60, 85]);
        assert_eq!(&rgb[24..27], &[255, 0, 255], "missing cells are magenta");
    }
}
