//! A TEMPEST plan in position, time and energy: a Hyperion-class rover crosses rolling
//! synthesised terrain at Gale from the morning on, charging as it goes —
//! `cargo run --release -p areo-mission --example plan_a_traverse`.

#![allow(clippy::print_stdout)] // an example prints what it shows

use areo_ephemeris::{Mars24, Site, flux::Atmosphere, parse_utc};
use areo_mission::{ActionConfig, ActionModel, Mission, PlannerConfig, Start, World, WorldConfig};
use areo_rover::resources::ResourceModel;
use areo_terrain::synth::{Noise, TerrainSpec};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dem = TerrainSpec {
        cols: 60,
        rows: 40,
        cell_m: 25.0,
        base_m: -4500.0,
        seed: 7,
        noise: Some(Noise { amplitude_m: 8.0, wavelength_m: 600.0, octaves: 3, persistence: 0.5 }),
        features: vec![],
    }
    .build()?;
    let config = WorldConfig {
        // Morning at Gale (about 08:00 local solar time).
        epoch: parse_utc("2012-08-06T22:15:00Z")?,
        span_s: 24.0 * 3600.0,
        sun_step_s: 120.0,
        horizon_sectors: Some(32),
        atmosphere: Atmosphere::BeerLambert { tau: 0.5 },
        site: Some(Site::new(-4.59, 137.44)?),
    };
    let world = World::new(dem, &config, &Mars24)?;
    let model = ActionModel::new(ResourceModel::hyperion(), ActionConfig::default());
    let start = Start { cell: world.cell(3, 20), t_min: 0.0, t_max: 600.0, energy_wh: 300.0 };
    let goals = [world.cell(56, 10), world.cell(50, 35)];
    let (_, plan) = Mission::plan(&world, &model, PlannerConfig::default(), start, &goals)?;
    println!(
        "{} waypoints over {:.1} h; lowest battery {:.0} Wh",
        plan.waypoints.len(),
        plan.duration_s() / 3600.0,
        plan.min_battery_wh()
    );
    for w in plan.waypoints.iter().filter(|w| w.goal.is_some()) {
        println!("goal {:?} at cell {:?} after {:.2} h with {:.0} Wh", w.goal, w.col_row, w.t_s / 3600.0, w.battery_wh);
    }
    Ok(())
}
