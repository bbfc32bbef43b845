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

#[test]
fn nights_are_the_complement_of_daylight() {
    use areo_ephemeris::events::night_intervals;
    let site = Site::new(-4.5895, 137.4417).unwrap();
    let flat = HorizonMask::flat();
    let (start, end) = (parse_utc("2025-03-01T00:00:00Z").unwrap(), parse_utc("2025-03-04T00:00:00Z").unwrap());
    let days = daylight_intervals(&site, &flat, start, end);
    let nights = night_intervals(&site, &flat, start, end);
    let total: f64 = days.iter().chain(&nights).map(|(a, b)| (*b - *a).to_seconds()).sum();
    assert!((total - (end - start).to_seconds()).abs() < 1e-3, "{total}");
    // They alternate and touch: every night ends where a day begins.
    for n in &nights {
        assert!(days.iter().any(|d| (d.0 - n.1).to_seconds().abs() < 1e-6) || n.1 == end);
    }
    // Three Earth days near the equator: three or four nights, each 11-14 h unless cut.
    assert!((3..=4).contains(&nights.len()), "{}", nights.len());
    for n in &nights[1..nights.len() - 1] {
        let h = (n.1 - n.0).to_seconds() / 3600.0;
        assert!((11.0..14.0).contains(&h), "{h}");
    }
}

#[test]
fn communication_windows_are_centred_on_the_earths_culmination() {
    use areo_ephemeris::earth::earth_azimuth_elevation_deg;
    use areo_ephemeris::events::communication_windows;
    let site = Site::new(-4.5895, 137.4417).unwrap();
    let start = parse_utc("2025-03-01T00:00:00Z").unwrap();
    let end = start + hifitime::Duration::from_seconds(3.0 * areo_ephemeris::SOL_S);
    let w = communication_windows(&site, start, end, 10.0, 1800.0);
    assert_eq!(w.len(), 3, "{w:?}");
    for (a, b) in &w {
        assert!(((*b - *a).to_seconds() - 1800.0).abs() < 1e-3);
        // The centre is the maximum: a brute-force scan at 10 s around it finds no
        // higher Earth (within the 10 ms tolerance's effect on elevation).
        let mid = *a + hifitime::Duration::from_seconds(900.0);
        let el_mid = earth_azimuth_elevation_deg(mid, &site).1;
        assert!(el_mid >= 10.0);
        for k in -360..=360 {
            let t = mid + hifitime::Duration::from_seconds(10.0 * f64::from(k));
            assert!(earth_azimuth_elevation_deg(t, &site).1 <= el_mid + 1e-6, "higher at {k}");
        }
    }
    // An elevation the Earth never reaches gives no session.
    assert!(communication_windows(&site, start, end, 89.0, 1800.0).is_empty());
}

#[test]
fn impossible_calendar_dates_and_other_scales_are_explained() {
    // 30 February: hifitime's InvalidGregorianDate, said in words (matched by variant).
    let err = parse_utc("2021-02-30T00:00:00Z").unwrap_err().to_string();
    assert!(err.contains("no such calendar date"), "{err}");
    assert!(err.contains("2021-02-30"), "{err}");
    let err = parse_utc("yesterday").unwrap_err().to_string();
    assert!(err.contains("YYYY-MM-DD"), "{err}");
    let err = parse_utc("2021-02-18T20:55:00 TAI").unwrap_err().to_string();
    assert!(err.contains("UTC"), "{err}");
    assert_eq!(format_utc(parse_utc("2021-02-18T20:55:00Z").unwrap()), "2021-02-18T20:55:00.000Z");
    // Outside the ephemeris' years: refused at once, not computed for minutes.
    let err = parse_utc("9999-01-01T00:00:00Z").unwrap_err().to_string();
    assert!(err.contains("1600..=2600"), "{err}");
    let site = Site::new(0.0, 0.0).unwrap();
    let err = utc_at_ltst(-1_000_000_000, &site, 12.0).unwrap_err().to_string();
    assert!(err.contains("sol") && err.contains("-97000..=258000"), "{err}");
    // The bounds are the years': MSD −97000 is in 1600, 258000 in 2600.
    let year = |sol| utc_at_ltst(sol, &site, 12.0).unwrap().to_gregorian_utc().0;
    assert_eq!((year(-97_000), year(258_000)), (1601, 2599));
}
