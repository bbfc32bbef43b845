//! A synthesised crater, its slopes, its shadows at a low Sun and its horizon:
//! `cargo run -p areo-terrain --example crater_shadows` (works with default features
//! off: none of this needs faer or parry3d).

#![allow(clippy::print_stdout)] // an example prints what it shows

use areo_terrain::horizon::HorizonMap;
use areo_terrain::shadow::{Curvature, GridSunDirection, Shadows};
use areo_terrain::synth::{Feature, Noise, TerrainSpec};

fn main() -> Result<(), areo_terrain::Error> {
    let dem = TerrainSpec {
        cols: 120,
        rows: 120,
        cell_m: 10.0,
        base_m: 0.0,
        seed: 1,
        noise: Some(Noise { amplitude_m: 1.0, wavelength_m: 200.0, octaves: 2, persistence: 0.5 }),
        features: vec![Feature::Crater {
            x_m: 600.0,
            y_m: 600.0,
            radius_m: 250.0,
            depth_m: 50.0,
            rim_height_m: 12.0,
            ejecta_radii: 2.0,
        }],
    }
    .build()?;
    let slope = areo_terrain::slope::slope_aspect(&dem);
    let steepest = slope.slope_deg.iter().copied().fold(0.0f32, f32::max);
    println!("{} × {} cells of 10 m; steepest slope {steepest:.1}°", dem.cols(), dem.rows());
    for elevation in [5.0, 15.0, 30.0] {
        let map = Shadows::new(GridSunDirection::new(90.0, elevation), Curvature::of(&dem)).map(&dem);
        println!("Sun in the east {elevation:>4}° up: {:.1} % of the map lit", 100.0 * map.lit_fraction());
    }
    let horizon = HorizonMap::compute(&dem, 32, Curvature::of(&dem))?;
    let centre = dem.index(60, 60);
    let highest = horizon.cell_profile(centre).into_iter().fold(f32::MIN, f32::max);
    println!("from the crater floor the rim stands {highest:.1}° high at most");
    Ok(())
}
