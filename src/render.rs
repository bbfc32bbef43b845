//! Pictures of terrain: a hillshade with cast shadows, as PNG (pure Rust, no system
//! library or font).

use std::path::Path;

use areo_terrain::Dem;
use areo_terrain::slope::SlopeAspect;

use crate::error::{Error, Result};

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

/// Encodes RGB bytes (`width` × `height`) as PNG into `out`.
pub fn encode_png(out: &mut Vec<u8>, width: usize, height: usize, rgb: &[u8]) -> std::result::Result<(), String> {
    let mut enc = png::Encoder::new(out, width as u32, height as u32);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().map_err(|e| e.to_string())?;
    w.write_image_data(rgb).map_err(|e| e.to_string())?;
    w.finish().map_err(|e| e.to_string())
}

/// Writes RGB bytes (`width` × `height`) as a PNG.
pub fn write_png(path: &Path, width: usize, height: usize, rgb: &[u8]) -> Result<()> {
    let mut bytes = Vec::new();
    encode_png(&mut bytes, width, height, rgb)
        .map_err(|m| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(m) })?;
    std::fs::write(path, bytes).map_err(|source| Error::Io { path: path.to_path_buf(), source })
}
