//! PNG pictures (pure Rust, no system library): RGB bytes to a file, written
//! atomically.

use std::path::Path;

use crate::error::{Error, Result};

/// Encodes RGB bytes (`width` × `height`) as PNG into `out`.
pub(crate) fn encode_png(
    out: &mut Vec<u8>,
    width: usize,
    height: usize,
    rgb: &[u8],
) -> std::result::Result<(), png::EncodingError> {
    let mut enc = png::Encoder::new(out, width as u32, height as u32);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header()?;
    w.write_image_data(rgb)?;
    w.finish()
}

/// Writes RGB bytes (`width` × `height`) as a PNG.
pub(crate) fn write_png(path: &Path, width: usize, height: usize, rgb: &[u8]) -> Result<()> {
    let mut bytes = Vec::new();
    encode_png(&mut bytes, width, height, rgb)
        .map_err(|m| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(m) })?;
    super::write_file(path, &bytes)
}

/// Writes a picture of `dem`'s grid (one pixel a cell, RGB bytes) as a PNG with its
/// ESRI world file beside it (`.pgw`: pixel size, rotations, and the centre of the
/// upper-left pixel, in the DEM's map metres), so GDAL and QGIS place it over the map.
/// Returns both paths.
pub(crate) fn write_map_png(path: &Path, dem: &areo_terrain::Dem, rgb: &[u8]) -> Result<Vec<std::path::PathBuf>> {
    write_grid_png(path, &areo_terrain::geotiff::Grid::of(dem), rgb)
}

/// [`write_map_png`] on a grid held without its DEM.
pub(crate) fn write_grid_png(
    path: &Path,
    grid: &areo_terrain::geotiff::Grid,
    rgb: &[u8],
) -> Result<Vec<std::path::PathBuf>> {
    write_png(path, grid.cols, grid.rows, rgb)?;
    let pgw = path.with_extension("pgw");
    super::write_file(&pgw, world_file(grid).as_bytes())?;
    Ok(vec![path.to_path_buf(), pgw])
}

/// The six lines of a world file for `dem`'s grid (north up, no rotation).
fn world_file(grid: &areo_terrain::geotiff::Grid) -> String {
    let (dx, dy) = (grid.dx, grid.dy);
    format!("{dx}\n0\n0\n{}\n{}\n{}\n", -dy, grid.x0 + dx / 2.0, grid.y_top - dy / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn world_file_puts_the_first_pixel_centre_half_a_cell_in() {
        let dem = areo_terrain::Dem::new(3, 2, 20.0, 25.0, 1000.0, 500.0, vec![0.0; 6]).unwrap();
        assert_eq!(world_file(&areo_terrain::geotiff::Grid::of(&dem)), "20\n0\n0\n-25\n1010\n487.5\n");
    }
}
