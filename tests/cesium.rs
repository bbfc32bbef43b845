//! CesiumJS (from npm) loads a run's `route.czml` through the page beside it,
//! `route.cesium.html`, in Debian's headless Chromium, on a Mars, a Moon and an Earth
//! run: the page sets the body's ellipsoid from the file, and the rover is where
//! plan.csv puts it at each of its waypoints' instants, to a metre, in Earth-fixed
//! metres computed here from plan.csv's latitude, longitude and elevation on that body.
//!
//! Needs Chromium and Cesium's `Build/Cesium` folder (`AREO_CESIUM`); `.ci/run`
//! installs both and sets `AREO_REQUIRE_CHROMIUM` and `AREO_REQUIRE_CESIUM`, under which
//! a missing one fails the test. Elsewhere the test says it did not run.

mod small_route;

use std::path::{Path, PathBuf};
use std::process::Command;

use small_route::scenario;

/// Cesium's `Build/Cesium` folder, if Chromium and it are here.
// Saying that the test did not run is the point of its one message.
#[allow(clippy::print_stderr)]
fn cesium_here() -> Option<PathBuf> {
    let chromium = Command::new("chromium").arg("--version").output().is_ok_and(|o| o.status.success());
    let cesium = std::env::var_os("AREO_CESIUM").map(PathBuf::from).filter(|p| p.join("Cesium.js").is_file());
    let required = std::env::var_os("AREO_REQUIRE_CESIUM").is_some();
    match (chromium, cesium) {
        (true, Some(dir)) => Some(dir),
        (c, d) if required => {
            panic!("AREO_REQUIRE_CESIUM is set but chromium runs: {c}, Cesium.js in AREO_CESIUM: {d:?}")
        }
        _ => {
            eprintln!("not run: needs chromium and AREO_CESIUM (Cesium's Build/Cesium); .ci/run installs both");
            None
        }
    }
}

/// A waypoint of plan.csv: its instant (s since 1970) and place.
struct Waypoint {
    unix_s: f64,
    lat_deg: f64,
    lon_deg: f64,
    elevation_m: f64,
}

/// Seconds since 1970 of an ISO 8601 UTC instant `YYYY-MM-DDTHH:MM:SS.sssZ` (the
/// proleptic Gregorian calendar's days, counted from 1 March so that leap days fall last).
fn unix_s(utc: &str) -> f64 {
    let num = |a: usize, b: usize| utc[a..b].parse::<i64>().unwrap();
    let (y, m, d) = (num(0, 4), num(5, 7), num(8, 10));
    let (y, m) = if m <= 2 { (y - 1, m + 9) } else { (y, m - 3) };
    let days = 365 * y + y / 4 - y / 100 + y / 400 + (153 * m + 2) / 5 + d - 1 - 719_468;
    let seconds: f64 = utc[17..utc.len() - 1].parse().unwrap();
    (days * 86_400 + num(11, 13) * 3600 + num(14, 16) * 60) as f64 + seconds
}

fn waypoints(plan: &Path) -> Vec<Waypoint> {
    let text = std::fs::read_to_string(plan).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("{name} in {header:?}"));
    let (utc, lat, lon, z) = (col("utc"), col("lat_deg"), col("lon_deg"), col("elevation_m"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let num = |i: usize| f[i].parse::<f64>().unwrap();
            Waypoint { unix_s: unix_s(f[utc]), lat_deg: num(lat), lon_deg: num(lon), elevation_m: num(z) }
        })
        .collect()
}

/// Earth-fixed metres of a point `h` above the ellipsoid of radii `a` (equatorial) and
/// `b` (polar) at latitude `lat` (geodetic; on a sphere the same as planetocentric) and
/// east longitude `lon`, degrees.
fn earth_fixed(a: f64, b: f64, lat: f64, lon: f64, h: f64) -> [f64; 3] {
    let (lat, lon) = (lat.to_radians(), lon.to_radians());
    let n = a * a / (a * a * lat.cos().powi(2) + b * b * lat.sin().powi(2)).sqrt();
    [(n + h) * lat.cos() * lon.cos(), (n + h) * lat.cos() * lon.sin(), (b * b / (a * a) * n + h) * lat.sin()]
}

/// The page's `#state` after Cesium loaded the CZML and sampled the rover at `instants`.
fn page_state(page: &Path, instants: &[f64]) -> serde_json::Value {
    let wanted: Vec<String> = instants.iter().map(|s| format!("{s}")).collect();
    let url = format!("file://{}#check={}", page.display(), wanted.join(","));
    let o = Command::new("chromium")
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking"])
        .args(["--disable-component-update", "--no-first-run", "--virtual-time-budget=20000", "--dump-dom", &url])
        .output()
        .expect("chromium");
    let dom = String::from_utf8_lossy(&o.stdout);
    let start = dom.find("<pre id=\"state\">").map(|i| i + "<pre id=\"state\">".len());
    let text = start.and_then(|s| dom[s..].find("</pre>").map(|e| &dom[s..s + e])).unwrap_or_default();
    let text = text.replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&");
    serde_json::from_str(&text).unwrap_or_else(|e| {
        panic!("{}: no state ({e}): {text:?}\n{}", page.display(), String::from_utf8_lossy(&o.stderr))
    })
}

#[test]
fn cesium_puts_the_rover_where_the_plan_does_on_mars_the_moon_and_the_earth() {
    let Some(cesium) = cesium_here() else { return };
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target").join("cesium-tests");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let runs = [
        ("mars", "Mars", (-4.6, 137.4), "2012-08-06T20:40:00Z", (3_396_000.0, 3_396_000.0)),
        ("moon", "Moon", (-89.2, 45.0), "2024-03-01T00:00:00Z", (1_737_400.0, 1_737_400.0)),
        ("earth", "Earth", (75.4, -89.8), "2001-07-20T16:00:00Z", (6_378_137.0, 6_378_137.0)),
    ];
    assert_eq!(unix_s("2012-08-06T20:40:00.000Z"), 1_344_285_600.0, "the calendar");
    assert_eq!(unix_s("2024-03-01T00:00:00.500Z"), 1_709_251_200.5, "the calendar");
    for (name, body, site, utc, (a, b)) in runs {
        let path = dir.join(format!("{name}.ron"));
        std::fs::write(&path, scenario(body, site, utc)).unwrap();
        let o = Command::new(env!("CARGO_BIN_EXE_areo"))
            .args(["-q", "run", path.to_str().unwrap(), "--out", dir.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        let out = dir.join(name);
        // Cesium where the page's two lines look for it.
        std::os::unix::fs::symlink(&cesium, out.join("Cesium")).unwrap();
        let plan = waypoints(&out.join("plan.csv"));
        assert!(plan.len() >= 5, "{name}: {} waypoints", plan.len());
        // One longitude convention in every file: plan.csv's are near the site's, in
        // −180..180 as the CZML's and the GeoJSON's (the Earth run's site is at −89.8°,
        // the Moon's 0.8° from the pole, where 2 km span degrees of longitude).
        assert!(plan.iter().all(|w| (w.lon_deg - site.1).abs() < 10.0), "{name}: longitudes off the site's {}", site.1);
        let picked: Vec<&Waypoint> = (0..5).map(|k| &plan[k * (plan.len() - 1) / 4]).collect();
        let state = page_state(&out.join("route.cesium.html"), &picked.iter().map(|w| w.unix_s).collect::<Vec<_>>());
        assert_eq!(state["error"], serde_json::Value::Null, "{name}: {state}");
        assert_eq!(state["body"], body, "{name}: {state}");
        let radii: Vec<f64> = serde_json::from_value(state["radii_m"].clone()).unwrap();
        assert_eq!(radii, [a, a, b], "{name}: the page's ellipsoid");
        let got = state["positions"].as_array().unwrap();
        assert_eq!(got.len(), picked.len(), "{name}: {state}");
        for (w, p) in picked.iter().zip(got) {
            let xyz: Vec<f64> = serde_json::from_value(p["xyz_m"].clone()).unwrap_or_else(|_| panic!("{name}: {p}"));
            let want = earth_fixed(a, b, w.lat_deg, w.lon_deg, w.elevation_m);
            let off = ((xyz[0] - want[0]).powi(2) + (xyz[1] - want[1]).powi(2) + (xyz[2] - want[2]).powi(2)).sqrt();
            assert!(off < 1.0, "{name} at {}: Cesium {xyz:?}, plan.csv {want:?}: {off} m apart", w.unix_s);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
