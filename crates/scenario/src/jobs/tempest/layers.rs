//! The map layers a TEMPEST run puts under its route for a GIS: the planner's DEM, its
//! slope, the true terrain's direct sun at the job's `shadow_utc`, on their grids, and
//! its direct sun through the run at instants of the Sun table (written as GeoTIFFs
//! from the report by `output::reports`).

use areo_ephemeris::format_utc;
use areo_mission::World;
use areo_terrain::geotiff::Grid;
use base64::Engine;
use hifitime::Duration;
use rayon::prelude::*;

use crate::report::Raster;
use crate::report::tempest::{MapLayers, SERIES_FRAMES, SERIES_PIXELS, ShadowSeries};

/// Shadow layer values: in direct sun, in shadow (terrain or the Sun below the
/// horizon), no data.
const LIT: u8 = 1;
const SHADOWED: u8 = 0;
const NO_DATA: u8 = 255;

/// The planner's elevation and slope as it holds them (`sensed`: after a simulated run,
/// with the cells the rover sensed), the true terrain's direct sun at `shadow_s` after
/// the epoch, and its direct sun through `run_s` (s after the epoch, first and last).
pub(super) fn layers(map: &World, truth: &World, shadow_s: f64, sensed: bool, run_s: (f64, f64)) -> MapLayers {
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
    let shadow_s = shadow_s.clamp(0.0, truth.span_s());
    let sun = truth.sun(shadow_s);
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
        direct_sun_utc: format_utc(truth.epoch() + Duration::from_seconds(shadow_s)),
        shadow_series: series(truth, run_s),
        no_go: None,
        classes: None,
    }
}

/// The true terrain's direct sun at the Sun table's instants from the last at or before
/// `t0` to the first at or after `t1` (s after the epoch), every so many steps that at
/// most [`SERIES_FRAMES`] span them.
fn series(truth: &World, (t0, t1): (f64, f64)) -> ShadowSeries {
    let (cols, rows) = (truth.cols(), truth.rows());
    let k = cols.max(rows).div_ceil(SERIES_PIXELS).max(1);
    let (w, h) = (cols.div_ceil(k), rows.div_ceil(k));
    let cells: Vec<u32> = (0..h).flat_map(|y| (0..w).map(move |x| truth.cell(x * k, y * k))).collect();
    let step = truth.sun_step_s();
    let (first, last) = ((t0 / step).floor().max(0.0) as usize, ((t1 / step).ceil() as usize).max(1));
    let every = (last - first).div_ceil(SERIES_FRAMES - 1).max(1);
    let instants: Vec<f64> = (first..=last).step_by(every).map(|j| j as f64 * step).collect();
    let bits = |set: &(dyn Fn(u32) -> bool + Sync)| {
        let mut b = vec![0u8; cells.len().div_ceil(8)];
        for (i, &c) in cells.iter().enumerate() {
            if set(c) {
                b[i / 8] |= 1 << (i % 8);
            }
        }
        base64::engine::general_purpose::STANDARD.encode(b)
    };
    let frames = instants
        .par_iter()
        .map(|&t| {
            let sun = truth.sun(t.min(truth.span_s()));
            bits(&|c| truth.lit(c, &sun) && truth.sun_above_ground_deg(c, &sun) > 0.0)
        })
        .collect();
    let valid = truth.dem().valid_mask();
    let epoch = truth.epoch();
    ShadowSeries {
        cells_per_pixel: k,
        cols: w,
        rows: h,
        sun_step_s: step,
        every_steps: every,
        unix_s: instants.iter().map(|&t| epoch.to_unix_seconds() + t).collect(),
        utc: instants.iter().map(|&t| format_utc(epoch + Duration::from_seconds(t))).collect(),
        frames,
        valid: bits(&|c| valid[c as usize]),
    }
}
