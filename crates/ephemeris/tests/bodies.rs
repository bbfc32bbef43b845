//! The Moon and the Earth: facts about their skies that any ephemeris must reproduce
//! (the published worked examples are unit tests next to the theories).

use areo_ephemeris::{Body, EarthFrom, Site, SunModel, moon, parse_utc};
use hifitime::Duration;

fn hours(start: &str, n: usize, step_h: f64) -> impl Iterator<Item = hifitime::Epoch> {
    let t0 = parse_utc(start).unwrap();
    (0..n).map(move |k| t0 + Duration::from_seconds(k as f64 * step_h * 3600.0))
}

/// At the lunar south pole the Sun never rises more than the lunar equator's tilt to
/// the ecliptic (1.54°) plus the site's parallax, and the Earth swings by the libration
/// in latitude (±6.85°) over a month.
#[test]
fn at_the_lunar_south_pole_the_sun_skims_the_horizon_and_the_earth_nods() {
    let pole = Site::on(Body::Moon, -89.999, 0.0).unwrap();
    let (mut sun_lo, mut sun_hi, mut earth_lo, mut earth_hi) = (90.0f64, -90.0f64, 90.0f64, -90.0f64);
    for t in hours("2025-01-01T00:00:00Z", 24 * 366, 1.0) {
        let sky = moon::sky(t);
        let sun = sky.sun.at_site(&pole).elevation_deg;
        let (_, earth) = sky.earth.at_site(&pole);
        sun_lo = sun_lo.min(sun);
        sun_hi = sun_hi.max(sun);
        earth_lo = earth_lo.min(earth);
        earth_hi = earth_hi.max(earth);
    }
    assert!(sun_hi > 1.4 && sun_hi < 1.65, "{sun_hi}");
    assert!(sun_lo < -1.4 && sun_lo > -1.65, "{sun_lo}");
    // Libration in latitude reaches ±6.85°; the site's parallax lowers the Earth by
    // a further 0.26° near the horizon.
    assert!(earth_hi > 6.3 && earth_hi < 6.85 - 0.2, "{earth_hi}");
    assert!(earth_lo < -6.85 && earth_lo > -6.85 - 0.3, "{earth_lo}");
}

/// A lunar solar day is a synodic month: the sub-solar longitude comes back after
/// 29.53 days, and local solar time is noon under the Sun.
#[test]
fn a_lunar_day_is_a_synodic_month() {
    let t0 = parse_utc("2025-03-01T00:00:00Z").unwrap();
    let lon = |t| Body::Moon.sun(t).subsolar_deg().1;
    let later = t0 + Duration::from_seconds(Body::Moon.solar_day_s());
    // The synodic month varies by ±7 h around its mean: 0.1° of longitude an hour.
    let d = (lon(later) - lon(t0) + 180.0).rem_euclid(360.0) - 180.0;
    assert!(d.abs() < 1.0, "{d}");
    let half = t0 + Duration::from_seconds(Body::Moon.solar_day_s() / 2.0);
    let d_half = (lon(half) - lon(t0)).rem_euclid(360.0);
    assert!((d_half - 180.0).abs() < 8.0, "{d_half}");
    let s = Body::Moon.sun(t0);
    let (_, sub_lon) = s.subsolar_deg();
    assert!((s.local_solar_time_hours(sub_lon) - 12.0).abs() < 1e-9);
    assert!((s.local_solar_time_hours(sub_lon + 90.0) - 18.0).abs() < 1e-9);
}

/// The Earth is 60 lunar radii away: from a site 90° from the sub-Earth point it sits
/// atan(1737.4 / distance) ≈ 0.26° lower than from the Moon's centre.
#[test]
fn the_earth_seen_from_a_lunar_site_shows_the_sites_parallax() {
    let t = parse_utc("2025-06-01T00:00:00Z").unwrap();
    let earth = Body::Moon.earth(t).unwrap();
    let (lat, lon) = earth.sub_point_deg();
    let below = Site::on(Body::Moon, lat, lon).unwrap();
    assert!(earth.at_site(&below).1 > 89.99);
    let limb = Site::on(Body::Moon, 0.0, lon + 90.0).unwrap();
    let topo = earth.at_site(&limb).1;
    let centre = limb.azimuth_elevation_deg(earth.direction_body_fixed).1;
    let expect = (1_737.4 / earth.distance_km).atan().to_degrees();
    assert!((centre - topo - expect).abs() < 0.01, "{centre} {topo} {expect}");
    assert!(expect > 0.24 && expect < 0.28);
}

/// Devon Island (75.4° N) around the 2001 summer experiment: the Sun never sets, and
/// its azimuth sweeps the whole horizon in a day.
#[test]
fn at_devon_island_in_july_the_sun_circles_without_setting() {
    let devon = Site::on(Body::Earth, 75.43, -89.87).unwrap();
    let mut lowest = 90.0f64;
    let mut octants = [false; 8];
    for t in hours("2001-07-20T00:00:00Z", 24 * 6, 1.0 / 6.0) {
        let p = Body::Earth.sun(t).at_site(&devon);
        lowest = lowest.min(p.elevation_deg);
        octants[(p.azimuth_deg / 45.0) as usize % 8] = true;
    }
    // Midnight Sun: at lower culmination the elevation is δ − (90° − φ) ≈ 20.6° −
    // 14.57° ≈ 6.0° (declination 20.6° on 20 July, falling to 19.5° by the 26th).
    assert!((lowest - 6.0).abs() < 0.3, "{lowest}");
    assert!(octants.iter().all(|&o| o));
}

/// Local noon at Greenwich comes within the equation of time (±16.5 min) of 12:00 UTC,
/// and the Sun's elevation then is 90° − latitude + declination.
#[test]
fn greenwich_noon_follows_the_equation_of_time() {
    let site = Site::on(Body::Earth, 51.4779, 0.0).unwrap();
    // 2025-02-11: the equation of time is about −14.2 min (noon at 12:14 UTC).
    let t = parse_utc("2025-02-11T12:14:12Z").unwrap();
    let s = Body::Earth.sun(t);
    let lst = s.local_solar_time_hours(site.lon_east_deg());
    assert!((lst - 12.0).abs() * 60.0 < 0.6, "{lst}");
    let (dec, _) = s.subsolar_deg();
    let el = s.at_site(&site).elevation_deg;
    assert!((el - (90.0 - 51.4779 + dec)).abs() < 0.02, "{el}");
}
