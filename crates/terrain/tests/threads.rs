//! Same input ⇒ identical output, whatever the thread count.

use areo_terrain::horizon::HorizonMap;
use areo_terrain::shadow::Curvature;
use areo_terrain::slope::slope_aspect;
use areo_terrain::synth::{Feature, Noise, TerrainSpec};

#[test]
fn slope_and_horizon_maps_do_not_depend_on_the_thread_count() {
    let dem = TerrainSpec {
        cols: 150,
        rows: 120,
        cell_m: 10.0,
        base_m: 0.0,
        seed: 9,
        noise: Some(Noise { amplitude_m: 25.0, wavelength_m: 400.0, octaves: 4, persistence: 0.5 }),
        features: vec![Feature::Crater {
            x_m: 700.0,
            y_m: 600.0,
            radius_m: 250.0,
            depth_m: 40.0,
            rim_height_m: 10.0,
            ejecta_radii: 2.0,
        }],
    }
    .build()
    .unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let sa = slope_aspect(&dem);
            let h = HorizonMap::compute(&dem, 16, Curvature::Sphere { radius_m: 3_389_500.0 }).unwrap();
            let horizon: Vec<f64> = (0..dem.cols() * dem.rows()).map(|i| h.horizon_deg(i, 33.0)).collect();
            (sa.slope_deg, sa.aspect_deg, horizon)
        })
    };
    let (one, three) = (run(1), run(3));
    assert!(one.0.iter().zip(&three.0).all(|(a, b)| a.to_bits() == b.to_bits()));
    assert!(one.1.iter().zip(&three.1).all(|(a, b)| a.to_bits() == b.to_bits()));
    assert_eq!(one.2, three.2);
}

/// A true terrain's horizon held as its differences from the map's: where a cell's
/// profile is listed it equals the full map of the true terrain, sector by sector, bit
/// for bit; where it is not, the two full maps agree. The same for 1 and 3 threads.
#[test]
fn horizon_changes_equal_the_difference_of_two_full_maps() {
    let spec = |features: Vec<Feature>| TerrainSpec {
        cols: 140,
        rows: 110,
        cell_m: 20.0,
        base_m: 0.0,
        seed: 4,
        noise: Some(Noise { amplitude_m: 30.0, wavelength_m: 800.0, octaves: 4, persistence: 0.5 }),
        features,
    };
    let map = spec(vec![]).build().unwrap();
    let truth =
        spec(vec![Feature::Hill { x_m: 1500.0, y_m: 1200.0, radius_m: 120.0, slope_deg: 35.0 }]).build().unwrap();
    let curvature = Curvature::Sphere { radius_m: 3_389_500.0 };
    for sectors in [16, 17] {
        let reference = HorizonMap::compute(&map, sectors, curvature).unwrap();
        let full = HorizonMap::compute(&truth, sectors, curvature).unwrap();
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| reference.changes(&truth, curvature).unwrap())
        };
        let (changes, three) = (run(1), run(3));
        let cells = map.cols() * map.rows();
        let mut listed = 0;
        for i in 0..cells {
            let (want, base) = (full.cell_profile(i), reference.cell_profile(i));
            match changes.profile(i) {
                Some(p) => {
                    listed += 1;
                    assert_eq!(p, &want[..], "cell {i}");
                    assert_ne!(want, base, "cell {i} is listed but does not differ");
                    assert_eq!(three.profile(i), Some(p));
                }
                None => {
                    assert_eq!(want, base, "cell {i} differs but is not listed");
                    assert!(three.profile(i).is_none());
                }
            }
        }
        assert_eq!(listed, changes.len());
        // The hill is seen from far: many cells, but far from all.
        assert!(listed > 500 && listed < cells / 2, "{listed} of {cells} cells changed");
    }
}
