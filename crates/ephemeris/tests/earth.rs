//! Earth as seen from Mars: the Keplerian chain is validated against Mars24.

use areo_ephemeris::earth::{earth_azimuth_elevation_deg, earth_from_mars, sun_direction_keplerian};
use areo_ephemeris::events::earth_visible_intervals;
use areo_ephemeris::{HorizonMask, Mars24, Site, SunModel, parse_utc};

fn angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    d.clamp(-1.0, 1.0).acos().to_degrees()
}

#[test]
fn the_keplerian_chain_reproduces_the_mars24_sun_direction() {
    // Same orbit, pole and prime meridian as the Earth direction: if the Sun agrees with
    // Mars24 to a few hundredths of a degree, the frame chain is right.
    for utc in [
        "1995-03-01T00:00:00Z",
        "2004-01-03T13:46:31Z",
        "2012-08-06T05:17:57Z",
        "2021-02-18T20:55:00Z",
        "2034-11-30T06:00:00Z",
    ] {
        let t = parse_utc(utc).unwrap();
        let err = angle_deg(sun_direction_keplerian(t), Mars24.sun(t).direction_body_fixed);
        assert!(err < 0.1, "{utc}: {err}°");
    }
}

#[test]
fn earth_distance_spans_opposition_and_conjunction() {
    // 2003-08-27: the closest opposition in 60 000 years, 0.3727 AU.
    let opp = earth_from_mars(parse_utc("2003-08-27T10:00:00Z").unwrap());
    assert!((opp.distance_au - 0.3727).abs() < 0.002, "{}", opp.distance_au);
    // Light time follows from the distance.
    assert!((opp.light_time_s - opp.distance_au * 499.004_784).abs() < 1e-6);
    // 2021-10-08: solar conjunction, ~2.6 AU.
    let conj = earth_from_mars(parse_utc("2021-10-08T00:00:00Z").unwrap());
    assert!(conj.distance_au > 2.55 && conj.distance_au < 2.7, "{}", conj.distance_au);
    // At conjunction the Earth sits behind the Sun: within ~1.5° of it from Mars.
    let t = parse_utc("2021-10-08T00:00:00Z").unwrap();
    let sep = angle_deg(conj.direction_body_fixed, Mars24.sun(t).direction_body_fixed);
    assert!(sep < 1.5, "{sep}");
    // At opposition the Earth passes between Mars and the Sun, offset from the Sun only
    // by Mars' heliocentric latitude BH: seen from Mars the gap is ≈ r_E·|BH|/Δ.
    let t = parse_utc("2003-08-28T17:00:00Z").unwrap();
    let e = earth_from_mars(t);
    let sep = angle_deg(e.direction_body_fixed, Mars24.sun(t).direction_body_fixed);
    let bh = areo_ephemeris::SolarGeometry::at(t).heliocentric_lat_deg;
    let r_e = 1.0 - 0.0167 * 0.5; // Earth's heliocentric distance in late August, AU
    let expect = r_e * bh.abs() / e.distance_au;
    assert!((sep - expect).abs() < 0.3, "separation {sep}, expected {expect}");
}

#[test]
fn earth_rises_and_sets_about_once_a_sol() {
    let site = Site::new(-4.59, 137.44).unwrap();
    let start = parse_utc("2013-05-01T00:00:00Z").unwrap();
    let end = parse_utc("2013-05-04T00:00:00Z").unwrap();
    let windows = earth_visible_intervals(&site, &HorizonMask::flat(), start, end);
    assert!((3..=4).contains(&windows.len()), "{}", windows.len());
    for (a, b) in &windows {
        let mid = *a + (*b - *a) * 0.5;
        let (_, el) = earth_azimuth_elevation_deg(mid, &site);
        assert!(el > 0.0);
    }
}
