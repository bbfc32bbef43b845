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
