//! Sunrise/sunset, local time round trips, daylight under a horizon mask.

use areo_ephemeris::events::{daylight_intervals, solar_day};
use areo_ephemeris::{HorizonMask, MarsTime, Site, SolarGeometry, format_utc, local_sol, parse_utc, utc_at_ltst};

#[test]
fn utc_to_ltst_to_utc_round_trips_under_a_second() {
    let sites =
        [Site::new(-4.5895, 137.4417).unwrap(), Site::new(18.4447, 77.4509).unwrap(), Site::new(-70.0, 300.0).unwrap()];
    for (i, utc) in ["2012-08-06T05:17:57Z", "2021-02-18T20:55:00Z", "2030-06-01T12:00:00Z"].iter().enumerate() {
        let t = parse_utc(utc).unwrap();
        let site = &sites[i];
        let ltst = MarsTime::from_epoch(t).ltst_hours(site.lon_east_deg());
        // Search the sol containing t and its neighbours (EOT can shift LTST across a
        // mean-sol boundary).
        let sol = local_sol(t, site);
        let best = (sol - 1..=sol + 1)
            .map(|s| (utc_at_ltst(s, site, ltst).unwrap() - t).to_seconds().abs())
            .fold(f64::MAX, f64::min);
        assert!(best < 1.0, "{utc}: round trip off by {best} s");
    }
}

#[test]
fn curiosity_landed_in_the_afternoon() {
    // Curiosity landed at about 15:00 local mean solar time at Gale (NASA: "~3 p.m.").
    let t = parse_utc("2012-08-06T05:17:57Z").unwrap();
    let lmst = MarsTime::from_epoch(t).lmst_hours(137.4417);
    assert!((lmst - 14.8).abs() < 0.5, "LMST {lmst}");
    // Perseverance landed at about 15:53 LMST at Jezero.
    let t = parse_utc("2021-02-18T20:55:00Z").unwrap();
    let lmst = MarsTime::from_epoch(t).lmst_hours(77.4509);
    assert!((lmst - 15.9).abs() < 0.3, "LMST {lmst}");
}

#[test]
fn sunrise_and_sunset_bracket_noon_and_summer_days_are_longest() {
    let site = Site::new(45.0, 0.0).unwrap();
    let flat = HorizonMask::flat();
    let mut longest = (0.0, 0.0);
    let mut shortest = (f64::MAX, 0.0);
    // One Mars year of sols, every 20 sols.
    let sol0 = local_sol(parse_utc("2022-01-01T00:00:00Z").unwrap(), &site);
    for k in 0..34 {
        let day = solar_day(sol0 + 20 * k, &site, &flat).unwrap();
        let (rise, set) = (day.sunrise.unwrap(), day.sunset.unwrap());
        assert!(rise < day.noon && day.noon < set, "{}", format_utc(day.noon));
        let ls = SolarGeometry::at(day.noon).ls_deg;
        let len = day.daylight_s();
        if len > longest.0 {
            longest = (len, ls);
        }
        if len < shortest.0 {
            shortest = (len, ls);
        }
        // Noon is LTST 12 by construction; check it through the forward path.
        let ltst = MarsTime::from_epoch(day.noon).ltst_hours(0.0);
        assert!((ltst - 12.0).abs() < 1e-4, "LTST at noon {ltst}");
    }
    // Northern summer solstice Ls = 90, winter Ls = 270 (±20 sols ≈ ±10° Ls).
    assert!((longest.1 - 90.0).abs() < 15.0, "longest day at Ls {}", longest.1);
    assert!((shortest.1 - 270.0).abs() < 15.0, "shortest day at Ls {}", shortest.1);
    assert!(longest.0 > 14.0 * 3600.0 && shortest.0 < 10.5 * 3600.0);
}

#[test]
fn equinox_day_at_the_equator_is_half_a_sol() {
    let site = Site::new(0.0, 0.0).unwrap();
    let day =
        solar_day(local_sol(parse_utc("2021-02-07T12:00:00Z").unwrap(), &site), &site, &HorizonMask::flat()).unwrap();
    let half_sol = areo_ephemeris::SOL_S / 2.0;
    assert!((day.daylight_s() - half_sol).abs() < 300.0, "{}", day.daylight_s());
    assert!(day.noon_elevation_deg > 88.0);
}

#[test]
fn a_horizon_mask_shortens_the_day() {
    let site = Site::new(-4.59, 137.44).unwrap();
    let start = parse_utc("2013-01-01T00:00:00Z").unwrap();
    let end = parse_utc("2013-01-04T00:00:00Z").unwrap();
    let open = daylight_intervals(&site, &HorizonMask::flat(), start, end);
    let walled = daylight_intervals(&site, &HorizonMask::new(vec![15.0; 16]).unwrap(), start, end);
    assert_eq!(open.len(), walled.len());
    let total = |v: &[(hifitime::Epoch, hifitime::Epoch)]| v.iter().map(|(a, b)| (*b - *a).to_seconds()).sum::<f64>();
    assert!(total(&walled) < total(&open) - 3.0 * 3600.0);
    for ((a, b), (c, d)) in open.iter().zip(&walled) {
        assert!(a <= c && d <= b);
    }
    // Three Earth days contain about three daylight periods of ~12 h at the equator.
    assert!((3..=4).contains(&open.len()));
}

#[test]
fn bad_inputs_are_errors() {
    assert!(parse_utc("2012-02-30T00:00:00Z").is_err());
    assert!(parse_utc("not a time").is_err());
    let site = Site::new(0.0, 0.0).unwrap();
    assert!(utc_at_ltst(50_000, &site, 25.0).is_err());
    assert!(Site::new(-91.0, 0.0).is_err());
}
