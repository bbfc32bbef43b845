use super::*;
use crate::reference::horizon_on_grid_lines;
use crate::shadow::{GridSunDirection, Method, cast_shadows};
use crate::synth::{Feature, Noise, TerrainSpec};

fn terrain() -> Dem {
    terrain_with(vec![])
}

/// The test terrain with `more` features besides its hill.
fn terrain_with(more: Vec<Feature>) -> Dem {
    let mut features = vec![Feature::Hill { x_m: 900.0, y_m: 700.0, radius_m: 400.0, slope_deg: 20.0 }];
    features.extend(more);
    TerrainSpec {
        cols: 90,
        rows: 70,
        cell_m: 20.0,
        base_m: 0.0,
        seed: 3,
        noise: Some(Noise { amplitude_m: 60.0, wavelength_m: 600.0, octaves: 3, persistence: 0.5 }),
        features,
    }
    .build()
    .unwrap()
}

#[test]
#[allow(clippy::print_stderr)] // the agreement figures are the point of the test
fn horizon_lookups_agree_with_shadow_maps_at_sector_centres() {
    let dem = terrain();
    let map = HorizonMap::compute(&dem, 32, Curvature::Flat).unwrap();
    assert_eq!(map.bytes(), 32 * 90 * 70 * 2);
    for (sector, el) in [(0usize, 10.0), (4, 15.0), (9, 6.0), (17, 25.0), (26, 12.0)] {
        let az = sector as f64 * 360.0 / 32.0;
        let truth = horizon_on_grid_lines(&dem, az, Curvature::Flat);
        let looked_up = map.shadowed(az, el);
        let traced = cast_shadows(&dem, GridSunDirection::new(az, el), Curvature::Flat, Method::OwnRay);
        let (mut differ, mut not_grazing, mut trace_differ) = (0, 0, 0);
        for i in 0..truth.len() {
            let shadowed = truth[i] > el;
            if looked_up[i] != shadowed {
                differ += 1;
                if (truth[i] - el).abs() > 1.0 {
                    not_grazing += 1;
                }
            }
            if traced[i] != looked_up[i] {
                trace_differ += 1;
            }
        }
        let n = truth.len() as f64;
        eprintln!(
            "az {az:6.2} el {el:4.1}: horizon map vs rays {differ}, of which {not_grazing} not grazing; vs trace {trace_differ} (of {n})"
        );
        assert!(differ as f64 / n <= 0.0025, "az {az}: {differ} differ from the ray cast");
        assert!(not_grazing as f64 / n <= 0.0005, "az {az}: {not_grazing} disagreements away from grazing");
        assert!(trace_differ as f64 / n <= 0.015, "az {az}: {trace_differ} differ from the shadow trace");
    }
}

#[test]
fn a_narrowed_map_is_within_half_a_step_of_the_two_byte_map_in_half_the_memory() {
    let dem = terrain();
    let wide = HorizonMap::compute(&dem, 32, Curvature::Flat).unwrap();
    let narrow = wide.narrowed();
    assert!(narrow.is_narrow() && !wide.is_narrow());
    assert_eq!(narrow.bytes() * 2, wide.bytes());
    let bound = narrow.error_deg();
    assert!((bound - 90.0 / 255.0).abs() < 1e-12);
    let mut largest: f64 = 0.0;
    for i in 0..dem.cols() * dem.rows() {
        for k in 0..97 {
            let az = k as f64 * 360.0 / 97.0;
            largest = largest.max((narrow.horizon_deg(i, az) - wide.horizon_deg(i, az)).abs());
        }
    }
    // The bound holds, and is nearly reached: the encoding is not finer than stated.
    assert!(largest <= bound + 1e-9, "{largest}° against the stated {bound}°");
    assert!(largest > 0.9 * bound, "{largest}°: far inside the stated {bound}°");
    // A window of the narrowed map is the narrowed window of the map.
    let a = narrow.window((10, 5, 40, 30), None);
    let b = wide.window((10, 5, 40, 30), None).narrowed();
    assert_eq!(a, b);
    // The truth's differences are taken at the map's precision: none on the same
    // terrain, and where the terrain differs, profiles within the bound of the
    // two-byte map's.
    assert!(narrow.changes(&dem, Curvature::Flat).unwrap().is_empty());
    let raised = terrain_with(vec![Feature::Hill { x_m: 400.0, y_m: 300.0, radius_m: 100.0, slope_deg: 30.0 }]);
    let (wide_changes, narrow_changes) =
        (wide.changes(&raised, Curvature::Flat).unwrap(), narrow.changes(&raised, Curvature::Flat).unwrap());
    assert!(!narrow_changes.is_empty() && narrow_changes.len() <= wide_changes.len());
    for i in 0..dem.cols() * dem.rows() {
        if let Some(p) = narrow_changes.profile(i) {
            let q = wide_changes.profile(i).expect("a narrow change is a wide one");
            assert!(p.iter().zip(q).all(|(a, b)| f64::from((a - b).abs()) <= bound + 1e-4));
        }
    }
}

#[test]
fn encoding_in_bulk_equals_encoding_one_by_one() {
    use rand::{RngExt, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let cells: Vec<[f32; 2]> = (0..1000)
        .map(|i| match i % 10 {
            0 => [0.0, 0.0],
            1 => [rng.random_range(-5.0..5.0), 0.0],
            _ => [rng.random_range(-50.0..50.0), rng.random_range(0.01..2.0)],
        })
        .collect();
    let zn: Vec<f32> = (0..1000).map(|i| if i % 7 == 0 { f32::NAN } else { 1.0 }).collect();
    let mut out = vec![0u16; 1000];
    encode_all(&cells, &zn, &mut out);
    for i in 0..1000 {
        let [sum, weight] = cells[i];
        assert_eq!(out[i], encode(finish(!zn[i].is_nan(), sum, weight)), "cell {i}: {:?}", cells[i]);
    }
}

#[test]
fn the_tangent_searched_from_a_neighbour_equals_the_bisection() {
    use rand::{RngExt, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    for _ in 0..200 {
        // A rough profile pushed onto the hull, then observers at the next abscissa
        // above and below the next sample.
        let mut hull = Hull::default();
        let n = rng.random_range(1..120);
        for x in 0..n {
            let y = rng.random_range(-20.0..20.0) + 0.1 * f64::from(x);
            let keep = hull_keep(&hull, (f64::from(x), y));
            hull.truncate(keep);
            hull.push((f64::from(x), y));
        }
        let ox = f64::from(n);
        let py = rng.random_range(-30.0..40.0);
        let keep = hull_keep(&hull, (ox, py));
        for dy in [-50.0, -3.0, -0.2, 0.0, 0.2, 3.0, 50.0, 500.0] {
            let fast = tangent_from(&hull, ox, py + dy, keep - 1, py);
            let slow = tangent(&hull, ox, py + dy).unwrap();
            assert!((fast - slow).abs() <= 1e-12 * slow.abs().max(1.0), "{fast} vs {slow}");
        }
    }
}

#[test]
fn flat_ground_has_a_flat_horizon_and_a_wall_raises_it() {
    let flat = Dem::from_fn(20, 20, 1.0, 1.0, |_, _| 0.0).unwrap();
    let h = horizon_toward(&flat, 123.0, Curvature::Flat);
    assert!(h.iter().all(|a| a.abs() < 1e-9 || *a == -90.0));
    // A 10 m wall 10 m east of a cell: horizon 45° toward the east.
    let wall = Dem::from_fn(40, 5, 1.0, 1.0, |x, _| if (30.0..31.0).contains(&x) { 10.0 } else { 0.0 }).unwrap();
    let h = horizon_toward(&wall, 90.0, Curvature::Flat);
    assert!((h[2 * 40 + 20] - 45.0).abs() < 0.5, "{}", h[2 * 40 + 20]);
}

#[test]
fn sunlight_is_the_elevation_above_the_ground_plane() {
    // A plane facing east at 20°: the Sun in the east at 30° stands 50° above it.
    let dem = Dem::from_fn(30, 30, 1.0, 1.0, |x, _| -x * 20f64.to_radians().tan()).unwrap();
    let map = HorizonMap::compute(&dem, 16, Curvature::Flat).unwrap();
    let lit = sun_above_ground_deg(&dem, &map, 90.0, 30.0);
    assert!((lit[15 * 30 + 15] - 50.0).abs() < 0.01, "{}", lit[15 * 30 + 15]);
    // From the west at 10° the Sun is behind the slope.
    assert!(sun_above_ground_deg(&dem, &map, 270.0, 10.0)[15 * 30 + 15].is_nan());
    let seq = los_sequence(&dem, &map, 0.0, 3.0, 1.0, |t| (90.0, 10.0 + 10.0 * t));
    assert_eq!(seq.len(), 3);
    assert!((seq[2].1[15 * 30 + 15] - 50.0).abs() < 0.01);
}

#[test]
fn a_raised_map_is_the_upper_envelope_of_its_profiles() {
    let wall = Dem::from_fn(40, 5, 1.0, 1.0, |x, _| if (30.0..31.0).contains(&x) { 10.0 } else { 0.0 }).unwrap();
    for map in [HorizonMap::compute(&wall, 16, Curvature::Flat).unwrap(), {
        let m = HorizonMap::compute(&wall, 16, Curvature::Flat).unwrap();
        m.narrowed()
    }] {
        let i = 2 * 40 + 20;
        let mut higher = map.cell_profile(i);
        // East (sector 4) raised well above the wall's 45°, north (sector 0) by a
        // fraction of a code step; west lowered, which must not lower the map.
        higher[4] = 60.123;
        higher[0] += 0.001;
        higher[12] -= 5.0;
        let raised = map.raised([(i, higher.clone()), (9999, higher.clone()), (1, vec![1.0; 3])]);
        let got = raised.cell_profile(i);
        assert!(f64::from(got[4]) >= 60.123 && f64::from(got[4]) < 60.123 + NARROW_STEP_DEG + 1e-9, "{}", got[4]);
        assert!(got[0] >= higher[0] && got[0] > map.cell_profile(i)[0], "rounded up: {} vs {}", got[0], higher[0]);
        assert_eq!(got[12], map.cell_profile(i)[12]);
        // Every other cell as it was.
        assert!((0..200).filter(|&c| c != i).all(|c| raised.cell_profile(c) == map.cell_profile(c)));
    }
}

/// The terrain `dem` changed in `edit`'s cells: (cell, new height or `None` for missing).
fn edited(dem: &Dem, edit: &[(usize, Option<f32>)]) -> Dem {
    let mut z = dem.elevations().to_vec();
    let mut valid = dem.valid_mask().to_vec();
    for &(i, h) in edit {
        match h {
            Some(h) => (z[i], valid[i]) = (h, true),
            None => valid[i] = false,
        }
    }
    Dem::new(dem.cols(), dem.rows(), dem.dx(), dem.dy(), dem.x0(), dem.y_top(), z).unwrap().with_mask(valid).unwrap()
}

/// Tracing only the lines near the changed cells finds the changes the whole trace
/// finds, cell for cell and bit for bit: a hill added, scattered cells raised and sunk
/// (one on the map's edge, one in a corner), cells gone missing, nothing changed; square
/// and oblong cells (a shift that is no simple fraction); sectors paired and not; flat
/// and on the Moon's sphere; two-byte and one-byte maps.
#[test]
fn changes_traced_near_the_changed_cells_equal_the_whole_trace() {
    use rand::{RngExt, SeedableRng};
    let square = terrain();
    let oblong = Dem::new(90, 70, 20.0, 27.3, 0.0, 70.0 * 27.3, square.elevations().to_vec()).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    for before in [square, oblong] {
        let (cols, cells) = (before.cols(), before.cols() * before.rows());
        let mut places: Vec<usize> = (0..6).map(|_| rng.random_range(0..cells)).collect();
        places.extend([45 * cols, cells - 1]);
        let scattered: Vec<(usize, Option<f32>)> =
            places.iter().map(|&i| (i, Some(before.elevations()[i] + rng.random_range(-80.0f32..120.0)))).collect();
        let afters = [
            (terrain_with(vec![Feature::Hill { x_m: 400.0, y_m: 1000.0, radius_m: 90.0, slope_deg: 30.0 }]), true),
            (edited(&before, &scattered), true),
            (edited(&before, &[(30 * cols + 40, None), (30 * cols + 41, None), (31 * cols + 40, None)]), true),
            (before.clone(), false),
        ];
        for (after, differs) in &afters {
            if after.dy() != before.dy() {
                continue; // the hill is built on square cells
            }
            for (sectors, curvature) in
                [(32, Curvature::Flat), (17, Curvature::Flat), (16, Curvature::Sphere { radius_m: 1_737_400.0 })]
            {
                let wide = HorizonMap::compute(&before, sectors, curvature).unwrap();
                for map in [wide.narrowed(), wide] {
                    let whole = map.changes(after, curvature).unwrap();
                    let near = map.changes_from(&before, after, curvature).unwrap();
                    assert_eq!(whole.is_empty(), !differs, "{sectors} sectors");
                    assert_eq!(near.len(), whole.len(), "{sectors} sectors, {} cells changed", whole.len());
                    for i in 0..cells {
                        let bits = |p: Option<&[f32]>| p.map(|p| p.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
                        assert_eq!(bits(near.profile(i)), bits(whole.profile(i)), "cell {i}, {sectors} sectors");
                    }
                }
            }
        }
    }
}
