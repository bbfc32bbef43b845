//! The map layers a TEMPEST run puts under its route for a GIS: the planner's DEM, its
//! slope and the true terrain's direct sun at the job's `shadow_utc`, on their grids
//! (written as GeoTIFFs from the report by `output::reports`).

use areo_mission::World;
use areo_terrain::geotiff::Grid;

use crate::report::Raster;
use crate::report::tempest::MapLayers;

/// Shadow layer values: in direct sun, in shadow (terrain or the Sun below the
/// horizon), no data.
const LIT: u8 = 1;
const SHADOWED: u8 = 0;
const NO_DATA: u8 = 255;

/// The planner's elevation and slope as it holds them (`sensed`: after a simulated run,
/// with the cells the rover sensed), and the true terrain's direct sun at `shadow_s`
/// after the epoch.
pub(super) fn layers(map: &World, truth: &World, shadow_s: f64, sensed: bool) -> MapLayers {
    let dem = map.dem();
    let (cols, rows) = (dem.cols(), dem.rows());
    let valid = dem.valid_mask();
    // The world's own elevations, as its slopes are: sensing replaces both.
    let elevation = (0..map.cells() as u32)
        .zip(valid)
        .map(|(c, ok)| if *ok { map.elevation(c).unwrap_or(f64::NAN) as f32 } else { f32::NAN })
        .collect();
    let slope = (0..map.cells() as u32)
        .zip(valid)
        .map(|(c, ok)| if *ok { map.slope_deg(c) as f32 } else { f32::NAN })
        .collect();
    let sun = truth.sun(shadow_s.clamp(0.0, truth.span_s()));
    let shadow = (0..truth.cells() as u32)
        .zip(truth.dem().valid_mask())
        // Direct sun on the ground, as `areo terrain shadow` writes it: neither in a cast
        // shadow nor on a slope facing away from the Sun.
        .map(|(c, ok)| match (*ok, truth.lit(c, &sun) && truth.sun_above_ground_deg(c, &sun) > 0.0) {
            (false, _) => NO_DATA,
            (true, true) => LIT,
            (true, false) => SHADOWED,
        })
        .collect();
    let truth_dem = truth.dem();
    MapLayers {
        map: if sensed { "as sensed" } else { "as planned" }.to_string(),
        grid: Grid::of(dem),
        elevation_m: Raster { cols, rows, values: elevation },
        slope_deg: Raster { cols, rows, values: slope },
        shadow_grid: Grid::of(truth_dem),
        direct_sun: Raster { cols: truth_dem.cols(), rows: truth_dem.rows(), values: shadow },
    }
}
