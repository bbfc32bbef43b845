//! Seasons: Ls cardinal points, perihelion, the sub-solar latitude bounds.

use areo_ephemeris::{SolarGeometry, parse_utc};

fn next_ls(target: f64, from: f64) -> f64 {
    SolarGeometry::next_ls_days(target, from)
}

#[test]
fn cardinal_seasons_are_ordered_and_a_mars_year_apart() {
    let start = parse_utc("2020-01-01T00:00:00Z").unwrap();
    let dt0 = areo_ephemeris::MarsTime::from_epoch(start).days_since_j2000_tt;
    let eq0 = next_ls(0.0, dt0);
    let sol90 = next_ls(90.0, eq0);
    let eq180 = next_ls(180.0, sol90);
    let sol270 = next_ls(270.0, eq180);
    let eq360 = next_ls(0.0, sol270 + 1.0);
    assert!(eq0 < sol90 && sol90 < eq180 && eq180 < sol270 && sol270 < eq360);
    // Tropical Mars year: 686.97 days (Allison & McEwen 2000).
    assert!((eq360 - eq0 - 686.97).abs() < 0.1, "year = {}", eq360 - eq0);
    // Northern spring is the longest season (~194 sols), autumn the shortest (~142).
    let spring = sol90 - eq0;
    let autumn = sol270 - eq180;
    assert!(spring > 195.0 && spring < 201.0, "spring {spring} days");
    assert!(autumn > 144.0 && autumn < 148.0, "autumn {autumn} days");
    // The 2020-2022 northern spring equinox fell on 2021-02-07 (Mars Year 36 begins).
    let my36 = 2_451_545.0 + eq0;
    let feb7_2021 = 2_459_252.5;
    assert!((my36 - feb7_2021).abs() < 1.0, "JD {my36}");
}

#[test]
fn perihelion_is_near_ls_251() {
    let dt0 = 7_000.0;
    let (mut best_dt, mut best_r) = (dt0, f64::MAX);
    let mut dt = dt0;
    while dt < dt0 + 687.0 {
        let r = SolarGeometry::at_days_since_j2000(dt).distance_au;
        if r < best_r {
            best_r = r;
            best_dt = dt;
        }
        dt += 0.25;
    }
    let ls = SolarGeometry::at_days_since_j2000(best_dt).ls_deg;
    assert!((ls - 251.0).abs() < 1.5, "perihelion at Ls {ls}");
    // Perihelion distance a(1 − e) = 1.5237 × (1 − 0.0934) = 1.3814 AU.
    assert!((best_r - 1.3814).abs() < 2e-3, "rH {best_r}");
}

#[test]
fn subsolar_latitude_stays_within_the_obliquity() {
    let mut max = 0.0f64;
    let mut dt = -3650.0;
    while dt < 13_000.0 {
        let g = SolarGeometry::at_days_since_j2000(dt);
        max = max.max(g.subsolar_lat_planetocentric_deg.abs());
        assert!(g.subsolar_lat_planetographic_deg.abs() <= 25.2 + 0.25);
        assert!(g.subsolar_lat_planetocentric_deg.abs() <= 25.2);
        dt += 3.7;
    }
    assert!(max > 25.1, "max {max}");
}
