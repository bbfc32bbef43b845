//! A raster laid over the map — a no-go mask, a terrain-class map: read from a GeoTIFF
//! or an ESRI ASCII grid, checked to be on the map's CRS and to overlap it, and sampled
//! at each map cell's centre by nearest neighbour (the raster cell under it).
//!
//! A raster with a CRS must be on the map's, in its projected metres. One without (an
//! ESRI ASCII grid) is in the scenario's metres — east and north of the map's
//! south-west corner, as `start` and `goals` are — unless the map has no CRS either,
//! when the two share the map file's numbers.

use super::*;

/// What a raster holds under one map cell's centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Sample {
    /// The raster does not reach the cell.
    Outside,
    /// A raster cell with no value (NaN or its no-data).
    NoData,
    /// Its value.
    Value(f64),
}

/// The raster `name` (relative to the scenario file) under every cell of `world`'s map,
/// cell by cell; `field` names the scenario field in errors.
pub(super) fn sample(name: &str, field: &str, file: &ScenarioFile, world: &World, frame: Frame) -> Result<Vec<Sample>> {
    let base = file.path.parent().unwrap_or(Path::new("."));
    // Read as values, not heights: a mask's 4e9 or a class id's fraction as written.
    let values =
        areo_terrain::read_values(&base.join(name)).map_err(|e| Error::from(e).referenced_by(&file.path, field))?;
    let raster = &values.grid;
    let bad = |message: String| scenario_error(file, field.to_string(), message);
    let dem = world.dem();
    let (m, d) = (raster.georef(), dem.georef());
    let local = areo_terrain::Projection::Local;
    if m.projection != local && (m.projection != d.projection || m.surface != d.surface) {
        return Err(bad(format!(
            "{name}: the raster's CRS ({}) is not the map's ({}): reproject it onto the map (gdalwarp -t_srs)",
            describe(m),
            describe(d)
        )));
    }
    let in_frame = m.projection == local && d.projection != local;
    let to_raster = |p: (f64, f64)| if in_frame { frame.to_local(p) } else { p };
    let re = raster.extent();
    let ((dx0, dy0), (dx1, dy1)) =
        (to_raster((dem.extent().x_min, dem.extent().y_min)), to_raster((dem.extent().x_max, dem.extent().y_max)));
    if re.x_max <= dx0 || re.x_min >= dx1 || re.y_max <= dy0 || re.y_min >= dy1 {
        return Err(bad(format!(
            "{name}: the raster (x {:.0}..{:.0} m, y {:.0}..{:.0} m) does not overlap the map (x {dx0:.0}..{dx1:.0} m, y {dy0:.0}..{dy1:.0} m{})",
            re.x_min,
            re.x_max,
            re.y_min,
            re.y_max,
            if in_frame {
                ", east and north of its south-west corner: a raster without a CRS is in the scenario's metres"
            } else {
                ""
            }
        )));
    }
    Ok((0..world.cells() as u32)
        .map(|cell| {
            let (x, y) = to_raster(world.center(cell));
            let col = ((x - raster.x0()) / raster.dx()).floor();
            let row = ((raster.y_top() - y) / raster.dy()).floor();
            if col < 0.0 || row < 0.0 || col >= raster.cols() as f64 || row >= raster.rows() as f64 {
                return Sample::Outside;
            }
            values.at(col as usize, row as usize).map_or(Sample::NoData, Sample::Value)
        })
        .collect())
}

/// A georeference in words, for an error.
fn describe(g: &areo_terrain::Georef) -> String {
    format!("{:?} on a sphere of {} m", g.projection, g.surface.equatorial_radius_m)
}
