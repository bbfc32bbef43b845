//! `shadows/`: the true terrain's direct sun through the run, as Cloud-Optimized
//! GeoTIFFs a map server's time dimension can serve, with `shadows/index.json` listing
//! each file's UTC. They are the plan viewer's frames (every ten minutes or more, at
//! most 240, on the viewer's image: the map around the route, at most 600 pixels a
//! side), georeferenced on that image's grid; 1 direct sun, 0 not, no no-data value;
//! each file's instant also its TIFF DateTime.

use std::path::{Path, PathBuf};

use base64::Engine;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::output::{json_for, write_file, write_with};
use crate::report::tempest::MapLayers;
use crate::report::view::ViewData;
use areo_terrain::geotiff;

/// One file of the series.
#[derive(Serialize)]
struct Entry {
    utc: String,
    unix_s: f64,
    file: String,
}

/// Writes `dir/shadows/` and its index; returns the files.
pub(super) fn write(dir: &Path, view: &ViewData, layers: &MapLayers) -> Result<Vec<PathBuf>> {
    let folder = dir.join("shadows");
    std::fs::create_dir_all(&folder).map_err(|source| Error::Io { path: folder.clone(), source })?;
    let map = &layers.shadow_grid;
    let k = view.cells_per_pixel as f64;
    let (c0, r0) = view.origin_cells;
    let grid = geotiff::Grid {
        cols: view.hillshade.cols,
        rows: view.hillshade.rows,
        dx: map.dx * k,
        dy: map.dy * k,
        x0: map.x0 + c0 as f64 * map.dx,
        y_top: map.y_top - r0 as f64 * map.dy,
        georef: map.georef,
    };
    let n = grid.cols * grid.rows;
    let mut files = Vec::new();
    let mut index = Vec::new();
    for (i, (frame, &unix_s)) in view.frames.iter().zip(&view.frame_unix_s).enumerate() {
        let bits = base64::engine::general_purpose::STANDARD
            .decode(frame)
            .map_err(|e| Error::Io { path: folder.clone(), source: std::io::Error::other(e) })?;
        let values: Vec<u8> = (0..n).map(|p| (bits[p / 8] >> (p % 8)) & 1).collect();
        let name = format!("direct_sun_{i:03}.tif");
        let path = folder.join(&name);
        let utc = view.frame_utc.get(i).cloned().unwrap_or_default();
        write_with(&path, |tmp| Ok(geotiff::write_cog_u8_at(&grid, &values, None, &utc, tmp)?))?;
        files.push(path);
        index.push(Entry { utc, unix_s, file: name });
    }
    let path = folder.join("index.json");
    write_file(&path, json_for(&path, &index, true)?.as_bytes())?;
    files.push(path);
    Ok(files)
}
