//! The map layers a TEMPEST run puts under its route for a GIS: the planner's DEM, its
//! slope, the true terrain's direct sun at the job's `shadow_utc`, on their grids, and
//! its direct sun through the run at instants of the Sun table (written as GeoTIFFs
//! from the report by `output::reports`).

use areo_ephemeris::format_utc;
use areo_mission::World;
use areo_terrain::geotiff::Grid;
use areo_terrain::{Georef, Projection};
use base64::Engine;
use hifitime::Duration;
use rayon::prelude::*;

use crate::report::tempest::{MapLayers, SERIES_FRAMES, SERIES_PIXELS, ShadowSeries};
use crate::report::{Raster, lon180};

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
    let dem = truth.dem();
    let (x0, y_top) = (dem.x0(), dem.y_top());
    let (x1, y0) = (x0 + (w * k) as f64 * dem.dx(), y_top - (h * k) as f64 * dem.dy());
    let (footprint, bbox) = footprint(dem.georef(), (x0, y0), (x1, y_top));
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
        footprint,
        bbox,
    }
}

/// Points sampled along each edge of the map for its footprint.
const EDGE_POINTS: usize = 16;

/// The outline of the map's part from (`x0`, `y0`) to (`x1`, `y1`) (map metres, west,
/// south, east, north) in longitude (−180..180) and latitude on its body — a closed ring
/// of points along its edges, from the south-west corner east along the south edge (on
/// an equirectangular map anticlockwise, as RFC 7946 asks) — and its box (west, south,
/// east, north). A map round its projection's pole is the cap out to its farthest point
/// from the pole; a map of no known projection has no outline and is the whole body.
fn footprint(georef: &Georef, (x0, y0): (f64, f64), (x1, y1): (f64, f64)) -> (Vec<[f64; 2]>, [f64; 4]) {
    let along = |a: (f64, f64), b: (f64, f64)| {
        (0..EDGE_POINTS).map(move |k| {
            let f = k as f64 / EDGE_POINTS as f64;
            (a.0 + (b.0 - a.0) * f, a.1 + (b.1 - a.1) * f)
        })
    };
    let corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)];
    let ring: Option<Vec<[f64; 2]>> = corners
        .windows(2)
        .flat_map(|w| along(w[0], w[1]))
        .chain([(x0, y0)])
        .map(|(x, y)| georef.projection.to_geographic(&georef.surface, x, y).map(|(lat, lon)| [lon180(lon), lat]))
        .collect();
    let Some(ring) = ring else { return (Vec::new(), [-180.0, -90.0, 180.0, 90.0]) };
    let (mut west, mut east) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut south, mut north) = (f64::INFINITY, f64::NEG_INFINITY);
    for &[lon, lat] in &ring {
        (west, east, south, north) = (west.min(lon), east.max(lon), south.min(lat), north.max(lat));
    }
    let pole = matches!(georef.projection, Projection::PolarStereographic { .. })
        && (x0..=x1).contains(&0.0)
        && (y0..=y1).contains(&0.0);
    if pole || east - west > 180.0 {
        // Round a pole, or across the antimeridian: every longitude.
        let (south, north) = if pole && north > 0.0 {
            (south, 90.0)
        } else if pole {
            (-90.0, north)
        } else {
            (south, north)
        };
        let cap = vec![[-180.0, south], [180.0, south], [180.0, north], [-180.0, north], [-180.0, south]];
        return (cap, [-180.0, south, 180.0, north]);
    }
    (ring, [west, south, east, north])
}

#[cfg(test)]
mod tests {
    use super::*;
    use areo_terrain::Spheroid;

    /// The outline of a map of 40 × 30 cells of 100 m from (`x0`, `y_top`).
    fn of(projection: Projection, surface: Spheroid, (x0, y_top): (f64, f64)) -> (Vec<[f64; 2]>, [f64; 4]) {
        footprint(&Georef { projection, surface }, (x0, y_top - 3000.0), (x0 + 4000.0, y_top))
    }

    /// An equirectangular map's outline runs through its corners, south-west first and
    /// last, east along the south edge; its box is theirs.
    #[test]
    fn an_equirectangular_maps_footprint_is_its_corners_on_the_body() {
        let projection = Projection::Equirectangular { lat_ts_deg: 0.0, lon0_deg: 137.4 };
        let (ring, bbox) = of(projection, Spheroid::MARS_MOLA_SPHERE, (-2000.0, 1500.0));
        assert_eq!(ring.len(), 4 * EDGE_POINTS + 1);
        assert_eq!(ring[0], ring[4 * EDGE_POINTS]);
        let corner = |x: f64, y: f64| {
            let (lat, lon) = projection.to_geographic(&Spheroid::MARS_MOLA_SPHERE, x, y).unwrap();
            [lon, lat]
        };
        let at = |k: usize| ring[k];
        assert_eq!(at(0), corner(-2000.0, -1500.0));
        assert_eq!(at(EDGE_POINTS), corner(2000.0, -1500.0));
        assert_eq!(at(2 * EDGE_POINTS), corner(2000.0, 1500.0));
        let (sw, ne) = (corner(-2000.0, -1500.0), corner(2000.0, 1500.0));
        assert_eq!(bbox, [sw[0], sw[1], ne[0], ne[1]]);
        // 4 km east–west on Mars's sphere at the equator: 0.0675° of longitude.
        assert!(((bbox[2] - bbox[0]) - (4000.0 / 3_396_000.0f64).to_degrees()).abs() < 1e-9);
    }

    /// A polar map round its pole is the cap out to its farthest corner; a map in a
    /// local frame has no outline and is the whole body.
    #[test]
    fn a_map_round_the_pole_is_a_cap_and_a_local_map_is_the_body() {
        let south = Projection::PolarStereographic { north: false, lon0_deg: 0.0 };
        let (ring, bbox) = of(south, Spheroid::MOON, (-2000.0, 1500.0));
        assert_eq!((bbox[0], bbox[1], bbox[2]), (-180.0, -90.0, 180.0));
        // Out to the farthest corner, 2.5 km from the pole: 2·atan(ρ / 2R) of latitude.
        let c = 2.0 * (2500.0 / (2.0 * 1_737_400.0f64)).atan();
        assert!((bbox[3] - (-90.0 + c.to_degrees())).abs() < 1e-9, "{bbox:?}");
        assert_eq!(ring, [[-180.0, bbox[1]], [180.0, bbox[1]], [180.0, bbox[3]], [-180.0, bbox[3]], [-180.0, bbox[1]]]);
        let (ring, bbox) = of(Projection::Local, Spheroid::MOON, (0.0, 3000.0));
        assert!(ring.is_empty());
        assert_eq!(bbox, [-180.0, -90.0, 180.0, 90.0]);
    }
}
