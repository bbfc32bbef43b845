//! The map layers a TEMPEST run writes for a GIS to put its route over: the planner's
//! DEM, its slope and the true terrain's direct sun at the job's `shadow_utc`, each a
//! GeoTIFF on the DEM's grid and CRS (the body named, metres).

use std::path::{Path, PathBuf};

use areo_mission::World;
use areo_terrain::geotiff;

use crate::error::Result;
use crate::output::write_with;

/// Shadow layer values: in direct sun, in shadow (terrain or the Sun below the
/// horizon), no data.
const LIT: u8 = 1;
const SHADOWED: u8 = 0;
const NO_DATA: u8 = 255;

/// Writes `dem.tif` (elevation, m), `slope.tif` (degrees) from the planner's map and
/// `shadow.tif` (1 direct sun, 0 shadowed or facing away, 255 no data) from the true
/// terrain at `shadow_s` after the epoch; returns the files.
pub(super) fn write(dir: &Path, map: &World, truth: &World, shadow_s: f64) -> Result<Vec<PathBuf>> {
    let dem = map.dem();
    let dem_path = dir.join("dem.tif");
    write_with(&dem_path, |tmp| Ok(geotiff::write(dem, tmp)?))?;
    let slope: Vec<f32> = (0..map.cells() as u32)
        .zip(dem.valid_mask())
        .map(|(c, ok)| if *ok { map.slope_deg(c) as f32 } else { f32::NAN })
        .collect();
    let slope_path = dir.join("slope.tif");
    let slope_dem = dem.with_values(slope)?;
    write_with(&slope_path, |tmp| Ok(geotiff::write(&slope_dem, tmp)?))?;
    let sun = truth.sun(shadow_s.clamp(0.0, truth.span_s()));
    let shadow: Vec<u8> = (0..truth.cells() as u32)
        .zip(truth.dem().valid_mask())
        // Direct sun on the ground, as `areo terrain shadow` writes it: neither in a cast
        // shadow nor on a slope facing away from the Sun.
        .map(|(c, ok)| match (*ok, truth.lit(c, &sun) && truth.sun_above_ground_deg(c, &sun) > 0.0) {
            (false, _) => NO_DATA,
            (true, true) => LIT,
            (true, false) => SHADOWED,
        })
        .collect();
    let shadow_path = dir.join("shadow.tif");
    write_with(&shadow_path, |tmp| Ok(geotiff::write_u8(truth.dem(), &shadow, Some(NO_DATA), tmp)?))?;
    Ok(vec![dem_path, slope_path, shadow_path])
}
