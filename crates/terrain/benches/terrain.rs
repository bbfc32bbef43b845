//! Terrain throughput on the TEMPEST-sized Gale DEM (2527 × 2356, from
//! ../shared/data/dem when present, else a synthesised DEM of the same size): one
//! shadow map by each method (target ≥ 50 M cells/s on one core for the default,
//! `Method::OwnRay`; `cast_shadows_*` names it, `sheared_*` and `interpolated_*` the
//! approximate traces), slope + aspect (≥ 100 M cells/s) and one horizon sector.

use std::path::PathBuf;

use areo_terrain::horizon::horizon_toward;
use areo_terrain::shadow::{Curvature, GridSunDirection, Method, Shadows};
use areo_terrain::slope::slope_aspect;
use areo_terrain::synth::{Noise, TerrainSpec};
use areo_terrain::{Dem, geotiff};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn dem() -> Dem {
    let p =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/dem/gale_mola_cubic164m_2527x2356.tif");
    geotiff::read(&p).unwrap_or_else(|e| {
        // A fallback measures another map: say so, and refuse where the data must be.
        assert!(
            std::env::var_os("AREO_REQUIRE_SHARED_DATA").is_none(),
            "{}: {e}, and AREO_REQUIRE_SHARED_DATA says it must be there",
            p.display()
        );
        #[allow(clippy::print_stderr)] // a bench says what it measures
        {
            eprintln!("terrain bench: {}: {e}; measuring a synthesised 2527 x 2356 DEM instead", p.display());
        }
        TerrainSpec {
            cols: 2527,
            rows: 2356,
            cell_m: 164.0,
            base_m: 0.0,
            seed: 1,
            noise: Some(Noise { amplitude_m: 2000.0, wavelength_m: 50_000.0, octaves: 6, persistence: 0.5 }),
            features: vec![],
        }
        .build()
        .unwrap()
    })
}

fn terrain(c: &mut Criterion) {
    let dem = dem();
    let cells = (dem.cols() * dem.rows()) as u64;
    let mut g = c.benchmark_group("terrain_2527x2356");
    g.sample_size(10);
    g.throughput(Throughput::Elements(cells));
    let mars = Curvature::Sphere { radius_m: 3_389_500.0 };
    let cases = [("az135_el20_curved", 135.0, 20.0, mars), ("az80_el5_flat", 80.0, 5.0, Curvature::Flat)];
    for (prefix, method) in
        [("cast_shadows", Method::OwnRay), ("sheared", Method::Sheared), ("interpolated", Method::Interpolated)]
    {
        for (case, az, el, curvature) in cases {
            g.bench_function(format!("{prefix}_{case}"), |b| {
                b.iter(|| Shadows::new(GridSunDirection::new(az, el), curvature).method(method).cast(&dem))
            });
        }
    }
    // A low Sun: the longest shadows, where the own ray marches furthest.
    g.bench_function("cast_shadows_az250_el2_flat", |b| {
        b.iter(|| Shadows::new(GridSunDirection::new(250.0, 2.0), Curvature::Flat).cast(&dem))
    });
    g.bench_function("slope_aspect", |b| b.iter(|| slope_aspect(&dem)));
    // What a TEMPEST run spends writing its DEM layer (the slope layer is the same size;
    // the shadow layer a quarter).
    let path = std::env::temp_dir().join(format!("areo-bench-{}.tif", std::process::id()));
    g.bench_function("geotiff_write_f32", |b| b.iter(|| areo_terrain::geotiff::write(&dem, &path).expect("written")));
    let _ = std::fs::remove_file(&path);
    // One sector of a horizon map (a 64-sector map is 64 of these, split over cores).
    g.bench_function("horizon_one_sector_az101", |b| {
        b.iter(|| horizon_toward(&dem, 101.25, Curvature::Sphere { radius_m: 3_389_500.0 }))
    });
    g.finish();
}

criterion_group!(benches, terrain);
criterion_main!(benches);
