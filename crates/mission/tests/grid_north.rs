//! A polar map whose central meridian is not the site's (a LOLA product, λ0 = 0, at a
//! site at 90°E): its grid's north is not true north, so the Sun and the Earth must turn
//! with the grid. The same ground on a map aligned with the site and on the turned map
//! must be lit alike, not a quarter turn apart.

use areo_ephemeris::flux::Atmosphere;
use areo_ephemeris::{Body, Site, parse_utc};
use areo_mission::{World, WorldConfig};
use areo_terrain::{Dem, Georef, Projection, Spheroid};

const SITE: (f64, f64) = (-89.0, 90.0);
const CELLS: usize = 121;
const CELL_M: f64 = 25.0;

/// A 300 m peak 600 m west of the site on flat ground: at the pole the Sun stands a
/// degree or two high, so its shadow crosses the whole map.
fn aligned() -> Dem {
    let half = 0.5 * CELLS as f64 * CELL_M;
    Dem::from_fn(CELLS, CELLS, CELL_M, CELL_M, |x, y| {
        let (dx, dy) = (x - half + 600.0, y - half);
        300.0 * (-(dx * dx + dy * dy) / (2.0 * 300.0f64.powi(2))).exp()
    })
    .unwrap()
    .placed_at(Spheroid::MOON, SITE.0, SITE.1)
    .unwrap()
}

/// The same ground on a south polar stereographic grid with λ0 = 0, centred on the
/// site: every cell's height read off the aligned map at the same latitude and
/// longitude.
fn turned(aligned: &Dem) -> Dem {
    let proj = Projection::PolarStereographic { north: false, lon0_deg: 0.0 };
    let (xs, ys) = proj.from_geographic(&Spheroid::MOON, SITE.0, SITE.1).unwrap();
    let half = 0.5 * CELLS as f64 * CELL_M;
    let grid = Dem::new(CELLS, CELLS, CELL_M, CELL_M, xs - half, ys + half, vec![0.0; CELLS * CELLS]).unwrap();
    let z = (0..CELLS * CELLS)
        .map(|i| {
            let (x, y) = grid.cell_center(i % CELLS, i / CELLS);
            let (lat, lon) = proj.to_geographic(&Spheroid::MOON, x, y).unwrap();
            let (xa, ya) = aligned.georef().projection.from_geographic(&Spheroid::MOON, lat, lon).unwrap();
            aligned.height(xa, ya).unwrap_or(0.0) as f32
        })
        .collect();
    grid.with_values(z).unwrap().with_georef(Georef { projection: proj, surface: Spheroid::MOON })
}

fn world(dem: Dem) -> World {
    let config = WorldConfig {
        epoch: parse_utc("2025-01-01T00:00:00Z").unwrap(),
        span_s: 30.0 * 86400.0,
        sun_step_s: 3600.0,
        horizon_sectors: Some(360),
        atmosphere: Atmosphere::Airless,
        site: Some(Site::on(Body::Moon, SITE.0, SITE.1).unwrap()),
    };
    World::new(dem, &config, &Body::Moon).unwrap()
}

#[test]
fn a_polar_map_turned_from_the_sites_meridian_is_lit_as_the_aligned_one() {
    let a = aligned();
    let b = turned(&a);
    let (wa, wb) = (world(a.clone()), world(b.clone()));
    assert_eq!(wa.true_north_on_grid_deg(), 0.0);
    assert!((wb.true_north_on_grid_deg() - 90.0).abs() < 1e-9);
    // Instants of the month with the Sun at least a degree up, a few days apart.
    let instants: Vec<f64> = (0..30 * 24)
        .map(|h| h as f64 * 3600.0)
        .filter(|&t| wa.sun(t).elevation_deg > 1.0)
        .enumerate()
        .filter(|(i, _)| i % 48 == 0)
        .map(|(_, t)| t)
        .collect();
    assert!(instants.len() >= 4, "{instants:?}");
    let mut shaded_in_disc = 0;
    for &t in &instants {
        let (sa, sb) = (wa.sun(t), wb.sun(t));
        // The same sky, a quarter turn on the grid.
        let turn = (sb.azimuth_deg - sa.azimuth_deg).rem_euclid(360.0);
        assert!((turn - 90.0).abs() < 1e-9, "{turn}");
        assert!((sb.enu[0] - sa.enu[1]).abs() < 1e-12 && (sb.enu[1] + sa.enu[0]).abs() < 1e-12);
        if let (Some(ea), Some(eb)) = (wa.earth(t), wb.earth(t)) {
            assert!(((eb.azimuth_deg - ea.azimuth_deg).rem_euclid(360.0) - 90.0).abs() < 1e-9);
        }
        // The same ground lit alike: cells of the turned map within 1.2 km of the
        // site (inside both maps), against the aligned map's cell at the same point.
        let (mut same, mut compared) = (0, 0);
        for cell in 0..wb.cells() as u32 {
            let (col, row) = wb.col_row(cell);
            let (x, y) = b.cell_center(col, row);
            let (lat, lon) = b.georef().projection.to_geographic(&Spheroid::MOON, x, y).unwrap();
            let (xa, ya) = a.georef().projection.from_geographic(&Spheroid::MOON, lat, lon).unwrap();
            let (ca, ra) = a.cell_at(xa, ya).unwrap();
            let (xc, yc) = a.cell_center(CELLS / 2, CELLS / 2);
            if (xa - xc).hypot(ya - yc) > 1200.0 {
                continue;
            }
            let lit_a = wa.lit(wa.cell(ca, ra), &sa);
            compared += 1;
            same += usize::from(lit_a == wb.lit(cell, &sb));
            shaded_in_disc += usize::from(!lit_a);
        }
        let agreement = same as f64 / compared as f64;
        // Cells whose centres straddle a shadow's edge may differ; a quarter turn off
        // agreed on 0.36–0.72 of them before the fix (0.998–1 after).
        assert!(agreement > 0.99, "t {t}: {same} of {compared} cells lit alike");
    }
    // The comparison has shadows to compare: the peak's shadow crosses the disc.
    assert!(shaded_in_disc > 500, "{shaded_in_disc}");
}
