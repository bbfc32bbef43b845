//! Planning on the Moon: the world's Earth table against the ephemeris, per-cell Earth
//! visibility against a brute-force ray march over the DEM, and Communicate sessions
//! that need the Earth in view.

use areo_ephemeris::flux::Atmosphere;
use areo_ephemeris::{Body, EarthFrom, Site, parse_utc};
use areo_mission::{Action, ActionModel, Binding, Mission, PlannerConfig, Start, World, WorldConfig, curvature_of};
use areo_terrain::Dem;
use hifitime::{Duration, Epoch};

use crate::common::{quantised_actions, rover};

fn site() -> Site {
    Site::on(Body::Moon, -89.3, 45.0).unwrap()
}

/// The first hour of 2025 at which the Earth stands 3–5° over the site.
fn epoch() -> Epoch {
    let t0 = parse_utc("2025-01-01T00:00:00Z").unwrap();
    (0..24 * 60)
        .map(|h| t0 + Duration::from_seconds(h as f64 * 3600.0))
        .find(|&t| (3.0..5.0).contains(&Body::Moon.earth(t).unwrap().at_site(&site()).1))
        .expect("the Earth rises 3–5° over the site in January–February 2025")
}

/// How far a point lies toward the Earth from the map's centre, m.
fn toward_earth(x: f64, y: f64, earth_az_deg: f64) -> f64 {
    let (s, c) = earth_az_deg.to_radians().sin_cos();
    (x - 600.0) * s + (y - 600.0) * c
}

/// 60 × 60 cells of 20 m with a ridge 20 m high across the Earth's direction, 200 m
/// toward the Earth from the map's centre.
fn ridge(earth_az_deg: f64) -> Dem {
    Dem::from_fn(60, 60, 20.0, 20.0, |x, y| 20.0 * (-((toward_earth(x, y, earth_az_deg) - 200.0) / 30.0).powi(2)).exp())
        .unwrap()
}

fn lunar_world(dem: Dem, epoch: Epoch, span_h: f64) -> World {
    let config = WorldConfig {
        epoch,
        span_s: span_h * 3600.0,
        sun_step_s: 600.0,
        horizon_sectors: Some(360),
        atmosphere: Atmosphere::Airless,
        site: Some(site()),
    };
    World::new(dem, &config, &Body::Moon).unwrap()
}

#[test]
fn the_worlds_earth_is_the_ephemeris_earth_at_the_site() {
    let t0 = epoch();
    let world = lunar_world(ridge(0.0), t0, 12.0);
    assert_eq!(world.body(), Body::Moon);
    // Horizon maps drop away on each body's IAU mean sphere.
    let sphere = |radius_m| areo_terrain::shadow::Curvature::Sphere { radius_m };
    assert_eq!(curvature_of(Body::Moon), sphere(1_737_400.0));
    assert_eq!(curvature_of(Body::Mars), sphere(3_389_500.0));
    assert_eq!(curvature_of(Body::Earth), sphere(6_371_008.8));
    for t in [0.0, 1234.0, 7777.0, 40_000.0] {
        let e = world.earth(t).unwrap();
        let (az, el) = Body::Moon.earth(t0 + Duration::from_seconds(t)).unwrap().at_site(&site());
        let daz = ((e.azimuth_deg - az + 180.0).rem_euclid(360.0) - 180.0) * el.to_radians().cos();
        assert!(daz.abs() < 0.01 && (e.elevation_deg - el).abs() < 0.01, "t {t}: {e:?} vs ({az}, {el})");
    }
}

/// The horizon toward the Earth by marching along the ray over the bilinear surface
/// (a step of a quarter cell) with the Moon's curvature drop d²/2R, and how far the ray
/// runs on the map.
fn brute_horizon_deg(dem: &Dem, x0: f64, y0: f64, az_deg: f64) -> (f64, f64) {
    let (s, c) = az_deg.to_radians().sin_cos();
    let z0 = dem.height(x0, y0).unwrap();
    // The Moon's mean radius (IAU), independent of the planner's curvature.
    let radius_m = 1_737_400.0;
    let mut best = f64::NEG_INFINITY;
    let mut d = 5.0;
    while let Some(z) = dem.height(x0 + d * s, y0 + d * c) {
        best = best.max(((z - z0 - d * d / (2.0 * radius_m)) / d).atan().to_degrees());
        d += 5.0;
    }
    (best, d)
}

#[test]
fn earth_visibility_matches_a_ray_march_toward_the_earth() {
    let t0 = epoch();
    let earth = Body::Moon.earth(t0).unwrap().at_site(&site());
    let dem = ridge(earth.0);
    let world = lunar_world(dem.clone(), t0, 2.0);
    let e = world.earth(0.0).unwrap();
    let (mut visible, mut hidden, mut close) = (0, 0, 0);
    for cell in 0..world.cells() as u32 {
        let (x, y) = world.center(cell);
        let (brute, run) = brute_horizon_deg(&dem, x, y, e.azimuth_deg);
        // Where the ray leaves the map before it has crossed the ridge, the sweep's
        // edge handling and the ray march see different parts of the flank; within
        // three cells of the crest the sweep's samples (cell centres) and the ray's
        // (the bilinear surface) see different crests. Both are skipped.
        let ahead = toward_earth(x, y, e.azimuth_deg);
        if run < 60.0 || (ahead < 260.0 && run < 260.0 - ahead) || (ahead - 200.0).abs() < 60.0 {
            continue;
        }
        let brute = brute.max(0.0);
        // The sweep samples the terrain at cell centres and interpolates between
        // sectors: next to the ridge, where the horizon climbs steeply, it differs from
        // the ray march by up to ~0.6°. Cells that close to the Earth's elevation are
        // not counted.
        if (e.elevation_deg - brute).abs() < 0.75 {
            close += 1;
            continue;
        }
        let expect = e.elevation_deg > brute;
        assert_eq!(world.earth_visible(cell, 0.0), expect, "cell {cell} at ({x}, {y}): brute horizon {brute}");
        if expect {
            visible += 1;
        } else {
            hidden += 1;
        }
    }
    assert!(visible > 1000 && hidden > 300, "visible {visible}, hidden {hidden}, close {close}");
    // The band behind the ridge where it stands within 0.75° of the Earth: wide, as
    // the ridge sinks slowly with distance.
    assert!(close < 600, "{close}");
}

#[test]
fn a_session_that_needs_the_earth_sends_the_rover_out_of_the_ridges_radio_shadow() {
    let t0 = epoch();
    let earth = Body::Moon.earth(t0).unwrap().at_site(&site());
    let world = lunar_world(ridge(earth.0), t0, 6.0);
    // A hidden cell just behind the ridge (as seen from the Earth) and a visible one
    // far enough back that the ridge sits lower than the Earth.
    let (s, c) = earth.0.to_radians().sin_cos();
    let at = |d: f64, side: f64| world.cell_at(600.0 + d * s + side * c, 600.0 + d * c - side * s).unwrap();
    let hidden = at(150.0, 0.0);
    let visible = at(-350.0, 0.0);
    assert!(!world.earth_visible(hidden, 0.0) && world.earth_visible(visible, 0.0));
    let mut lunar = rover(1e5);
    lunar.locomotor.gravity_m_s2 = Some(Body::Moon.surface_gravity_m_s2());
    let session = (1200.0, 3000.0);
    let talking = ActionModel::new(lunar.clone(), quantised_actions(600.0)).with_sessions(vec![session]);
    let needs_earth = talking.clone().sessions_need_earth(true);
    assert!(talking.stay(&world, Action::Hibernate, hidden, 1200.0).is_ok());
    assert_eq!(needs_earth.stay(&world, Action::Hibernate, hidden, 1200.0).unwrap_err(), Binding::EarthHidden);
    assert!(needs_earth.stay(&world, Action::Hibernate, visible, 1200.0).is_ok());
    // From behind the ridge to another hidden cell 400 m along it: without the Earth
    // constraint the rover waits out the session where it is; with it, it must stand
    // in the Earth's view for the whole session.
    let start = Start { cell: hidden, t_min: 0.0, t_max: 0.0, energy_wh: 5e4 };
    let goal = at(150.0, 400.0);
    let config = PlannerConfig::default();
    let (_m, free) = Mission::plan(&world, &talking, config.clone(), start, &[goal]).unwrap();
    let (_m, plan) = Mission::plan(&world, &needs_earth, config, start, &[goal]).unwrap();
    let during = |p: &areo_mission::MissionPlan| {
        p.waypoints
            .windows(2)
            .filter(|w| w[0].t_s < session.1 && w[1].t_s > session.0)
            .map(|w| (w[0].cell, w[0].action))
            .collect::<Vec<_>>()
    };
    assert!(during(&free).iter().any(|&(cell, _)| !world.earth_visible(cell, session.0)));
    let held = during(&plan);
    assert!(!held.is_empty());
    for (cell, action) in held {
        assert!(!matches!(action, Some(Action::Drive(_))), "a drive across the session");
        for k in 0..=6 {
            let t = session.0 + (session.1 - session.0) * k as f64 / 6.0;
            assert!(world.earth_visible(cell, t), "cell {cell} hides the Earth at {t}");
        }
    }
    assert!(plan.waypoints.iter().any(|w| w.earth_in_view));
}

/// The same check on real terrain: the MOLA crop of Gale crater (a 4 km relief across
/// 30 km, Mount Sharp's flank), with the Earth seen from Mars 8–12° up, where the
/// crater's walls and the mountain hide it from part of the map.
#[test]
fn earth_visibility_on_the_gale_mola_crop_matches_a_ray_march() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../terrain/tests/data/gale_mola_crop_64.tif");
    let dem = areo_terrain::read(&path).unwrap();
    let (x, y) = dem.cell_center(32, 32);
    let (lat, lon) = dem.geographic(x, y).unwrap();
    let site = Site::new(lat, lon).unwrap();
    let t0 = parse_utc("2025-03-01T00:00:00Z").unwrap();
    let epoch = (0..24 * 30 * 4)
        .map(|q| t0 + Duration::from_seconds(q as f64 * 900.0))
        .find(|&t| (8.0..12.0).contains(&Body::Mars.earth(t).unwrap().at_site(&site).1))
        .expect("the Earth crosses 8–12° over Gale within a month");
    let config = WorldConfig {
        epoch,
        span_s: 3600.0,
        sun_step_s: 600.0,
        horizon_sectors: Some(360),
        atmosphere: Atmosphere::BeerLambert { tau: 0.5 },
        site: Some(site),
    };
    let world = World::new(dem.clone(), &config, &Body::Mars).unwrap();
    let e = world.earth(0.0).unwrap();
    // Mars's mean radius (IAU 2015), independent of the planner's curvature.
    let radius_m = 3_389_500.0;
    let (s, c) = e.azimuth_deg.to_radians().sin_cos();
    let (mut visible, mut hidden, mut close) = (0, 0, 0);
    for cell in 0..world.cells() as u32 {
        let (x0, y0) = world.center(cell);
        let z0 = dem.height(x0, y0).unwrap();
        // March a quarter cell at a time to the map's edge.
        let (mut best, mut d) = (f64::NEG_INFINITY, 115.0);
        while let Some(z) = dem.height(x0 + d * s, y0 + d * c) {
            best = best.max(((z - z0 - d * d / (2.0 * radius_m)) / d).atan().to_degrees());
            d += 115.0;
        }
        // Rays shorter than three cells see too little to compare; the sweep's
        // cell-centre samples and the ray's bilinear surface differ by up to ~1° on
        // this rough ground, so cells that close to the Earth's elevation are skipped.
        if d < 1400.0 || (e.elevation_deg - best.max(0.0)).abs() < 1.0 {
            close += 1;
            continue;
        }
        let expect = e.elevation_deg > best.max(0.0);
        assert_eq!(world.earth_visible(cell, 0.0), expect, "cell {cell}: ray-march horizon {best:.2}°, Earth {e:?}");
        if expect {
            visible += 1;
        } else {
            hidden += 1;
        }
    }
    // 3576 visible, 212 hidden, 308 skipped.
    assert!(visible > 3000 && hidden > 150 && close < 400, "visible {visible}, hidden {hidden}, skipped {close}");
}

/// The local sol counts local midnights: over four sols sampled every 10 minutes it
/// steps by one exactly where the local solar time wraps past 24 h, and nowhere else.
#[test]
fn local_sol_steps_where_local_solar_time_wraps() {
    let world = crate::common::mars_world(crate::common::flat(4, 4, 10.0), 100.0, None);
    let lon = 137.4;
    assert_eq!(world.local_sol(0.0, lon), 0);
    let (mut sol, mut ltst) = (0, world.local_solar_time_h(0.0, lon));
    let mut wraps = 0;
    for k in 1..=(4.0 * areo_ephemeris::Body::Mars.solar_day_s() / 600.0) as usize {
        let t = 600.0 * k as f64;
        let (s, l) = (world.local_sol(t, lon), world.local_solar_time_h(t, lon));
        let wrapped = l < ltst;
        wraps += usize::from(wrapped);
        assert_eq!(s, sol + i64::from(wrapped), "t = {t} s: LTST {ltst} → {l} h, sol {sol} → {s}");
        (sol, ltst) = (s, l);
    }
    assert_eq!((wraps, sol), (4, 4));
}
