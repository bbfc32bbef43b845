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
