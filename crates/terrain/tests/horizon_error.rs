//! How far a horizon map's sector horizons are from each cell's own ray (issue 21):
//! every cell of every sector against the brute-force horizon on the triangulated
//! surface, on the real Gale MOLA crop and on synthesised terrain. The figures printed
//! are the ones the `HorizonMap` rustdoc states.

use std::path::Path;

use areo_terrain::horizon::HorizonMap;
use areo_terrain::shadow::Curvature;
use areo_terrain::synth::{Feature, Noise, TerrainSpec};
use areo_terrain::tin::horizon_on_triangles;
use areo_terrain::{Dem, geotiff};

/// (largest, 99.9th percentile, 99th percentile) of |map − own ray| in degrees over
/// every valid cell of every sector, away from the map's border.
fn errors(dem: &Dem, sectors: usize) -> (f64, f64, f64) {
    let map = HorizonMap::compute(dem, sectors, Curvature::Flat).unwrap();
    let mut e = Vec::new();
    for s in 0..sectors {
        let az = s as f64 * 360.0 / sectors as f64;
        let truth = horizon_on_triangles(dem, az, Curvature::Flat);
        for (i, t) in truth.iter().enumerate() {
            let (c, r) = (i % dem.cols(), i / dem.cols());
            // Border cells: their own ray may leave the map before it crosses an edge
            // (−90°) while the sweep's line beside it stays in; stated apart.
            let border = c == 0 || r == 0 || c + 1 == dem.cols() || r + 1 == dem.rows();
            if t.is_finite() && !border {
                // Both sides clamp at the encoding's −90°.
                let d = (map.horizon_deg(i, az) - t).abs();
                e.push(d);
            }
        }
    }
    e.sort_by(f64::total_cmp);
    let q = |p: f64| e[((e.len() - 1) as f64 * p) as usize];
    (e[e.len() - 1], q(0.999), q(0.99))
}

#[test]
fn sector_horizons_are_within_the_stated_error_of_each_cells_own_ray() {
    let gale = geotiff::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gale_mola_crop_64.tif")).unwrap();
    let synth = TerrainSpec {
        cols: 80,
        rows: 60,
        cell_m: 20.0,
        base_m: 0.0,
        seed: 5,
        noise: Some(Noise { amplitude_m: 40.0, wavelength_m: 500.0, octaves: 3, persistence: 0.5 }),
        features: vec![Feature::Hill { x_m: 800.0, y_m: 600.0, radius_m: 300.0, slope_deg: 25.0 }],
    }
    .build()
    .unwrap();
    let measured: Vec<_> = [("gale 64x64", &gale), ("synthesised 80x60", &synth)]
        .into_iter()
        .map(|(name, dem)| {
            let (max, p999, p99) = errors(dem, 32);
            eprintln!("{name}: |horizon map − own ray| max {max:.3}°, 99.9 % {p999:.3}°, 99 % {p99:.3}°");
            (name, max, p999, p99)
        })
        .collect();
    for (name, max, p999, p99) in measured {
        // The bounds the HorizonMap rustdoc states (measured 2026-11-25: Gale 1.83°,
        // 5.73°, 18.97°; synthesised 1.18°, 3.55°, 11.91°).
        assert!(p99 <= 2.0, "{name}: 99 % within {p99}°");
        assert!(p999 <= 6.0, "{name}: 99.9 % within {p999}°");
        assert!(max <= 20.0, "{name}: largest {max}°");
    }
}

/// Cells where the shadow sweep and each cell's own ray (brute force on the same
/// triangulated surface) disagree, as a fraction of valid cells.
fn sweep_disagreement(dem: &Dem, az: f64, el: f64) -> f64 {
    let swept = areo_terrain::shadow::cast_shadows(dem, az, el, Curvature::Flat);
    let own = horizon_on_triangles(dem, az, Curvature::Flat);
    let (mut differ, mut valid) = (0usize, 0usize);
    for (s, h) in swept.iter().zip(&own) {
        if h.is_finite() {
            valid += 1;
            differ += usize::from(*s != (*h > el));
        }
    }
    differ as f64 / valid as f64
}

#[test]
fn the_shadow_sweep_is_measured_against_each_cells_own_ray() {
    // The cast-shadow sweep against each cell's own ray on the same surface, at the
    // azimuths and elevations issue 21 tried: what the `shadow` docs state.
    let gale = geotiff::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gale_mola_crop_64.tif")).unwrap();
    let mut worst: f64 = 0.0;
    for (az, el) in [(270.0, 5.0), (90.0, 10.0), (315.0, 15.0), (135.0, 20.0), (200.0, 8.0)] {
        let d = sweep_disagreement(&gale, az, el);
        eprintln!("gale crop az {az} el {el}: {:.3} % of cells differ from their own ray", 100.0 * d);
        worst = worst.max(d);
    }
    assert_eq!(worst, 0.0, "the 64 × 64 crop: every cell as its own ray says");
    // The case on the full 897 × 897 map: a due-west Sun 5° up.
    let Some(path) = crate::readers::shared("gale_mola_463m.tif") else {
        eprintln!("skipped the full map: ../shared/data/dem/gale_mola_463m.tif is not there");
        return;
    };
    let full = geotiff::read(&path).unwrap();
    let extra: &[(f64, f64)] = if std::env::var_os("AREO_MORE_AZIMUTHS").is_some() {
        &[(90.0, 10.0), (315.0, 15.0), (135.0, 20.0), (200.0, 8.0), (250.0, 2.0)]
    } else {
        &[]
    };
    for &(az, el) in [(270.0, 5.0)].iter().chain(extra) {
        let d = sweep_disagreement(&full, az, el);
        eprintln!("gale 897 x 897 az {az} el {el}: {:.3} % of cells differ from their own ray", 100.0 * d);
        // What the `shadow` docs state (measured 2026-11-25 with AREO_MORE_AZIMUTHS,
        // release): 0 at 270°/5° and 90°/10°, 0.007 % at 315°/15°, 0.004 % at 135°/20°,
        // 0.028 % at 200°/8°, 0.113 % at 250°/2°.
        let bound = if az % 90.0 == 0.0 {
            0.0
        } else if el >= 5.0 {
            0.0005
        } else {
            0.005
        };
        assert!(d <= bound, "az {az} el {el}: {d} of cells differ (stated at most {bound})");
    }
}

#[test]
fn the_shadow_sweep_on_synthesised_terrain_at_many_azimuths() {
    // Craters, a hill and noise on square 30 m cells: every 15° of azimuth, at a Sun 2°,
    // 5° and 15° up, against each cell's own ray. Issue 21's targets are ≥ 99.95 % of
    // cells at 5° and above, ≥ 99.5 % at 2°, and every cell on cardinal azimuths.
    let dem = TerrainSpec {
        cols: 120,
        rows: 100,
        cell_m: 30.0,
        base_m: 0.0,
        seed: 11,
        noise: Some(Noise { amplitude_m: 25.0, wavelength_m: 900.0, octaves: 4, persistence: 0.5 }),
        features: vec![
            Feature::Crater {
                x_m: 1200.0,
                y_m: 1500.0,
                radius_m: 500.0,
                depth_m: 120.0,
                rim_height_m: 40.0,
                ejecta_radii: 2.0,
            },
            Feature::Hill { x_m: 2800.0, y_m: 1000.0, radius_m: 600.0, slope_deg: 22.0 },
        ],
    }
    .build()
    .unwrap();
    let (mut worst_low, mut worst_high): (f64, f64) = (0.0, 0.0);
    for k in 0..24 {
        let az = k as f64 * 15.0;
        for el in [2.0, 5.0, 15.0] {
            let d = sweep_disagreement(&dem, az, el);
            if az % 90.0 == 0.0 {
                assert_eq!(d, 0.0, "az {az} el {el}: a cardinal azimuth, every cell as its own ray says");
            }
            if el < 5.0 {
                worst_low = worst_low.max(d);
            } else {
                worst_high = worst_high.max(d);
            }
        }
    }
    eprintln!(
        "synthesised 120x100, 24 azimuths: worst {:.3} % at 2°, {:.3} % at 5° and 15°",
        100.0 * worst_low,
        100.0 * worst_high
    );
    // Measured 2026-11-25: 0.100 % at 5° and above (99.90 %: issue 21's 99.95 % is not
    // met here yet), 0.142 % at 2° (met). The asserts keep today's level.
    assert!(worst_high <= 0.0012, "at 5° and above: {worst_high}");
    assert!(worst_low <= 0.005, "≥ 99.5 % at 2°: {worst_low}");
}
