//! `shadows/`: the true terrain's direct sun through the run, as Cloud-Optimized
//! GeoTIFFs a map server's time dimension can serve, with `shadows/index.json` listing
//! each file's UTC: the report's [`ShadowSeries`](crate::report::tempest::ShadowSeries)
//! — instants of the Sun table, at most 240, on the whole map at most 1024 pixels a
//! side — 1 direct sun, 0 not, 255 no data; each file's instant also its TIFF DateTime;
//! and the same series as a STAC catalogue (`stac`).

use std::path::{Path, PathBuf};

use base64::Engine;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::output::{bands, json_for, write_file, write_with};
use crate::report::tempest::MapLayers;
use areo_terrain::geotiff;

/// The no-data value, as `direct_sun.tif`'s.
const NO_DATA: u8 = 255;

/// One file of the series.
#[derive(Serialize)]
struct Entry {
    utc: String,
    unix_s: f64,
    file: String,
}

/// Writes `dir/shadows/` and its index; returns the files.
pub(super) fn write(dir: &Path, layers: &MapLayers) -> Result<Vec<PathBuf>> {
    let folder = dir.join("shadows");
    std::fs::create_dir_all(&folder).map_err(|source| Error::Io { path: folder.clone(), source })?;
    let (map, series) = (&layers.shadow_grid, &layers.shadow_series);
    let k = series.cells_per_pixel as f64;
    let grid = geotiff::Grid {
        cols: series.cols,
        rows: series.rows,
        dx: map.dx * k,
        dy: map.dy * k,
        x0: map.x0,
        y_top: map.y_top,
        georef: map.georef,
    };
    let n = grid.cols * grid.rows;
    let bits = |text: &str| {
        base64::engine::general_purpose::STANDARD
            .decode(text)
            .map_err(|e| Error::Io { path: folder.clone(), source: std::io::Error::other(e) })
    };
    let valid = bits(&series.valid)?;
    let mut files = Vec::new();
    let mut index = Vec::new();
    for (i, (frame, &unix_s)) in series.frames.iter().zip(&series.unix_s).enumerate() {
        let lit = bits(frame)?;
        let values: Vec<u8> = (0..n)
            .map(|p| match ((valid[p / 8] >> (p % 8)) & 1, (lit[p / 8] >> (p % 8)) & 1) {
                (0, _) => NO_DATA,
                (_, v) => v,
            })
            .collect();
        let name = format!("direct_sun_{i:03}.tif");
        let path = folder.join(&name);
        let utc = series.utc.get(i).cloned().unwrap_or_default();
        write_with(&path, |tmp| {
            Ok(geotiff::write_cog_u8_at(&grid, &values, Some(NO_DATA), (&utc, &bands::DIRECT_SUN), tmp)?)
        })?;
        files.push(path);
        index.push(Entry { utc, unix_s, file: name });
    }
    let path = folder.join("index.json");
    write_file(&path, json_for(&path, &index, true)?.as_bytes())?;
    files.push(path);
    let frames: Vec<(String, String)> = index.into_iter().map(|e| (e.utc, e.file)).collect();
    files.extend(super::stac::write(&folder, &grid, series, &frames)?);
    Ok(files)
}
