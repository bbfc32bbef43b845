//! A GIS reads areo's routes and map layers as lying on the right body. GDAL's tools
//! (Debian's `gdal-bin`, which `.ci/run` installs) name the CRS of a Mars, a Moon and an
//! Earth route.geojson; the initial plan's length that OGR measures in a metric
//! projection on that body equals areo's own within 0.5 % (on the Earth's CRS a route
//! on Mars would measure about twice as long); the DEM, slope and shadow GeoTIFFs name
//! the body's sphere and metres, and GDAL places the start cell where the route starts;
//! the WKT a map's CRS is given as (`Georef::wkt`, Python's `Dem.crs`) reads as its
//! projection on its body.
//! Without GDAL the test fails where `AREO_REQUIRE_GDAL` is set (CI) and says it did not
//! run otherwise.

mod small_route;

use std::path::{Path, PathBuf};
use std::process::Command;

use small_route::scenario;

use areo_scenario::Body;

fn areo(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_areo")).args(args).output().expect("run areo")
}

fn tool(name: &str, args: &[&str]) -> String {
    let out = Command::new(name).args(args).output().unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(out.status.success(), "{name} {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn number(facts: &serde_json::Value, name: &str) -> f64 {
    facts[name].as_f64().unwrap_or_else(|| panic!("fact {name}: {}", facts[name]))
}

/// Whether GDAL's `tool` runs here; without it the test fails where `AREO_REQUIRE_GDAL`
/// is set (CI) and says it did not run otherwise.
// Saying that the test did not run is the point of its one message.
#[allow(clippy::print_stderr)]
fn gdal_here(tool: &str) -> bool {
    match Command::new(tool).arg("--version").output() {
        Ok(_) => true,
        Err(e) if std::env::var_os("AREO_REQUIRE_GDAL").is_some() => {
            panic!("AREO_REQUIRE_GDAL is set but {tool} cannot run: {e}")
        }
        Err(e) => {
            eprintln!("not run: no GDAL here ({e}); .ci/run installs gdal-bin and requires it");
            false
        }
    }
}

#[test]
fn gdal_reads_each_route_on_its_own_body_at_its_own_length() {
    if !gdal_here("ogrinfo") {
        return;
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target").join("gis-test");
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    // Every file of a run names one geographic CRS: the sphere the map is projected on
    // (the synthesised Mars map sits on the MOLA sphere, 3 396 000 m, not the IAU's
    // 3 396 190 m; the Earth's on WGS 84's equatorial radius).
    let cases = [
        (
            "Mars",
            Body::Mars,
            (-4.5895, 137.4417),
            "2012-08-06T16:00:00Z",
            ("Mars - Sphere, R = 3396000 m / Ocentric", 3_396_000.0),
        ),
        ("Moon", Body::Moon, (-20.0, 10.0), "2025-01-10T00:00:00Z", ("Moon (2015) - Sphere / Ocentric", 1_737_400.0)),
        (
            "Earth",
            Body::Earth,
            (75.43, -89.87),
            "2025-06-21T12:00:00Z",
            ("Earth - Sphere, R = 6378137 m / Ocentric", 6_378_137.0),
        ),
    ];
    for (name, body, site, utc, (crs, radius)) in cases {
        let path = root.join(format!("{}.ron", name.to_lowercase()));
        std::fs::write(&path, scenario(name, site, utc)).unwrap();
        let out = areo(&["run", path.to_str().unwrap(), "--out", root.to_str().unwrap()]);
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        let dir = root.join(name.to_lowercase());
        let route = dir.join("route.geojson");
        let info = tool("ogrinfo", &["-so", "-al", route.to_str().unwrap()]);
        assert!(info.contains(&format!("GEOGCRS[\"{crs}\"")), "{name}: {info}");

        // OGR's length of the initial plan in an equidistant projection on the body's
        // sphere, centred at the site.
        let metric = dir.join("route-metric.geojson");
        assert!((radius - body.ellipsoid().equatorial_radius_m).abs() < 200.0, "{name}");
        let projection = format!("+proj=eqc +lat_ts={} +lon_0={} +R={radius} +units=m +no_defs", site.0, site.1);
        tool("ogr2ogr", &["-t_srs", &projection, metric.to_str().unwrap(), route.to_str().unwrap()]);
        let sql = "SELECT ST_Length(geometry) AS len FROM route WHERE name = 'initial plan'";
        let lengths = tool("ogrinfo", &["-dialect", "SQLite", "-sql", sql, metric.to_str().unwrap()]);
        let ogr: f64 = lengths
            .lines()
            .find_map(|l| l.trim().strip_prefix("len (Real) = "))
            .and_then(|v| v.trim().parse().ok())
            .unwrap_or_else(|| panic!("{name}: no length in {lengths}"));
        let geojson: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&route).unwrap()).unwrap();
        let named = geojson["crs"]["properties"]["name"].as_str().unwrap_or_default().to_string();
        layers_lie_under_the_route(name, &dir, &route, (crs, &named));
        every_file_names_one_crs(name, &dir, (crs, radius), site.1);
        // The KML (always WGS 84 to GDAL, as KML is; Google Earth reads the hint) holds
        // the plan's line, the start and the goal.
        let kml = tool("ogrinfo", &["-so", "-al", dir.join("route.kml").to_str().unwrap()]);
        assert!(kml.contains("Feature Count: 3"), "{name}: {kml}");

        let facts: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("facts.json")).unwrap()).unwrap();
        let own = number(&facts, "initial_plan_distance_m");
        assert!(own > 1000.0, "{name}: a plan of {own} m");
        assert!((ogr - own).abs() <= 0.005 * own, "{name}: OGR measures {ogr} m, areo {own} m");
    }
}

/// The DEM, slope and shadow GeoTIFFs name the body's sphere and metres, their grid is
/// the scenario's (30 m cells), and GDAL puts the start cell's centre (map metres
/// (105, 405) on a 40-row map: pixel (3.5, 26.5)) where the route's first point is.
fn layers_lie_under_the_route(
    name: &str,
    dir: &std::path::Path,
    route: &std::path::Path,
    (gcs, geographic): (&str, &str),
) {
    for layer in ["dem.tif", "slope.tif", "direct_sun.tif"] {
        let path = dir.join(layer);
        let info: serde_json::Value =
            serde_json::from_str(&tool("gdalinfo", &["-json", path.to_str().unwrap()])).unwrap();
        let wkt = info["coordinateSystem"]["wkt"].as_str().unwrap_or_default();
        assert!(wkt.contains(&format!("BASEGEOGCRS[\"{gcs}\"")), "{name} {layer}: {wkt}");
        assert!(wkt.contains("LENGTHUNIT[\"metre\",1"), "{name} {layer}: {wkt}");
        let gt: Vec<f64> = serde_json::from_value(info["geoTransform"].clone()).unwrap();
        assert_eq!((gt[1], gt[2], gt[4], gt[5]), (30.0, 0.0, 0.0, -30.0), "{name} {layer}");
        assert_eq!(info["size"], serde_json::json!([60, 40]), "{name} {layer}");
        // A Cloud-Optimized GeoTIFF, as GDAL reads it and as GDAL's validator finds it.
        assert_eq!(info["metadata"]["IMAGE_STRUCTURE"]["LAYOUT"], "COG", "{name} {layer}: {}", info["metadata"]);
        cog_validator_accepts(&path);
        // A map smaller than a tile is one tile of its size, rounded up to 16 pixels.
        assert_eq!(info["bands"][0]["block"], serde_json::json!([64, 64]), "{name} {layer}");
    }
    let shadow: serde_json::Value =
        serde_json::from_str(&tool("gdalinfo", &["-json", dir.join("direct_sun.tif").to_str().unwrap()])).unwrap();
    assert_eq!(shadow["bands"][0]["noDataValue"], 255.0, "{name}");
    bands_say_what_they_hold(name, dir, &shadow);

    let mut transform = Command::new("gdaltransform")
        .args(["-t_srs", geographic, dir.join("dem.tif").to_str().unwrap()])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("gdaltransform");
    std::io::Write::write_all(&mut transform.stdin.take().unwrap(), b"3.5 26.5\n").unwrap();
    let out = String::from_utf8(transform.wait_with_output().unwrap().stdout).unwrap();
    let lon_lat: Vec<f64> = out.split_whitespace().take(2).map(|v| v.parse().unwrap()).collect();
    let geojson: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(route).unwrap()).unwrap();
    let first = &geojson["features"][0]["geometry"]["coordinates"][0];
    let (lon, lat) = (first[0].as_f64().unwrap(), first[1].as_f64().unwrap());
    assert!(
        (lon_lat[0] - lon).abs() < 1e-9 && (lon_lat[1] - lat).abs() < 1e-9,
        "{name}: GDAL {out}, route ({lon}, {lat})"
    );
}

/// Every file of a run names the same geographic CRS, sphere and longitude convention,
/// as each file's reader takes it: GDAL for the GeoTIFFs, both GeoJSONs and plan.csv
/// (through its `.prj`), the XML for the KML's data, the JSON for the CZML and the STAC
/// items; every longitude in −180..180 and near the site's (`lon`: a 0..360 file on the
/// Earth's west would read 270).
fn every_file_names_one_crs(name: &str, dir: &Path, (crs, radius): (&str, f64), lon: f64) {
    let p = |f: &str| dir.join(f).to_str().unwrap().to_string();
    let near =
        |what: &str, l: f64| assert!((-180.0..=180.0).contains(&l) && (l - lon).abs() < 5.0, "{name} {what}: {l}");
    for layer in ["dem.tif", "slope.tif", "direct_sun.tif", "route.geojson", "route_time.geojson"] {
        let proj = tool("gdalsrsinfo", &["-o", "proj4", &p(layer)]);
        assert!(proj.contains(&format!("+R={radius} ")), "{name} {layer}: {proj}");
        // A map's central meridian is a longitude too.
        if let Some(lon_0) = proj.split_whitespace().find_map(|w| w.strip_prefix("+lon_0=")) {
            near(layer, lon_0.parse().unwrap());
        }
    }
    let csv = ["-so", "-oo", "X_POSSIBLE_NAMES=lon_deg", "-oo", "Y_POSSIBLE_NAMES=lat_deg", &p("plan.csv"), "plan"];
    let info = tool("ogrinfo", &csv);
    assert!(info.contains(&format!("GEOGCRS[\"{crs}\"")) && info.contains(&format!(",{radius},0,")), "{name}: {info}");
    let near =
        |what: &str, l: f64| assert!((-180.0..=180.0).contains(&l) && (l - lon).abs() < 5.0, "{name} {what}: {l}");
    let extent = info.lines().find_map(|l| l.strip_prefix("Extent: (")).unwrap_or_else(|| panic!("{name}: {info}"));
    near("plan.csv", extent.split(',').next().unwrap().trim().parse().unwrap());

    let kml_text = std::fs::read_to_string(p("route.kml")).unwrap();
    let kml = roxmltree::Document::parse(&kml_text).unwrap();
    let data = |key: &str| {
        let d = kml.descendants().find(|n| n.has_tag_name("Data") && n.attribute("name") == Some(key));
        d.and_then(|d| d.descendants().find(|n| n.has_tag_name("value"))).and_then(|v| v.text()).unwrap_or_default()
    };
    assert_eq!((data("crs_name"), data("radius_m").parse::<f64>().ok()), (crs, Some(radius)), "{name}: route.kml");
    for c in kml.descendants().filter(|n| n.has_tag_name("coordinates")) {
        for pair in c.text().unwrap_or_default().split_whitespace() {
            near("route.kml", pair.split(',').next().unwrap().parse().unwrap());
        }
    }
    let json =
        |f: &str| -> serde_json::Value { serde_json::from_str(&std::fs::read_to_string(p(f)).unwrap()).unwrap() };
    let czml = json("route.czml");
    let body = &czml[0]["properties"]["body"];
    assert_eq!(body["crs_name"], crs, "{name}: route.czml");
    assert_eq!((body["equatorial_radius_m"].as_f64(), body["polar_radius_m"].as_f64()), (Some(radius), Some(radius)));
    assert_eq!(czml[0]["properties"]["crs"], json("route.geojson")["crs"], "{name}: CZML and GeoJSON");
    let rover = czml.as_array().unwrap().iter().find(|p| p["id"] == "rover").unwrap();
    for k in rover["position"]["cartographicDegrees"].as_array().unwrap().chunks(4) {
        near("route.czml", k[1].as_f64().unwrap());
    }
    let item = json("shadows/direct_sun_000.json");
    let wkt = item["properties"]["proj:wkt2"].as_str().unwrap_or_default();
    assert!(wkt.contains(&format!("BASEGEOGCRS[\"{crs}\"")), "{name}: STAC item {wkt}");
    for corner in item["geometry"]["coordinates"][0].as_array().unwrap() {
        near("the STAC footprint", corner[0].as_f64().unwrap());
    }
}

/// GDAL's COG validator (`validate_cloud_optimized_geotiff.py` from Debian's
/// python3-gdal, which `.ci/gdal-up` installs) accepts `path`, its full check included
/// (every tile's data where the index says).
fn cog_validator_accepts(path: &Path) {
    let out = Command::new("/usr/bin/python3")
        .args(["-m", "osgeo_utils.samples.validate_cloud_optimized_geotiff", "--full-check=yes"])
        .arg(path)
        .output()
        .unwrap_or_else(|e| panic!("GDAL's COG validator: {e}"));
    let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success() && said.contains("is a valid cloud optimized GeoTIFF"), "{}: {said}", path.display());
}

/// Each layer's band names what it holds and its unit, as GDAL reads them; the direct
/// sun's codes have a colour table (1 drawn yellow, 0 dark).
fn bands_say_what_they_hold(name: &str, dir: &Path, shadow: &serde_json::Value) {
    for (layer, unit, words) in [("dem.tif", "m", "elevation"), ("slope.tif", "degree", "slope")] {
        let info: serde_json::Value =
            serde_json::from_str(&tool("gdalinfo", &["-json", dir.join(layer).to_str().unwrap()])).unwrap();
        let band = &info["bands"][0];
        assert_eq!(band["unit"], unit, "{name} {layer}: {band}");
        assert!(band["description"].as_str().unwrap_or_default().contains(words), "{name} {layer}: {band}");
    }
    let band = &shadow["bands"][0];
    assert!(band["description"].as_str().unwrap_or_default().contains("direct sun"), "{name}: {band}");
    assert_eq!(band["colorInterpretation"], "Palette", "{name}: {band}");
    let entries = band["colorTable"]["entries"].as_array().unwrap();
    assert_eq!(entries.len(), 256, "{name}");
    assert_eq!(entries[1], serde_json::json!([250, 214, 92, 255]), "{name}");
    assert_eq!(entries[0], serde_json::json!([40, 44, 72, 255]), "{name}");
}

/// A terrain preview PNG lies where its GeoTIFF does: GDAL reads its world file (.pgw)
/// into the same geotransform.
#[test]
fn gdal_places_a_preview_png_over_its_geotiff() {
    if !gdal_here("gdalinfo") {
        return;
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = root.join("target").join("gis-test-pgw");
    std::fs::create_dir_all(&dir).unwrap();
    let dem = root.join("crates/terrain/tests/data/gale_mola_crop_64.tif");
    let tif = dir.join("slope.tif");
    let out = areo(&["terrain", "slope", dem.to_str().unwrap(), "-o", tif.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let transform = |path: &std::path::Path| -> Vec<f64> {
        let info: serde_json::Value =
            serde_json::from_str(&tool("gdalinfo", &["-json", path.to_str().unwrap()])).unwrap();
        serde_json::from_value(info["geoTransform"].clone()).unwrap_or_else(|_| panic!("{}: {info}", path.display()))
    };
    let (from_tif, from_png) = (transform(&tif), transform(&dir.join("slope.png")));
    for (a, b) in from_tif.iter().zip(&from_png) {
        assert!((a - b).abs() < 1e-6, "{from_tif:?} vs {from_png:?}");
    }
}

#[test]
fn gdal_reads_each_maps_wkt_as_its_projection_on_its_body() {
    // `Georef::wkt` (what areo's Python `Dem.crs` gives): GDAL must read each as the
    // projection, sphere and parameters areo projects with.
    use areo_scenario::terrain::{Georef, Projection, Spheroid};
    if !gdal_here("gdalsrsinfo") {
        return;
    }
    let cases = [
        (
            Georef {
                projection: Projection::Equirectangular { lat_ts_deg: -5.40234375, lon0_deg: 0.0 },
                surface: Spheroid::MARS_MOLA_SPHERE,
            },
            vec!["+proj=eqc", "+lat_ts=-5.40234375", "+lon_0=0", "+R=3396000"],
        ),
        (
            Georef {
                projection: Projection::PolarStereographic { north: false, lon0_deg: 0.0 },
                surface: Spheroid::MOON,
            },
            vec!["+proj=stere", "+lat_0=-90", "+k=1", "+R=1737400"],
        ),
        (
            Georef {
                projection: Projection::PolarStereographic { north: true, lon0_deg: -45.0 },
                surface: Spheroid::MARS_IAU2015,
            },
            vec!["+proj=stere", "+lat_0=90", "+lon_0=-45", "+R=3396190"],
        ),
        (
            Georef {
                projection: Projection::Equirectangular { lat_ts_deg: 75.4, lon0_deg: 270.2 },
                surface: Spheroid::EARTH_WGS84,
            },
            vec!["+proj=eqc", "+lat_ts=75.4", "+lon_0=-89.8", "+R=6378137"],
        ),
    ];
    for (georef, expect) in cases {
        let proj = tool("gdalsrsinfo", &["-o", "proj4", &georef.wkt()]);
        for e in expect {
            assert!(proj.split_whitespace().any(|w| w == e), "{e} not in {proj} for {georef:?}");
        }
    }
    let local = Georef { projection: Projection::Local, surface: Spheroid::MARS_IAU2015 };
    let wkt = tool("gdalsrsinfo", &["-o", "wkt2", &local.wkt()]);
    assert!(wkt.contains("ENGCRS") && wkt.contains("metre"), "{wkt}");
}

/// A map larger than a tile is written with overviews, halving until one tile holds it,
/// and GDAL reads the full image and each overview (a 600 × 450-cell synthesised map).
#[test]
fn gdal_reads_a_large_layer_as_a_cog_with_its_overviews() {
    if !gdal_here("gdalinfo") {
        return;
    }
    let dir = std::env::temp_dir().join(format!("areo-gis-cog-{}", std::process::id()));
    // Starting at dawn (local true solar time about 6.5 h), so that the Sun is low and
    // the hill casts shadows.
    let text = scenario("Mars", (-4.6, 137.4), "2012-08-06T20:40:00Z")
        .replace("cols: 60, rows: 40", "cols: 600, rows: 450")
        .replace("(name: \"east\", x_m: 1665, y_m: 825)", "(name: \"east\", x_m: 1665, y_m: 405)")
        .replace("horizon_h: 12,", "horizon_h: 12, sun_step_min: 4, shadow_utc: \"2012-08-06T21:40:00Z\",");
    let path = dir.join("big.ron");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(&path, text).unwrap();
    let out = areo(&["-q", "run", path.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let info: serde_json::Value =
        serde_json::from_str(&tool("gdalinfo", &["-json", dir.join("big/dem.tif").to_str().unwrap()])).unwrap();
    assert_eq!(info["metadata"]["IMAGE_STRUCTURE"]["LAYOUT"], "COG");
    // Tiles and overviews in the order the validator wants.
    cog_validator_accepts(&dir.join("big/dem.tif"));
    cog_validator_accepts(&dir.join("big/slope.tif"));
    assert_eq!(info["size"], serde_json::json!([600, 450]));
    let overviews: Vec<serde_json::Value> =
        info["bands"][0]["overviews"].as_array().unwrap().iter().map(|o| o["size"].clone()).collect();
    assert_eq!(overviews, [serde_json::json!([300, 225]), serde_json::json!([150, 113])]);
    assert_eq!(info["bands"][0]["block"], serde_json::json!([256, 256]));
    // The direct sun through the run: COGs listed with their instants.
    let folder = dir.join("big/shadows");
    let index: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("index.json")).unwrap()).unwrap();
    let entries = index.as_array().unwrap();
    assert!(entries.len() >= 2, "{} frames", entries.len());
    let times: Vec<f64> = entries.iter().map(|e| e["unix_s"].as_f64().unwrap()).collect();
    // Instants of the Sun table (every 4 minutes from the start), evenly spaced, from
    // the last at or before the run's first instant to the first at or after its last.
    let start = 1_344_285_600.0; // 2012-08-06T20:40:00Z
    let plan = std::fs::read_to_string(dir.join("big/plan.csv")).unwrap();
    let t_s = |line: &str| line.split(',').nth(2).unwrap().parse::<f64>().unwrap();
    let (run0, run1) = (t_s(plan.lines().nth(1).unwrap()), t_s(plan.lines().last().unwrap()));
    assert!(times.iter().all(|t| (t - start) % 240.0 == 0.0), "{times:?}");
    assert!(times[0] <= start + run0 && start + run0 < times[0] + 240.0, "{} for a run from {run0} s", times[0]);
    let spacing = times[1] - times[0];
    assert!(times.windows(2).all(|w| w[1] - w[0] == spacing), "{times:?}");
    assert!(*times.last().unwrap() >= start + run1 && entries.len() <= 240, "{times:?} for a run to {run1} s");
    // At `shadow_utc` it is the direct sun direct_sun.tif has (both read by GDAL as raw
    // bytes: the same values, no data included).
    let raw = |tif: &Path| {
        let out = tif.with_extension("raw");
        tool("gdal_translate", &["-q", "-of", "ENVI", tif.to_str().unwrap(), out.to_str().unwrap()]);
        std::fs::read(&out).unwrap()
    };
    let at = entries.iter().find(|e| e["utc"] == "2012-08-06T21:40:00.000Z").expect("21:40 in the series");
    let (series, single) = (raw(&folder.join(at["file"].as_str().unwrap())), raw(&dir.join("big/direct_sun.tif")));
    assert_eq!(series.len(), 600 * 450);
    let differ = series.iter().zip(&single).filter(|(a, b)| a != b).count();
    assert!(differ == 0, "{differ} of {} values differ", series.len());
    assert!(series.contains(&0) && series.contains(&1), "shadow and sun both at 21:40");
    // direct_sun.tif names its instant as the series' files do.
    let single_info: serde_json::Value =
        serde_json::from_str(&tool("gdalinfo", &["-json", dir.join("big/direct_sun.tif").to_str().unwrap()])).unwrap();
    assert_eq!(single_info["metadata"][""]["TIFFTAG_DATETIME"], "2012:08:06 21:40:00");
    for e in [&entries[0], entries.last().unwrap()] {
        let file = folder.join(e["file"].as_str().unwrap());
        let info: serde_json::Value =
            serde_json::from_str(&tool("gdalinfo", &["-json", file.to_str().unwrap()])).unwrap();
        assert_eq!(info["metadata"]["IMAGE_STRUCTURE"]["LAYOUT"], "COG", "{}", file.display());
        cog_validator_accepts(&file);
        // The file's own time is the index's, to the second.
        let utc = e["utc"].as_str().unwrap();
        let stamp = info["metadata"][""]["TIFFTAG_DATETIME"].as_str().unwrap_or_default().to_string();
        assert_eq!(stamp, utc[..19].replacen('-', ":", 2).replace('T', " "), "{}", file.display());
        assert!(utc.starts_with("2012-08-06T"), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// GDAL reads the gale-ground run's `classes.tif` and `no_go.tif` as COGs on the map's
/// grid, the classes equal to the GDAL-made class map cell for cell (a histogram each)
/// and the mask's marked cells GDAL's burnt ones.
#[test]
fn gdal_reads_the_class_and_mask_layers_as_the_layers_gdal_made() {
    if !gdal_here("gdalinfo") {
        return;
    }
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("areo-gis-ground-{}", std::process::id()));
    let scenario = root.join("scenarios/gale-ground.ron");
    let out = areo(&["-q", "run", scenario.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let histogram = |path: &std::path::Path| -> (serde_json::Value, Vec<u64>) {
        let info: serde_json::Value =
            serde_json::from_str(&tool("gdalinfo", &["-json", "-hist", path.to_str().unwrap()])).unwrap();
        let buckets = info["bands"][0]["histogram"]["buckets"].as_array().unwrap().iter().map(|b| b.as_u64().unwrap());
        let counts = buckets.take(5).collect();
        (info, counts)
    };
    let (ours, counts) = histogram(&dir.join("gale-ground/classes.tif"));
    let (_, theirs) = histogram(&root.join("scenarios/data/gale_roughness_classes.tif"));
    assert_eq!(ours["metadata"]["IMAGE_STRUCTURE"]["LAYOUT"], "COG");
    cog_validator_accepts(&dir.join("gale-ground/classes.tif"));
    cog_validator_accepts(&dir.join("gale-ground/no_go.tif"));
    assert_eq!(ours["size"], serde_json::json!([64, 64]));
    assert_eq!(ours["bands"][0]["noDataValue"].as_f64(), Some(255.0));
    assert_eq!(counts, theirs, "class counts 0..5: ours {counts:?}, GDAL's {theirs:?}");
    assert_eq!(counts[1..4], [1481, 1865, 750]);
    // The mask layer: 1 where GDAL burnt the polygon, 2 within the 500 m inflation.
    let (mask, counts) = histogram(&dir.join("gale-ground/no_go.tif"));
    assert_eq!(mask["metadata"]["IMAGE_STRUCTURE"]["LAYOUT"], "COG");
    let (_, burnt) = histogram(&root.join("scenarios/data/gale_hazard_mask.tif"));
    assert_eq!(counts[1], burnt[1], "marked cells: ours {counts:?}, GDAL's {burnt:?}");
    assert_eq!(counts[2], 19);
    codes_have_names_and_colours(&ours, &mask);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The class map names the scenario's classes by id and colours them (the palette's
/// first three colours, in the order of the ids); the mask names and colours its codes.
fn codes_have_names_and_colours(classes: &serde_json::Value, mask: &serde_json::Value) {
    let band = &classes["bands"][0];
    assert_eq!(band["categories"], serde_json::json!(["", "smooth", "rough", "blocky"]), "{band}");
    assert_eq!(band["colorInterpretation"], "Palette");
    let entries = band["colorTable"]["entries"].as_array().unwrap();
    assert_eq!(
        entries[1..4],
        [
            serde_json::json!([0, 114, 178, 255]),
            serde_json::json!([230, 159, 0, 255]),
            serde_json::json!([0, 158, 115, 255])
        ]
    );
    assert!(band["description"].as_str().unwrap_or_default().contains("terrain class"), "{band}");
    let band = &mask["bands"][0];
    let names =
        serde_json::json!(["free", "marked by the mask", "within the mask's inflation", "cut off from the start"]);
    assert_eq!(band["categories"], names, "{band}");
    assert_eq!(band["colorTable"]["entries"][1], serde_json::json!([213, 94, 0, 255]));
}

/// A class map with a colour table that GDAL wrote — as a BigTIFF, big-endian — plans
/// as the same map without one: areo reads a palette image's samples as its codes.
#[test]
fn a_class_map_gdal_wrote_with_a_colour_table_reads_as_its_codes() {
    if !gdal_here("gdal_translate") {
        return;
    }
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("areo-gis-palette-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let source = root.join("scenarios/data/gale_roughness_classes.tif");
    let vrt = dir.join("coloured.vrt");
    // A colour table on the classes, then a BigTIFF in big-endian order from it.
    tool("gdal_translate", &["-q", "-of", "VRT", source.to_str().unwrap(), vrt.to_str().unwrap()]);
    let table = "<ColorInterp>Palette</ColorInterp><ColorTable><Entry c1=\"0\" c2=\"0\" c3=\"0\" c4=\"255\"/>\
                 <Entry c1=\"0\" c2=\"114\" c3=\"178\" c4=\"255\"/><Entry c1=\"230\" c2=\"159\" c3=\"0\" c4=\"255\"/>\
                 <Entry c1=\"0\" c2=\"158\" c3=\"115\" c4=\"255\"/></ColorTable>";
    let text = std::fs::read_to_string(&vrt).unwrap();
    let text = text.replacen("<ColorInterp>Gray</ColorInterp>", table, 1);
    assert!(text.contains("<ColorTable>"), "{text}");
    std::fs::write(&vrt, text).unwrap();
    let coloured = dir.join("coloured.tif");
    tool(
        "gdal_translate",
        &["-q", "-co", "BIGTIFF=YES", "-co", "ENDIANNESS=BIG", vrt.to_str().unwrap(), coloured.to_str().unwrap()],
    );
    let info: serde_json::Value =
        serde_json::from_str(&tool("gdalinfo", &["-json", coloured.to_str().unwrap()])).unwrap();
    assert_eq!(info["bands"][0]["colorInterpretation"], "Palette", "{info}");
    let scenario = std::fs::read_to_string(root.join("scenarios/gale-ground.ron")).unwrap();
    let mut facts = Vec::new();
    for (name, map) in [("plain", source), ("coloured", coloured)] {
        let text = scenario
            .replace("\"data/gale_roughness_classes.tif\"", &format!("{:?}", map.to_str().unwrap()))
            .replace("\"data/", &format!("\"{}/scenarios/data/", root.display()))
            .replace("\"rovers/", &format!("\"{}/scenarios/rovers/", root.display()));
        let path = dir.join(format!("{name}.ron"));
        std::fs::write(&path, text).unwrap();
        let out = areo(&["-q", "run", path.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        let read = std::fs::read_to_string(dir.join(name).join("facts.json")).unwrap();
        facts.push(serde_json::from_str::<serde_json::Value>(&read).unwrap());
    }
    for class in ["smooth", "rough", "blocky"] {
        let key = format!("terrain_classes.classes.{class}.cells");
        assert_eq!(facts[0][&key], facts[1][&key], "{key}");
        assert!(facts[0][&key].as_u64().unwrap() > 700, "{key}: {}", facts[0][&key]);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
