//! The commands besides `run`, end to end: `areo terrain info`, `slope`, `shadow`
//! (whole and tiled), `horizon` (whole and tiled), `viewshed` on the real MOLA Gale crop,
//! and their errors (a corrupt DEM, an unknown format, a bad Sun); `areo grid` on a
//! Moving AI file; `areo rover check` on LSR-1 and a resource model.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn areo(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_areo")).args(args).output().expect("run areo")
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn tmp(tag: &str) -> PathBuf {
    let dir = root().join("target").join("commands-tests").join(tag);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn terrain_info_slope_and_shadow_on_the_real_crop() {
    let dem = root().join("crates/terrain/tests/data/gale_mola_crop_64.tif");
    let out = areo(&["terrain", "info", dem.to_str().unwrap()]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("64 × 64 cells") && text.contains("equirectangular"), "{text}");
    let dir = tmp("terrain");
    let shadow = dir.join("shadow.tif");
    let out = areo(&[
        "terrain",
        "shadow",
        dem.to_str().unwrap(),
        "--sun-azimuth",
        "100",
        "--sun-elevation",
        "90",
        "-o",
        shadow.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // A Sun at the zenith lights every cell.
    assert!(String::from_utf8_lossy(&out.stdout).contains("100.00 % of the valid cells"));
    let bytes = std::fs::read(&shadow).unwrap();
    assert!(bytes.starts_with(b"II*\0") || bytes.starts_with(b"MM\0*"));
    assert!(dir.join("shadow.png").exists());
    // A low Sun, by each method: the same shadows but for cells it grazes.
    let lit = |method: &str| {
        let mut args = vec!["terrain", "shadow", dem.to_str().unwrap(), "--sun-azimuth", "100"];
        args.extend(["--sun-elevation", "4", "--method", method, "-o", shadow.to_str().unwrap()]);
        let out = areo(&args);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        text.split(" % of the valid cells").next().and_then(|v| v.trim().parse::<f64>().ok()).expect("lit %")
    };
    let (own, sheared, fast) = (lit("own-ray"), lit("sheared"), lit("interpolated"));
    assert!(
        own < 99.0 && (sheared - own).abs() < 1.0 && (fast - own).abs() < 2.0,
        "own {own} %, sheared {sheared} %, interpolated {fast} %"
    );
    let out = areo(&[
        "terrain",
        "shadow",
        dem.to_str().unwrap(),
        "--sun-azimuth",
        "1",
        "--sun-elevation",
        "4",
        "--method",
        "exact",
        "-o",
        shadow.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2), "an unknown --method is a usage error");
    let slope = dir.join("slope.tif");
    let out = areo(&["terrain", "slope", dem.to_str().unwrap(), "-o", slope.to_str().unwrap()]);
    assert!(out.status.success());
    assert!(slope.exists() && dir.join("slope.png").exists());
}

#[test]
fn tiled_shadow_on_the_real_crop_is_the_whole_maps_map() {
    // The Gale crop in 16 × 16 tiles (16 of them), read through windows, written band
    // by band: byte for byte the values of the whole-map run.
    let dem = root().join("crates/terrain/tests/data/gale_mola_crop_64.tif");
    let dir = tmp("tiled_shadow");
    let (whole, tiled) = (dir.join("whole.tif"), dir.join("tiled.tif"));
    let run = |out: &Path, tile: Option<&str>| {
        let mut args =
            vec!["terrain", "shadow", dem.to_str().unwrap(), "--sun-azimuth", "290", "--sun-elevation", "12"];
        args.extend(["-o", out.to_str().unwrap()]);
        if let Some(t) = tile {
            args.extend(["--tile", t]);
        }
        let out = areo(&args);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    run(&whole, None);
    let text = run(&tiled, Some("16"));
    assert!(text.contains("16 tiles, each read with a halo of"), "{text}");
    let (a, b) = (areo_scenario::terrain::read_dem(&whole).unwrap(), areo_scenario::terrain::read_dem(&tiled).unwrap());
    assert_eq!(a.elevations(), b.elevations());
    assert!(a.elevations().contains(&0.0), "some cells in shadow");
    let out = areo(&[
        "terrain",
        "shadow",
        dem.to_str().unwrap(),
        "--sun-azimuth",
        "1",
        "--sun-elevation",
        "4",
        "--tile",
        "3",
        "-o",
        tiled.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2), "a tile under 16 cells is a usage error");
    // A Sun half a degree up over 1.2 km of relief: a 476 km halo, so each tile is read
    // as the whole crop, and the estimate is past a 100 KB allowance.
    let out = areo(&[
        "--max-memory-gb",
        "0.0001",
        "terrain",
        "shadow",
        dem.to_str().unwrap(),
        "--sun-azimuth",
        "10",
        "--sun-elevation",
        "0.5",
        "--tile",
        "16",
        "-o",
        tiled.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("--tile 16") && err.contains("--max-memory-gb"), "{err}");
}

#[test]
fn tiled_horizon_on_the_real_crop_holds_the_whole_maps_horizons() {
    // The Gale crop's 16-sector horizon map in 32-cell tiles: one tiled GeoTIFF with a
    // plane per sector, every horizon at or above the lowest Sun the whole map's.
    let dem = root().join("crates/terrain/tests/data/gale_mola_crop_64.tif");
    let dir = tmp("tiled_horizon");
    let (whole, tiled) = (dir.join("whole"), dir.join("tiled.tif"));
    let d = dem.to_str().unwrap();
    let out = areo(&["terrain", "horizon", d, "--sectors", "16", "-o", whole.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let args = ["terrain", "horizon", d, "--sectors", "16", "--tile", "32", "--lowest-sun", "3"];
    let out = areo(&[&args[..], &["-o", tiled.to_str().unwrap()]].concat());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("4 tiles, each read with a halo of") && text.contains("below 3° stored as 3°"), "{text}");
    let mut dec = tiff::decoder::Decoder::new(std::fs::File::open(&tiled).unwrap()).unwrap();
    assert_eq!(dec.chunk_dimensions(), (32, 32));
    let (mut above, mut checked) = (0, 0);
    for s in 0..16 {
        let plane = areo_scenario::terrain::read_dem(&whole.join(format!("s{s:03}.tif"))).unwrap();
        for t in 0..4u32 {
            let tiff::decoder::DecodingResult::U16(codes) = dec.read_chunk(s * 4 + t).unwrap() else { panic!() };
            let (c0, r0) = ((t % 2) as usize * 32, (t / 2) as usize * 32);
            for r in 0..32 {
                for c in 0..32 {
                    let deg = f64::from(codes[r * 32 + c]) * 180.0 / 65535.0 - 90.0;
                    let want = f64::from(plane.z(c0 + c, r0 + r).unwrap()).max(3.0);
                    // Both are the same 2-byte code; the float file rounds it to f32.
                    assert!((deg - want).abs() < 0.002, "sector {s} cell ({}, {}): {deg} vs {want}", c0 + c, r0 + r);
                    above += usize::from(want > 3.01);
                    checked += 1;
                }
            }
        }
    }
    assert_eq!(checked, 16 * 64 * 64);
    assert!(above > 500, "enough horizons above the floor to mean something: {above}");
    let out = areo(&[&args[..5], &["--tile", "24", "-o", tiled.to_str().unwrap()]].concat());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("--tile 24: allowed a multiple of 16"), "{err}");
}

#[test]
fn terrain_viewshed_from_a_mast_on_the_real_crop() {
    let dem = root().join("crates/terrain/tests/data/gale_mola_crop_64.tif");
    let out_path = tmp("viewshed").join("view.tif");
    // The crop's centre, 10 m up.
    let from = "8123756.41,-312563.93,10";
    let out = areo(&["terrain", "viewshed", dem.to_str().unwrap(), "--from", from, "-o", out_path.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    let pct: f64 = text.split('%').next().unwrap().trim().parse().unwrap();
    assert!(pct > 1.0 && pct <= 100.0, "{text}");
    let out = areo(&["terrain", "viewshed", dem.to_str().unwrap(), "--from", "0,0", "-o", out_path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "a malformed --from is a usage error");
    let out =
        areo(&["terrain", "viewshed", dem.to_str().unwrap(), "--from", "0,0,10", "-o", out_path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "an observer off the map is an input error");
    assert!(String::from_utf8_lossy(&out.stderr).contains("off the map"));
}

#[test]
fn terrain_rejects_a_corrupt_dem_with_exit_2() {
    let dir = tmp("terrain-bad");
    let bad = dir.join("bad.tif");
    std::fs::write(&bad, b"II*\0this is not a tiff").unwrap();
    let out = areo(&["terrain", "info", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("bad.tif"));
}

#[test]
fn terrain_names_an_unknown_format_and_a_bad_sun_as_such() {
    let dir = tmp("terrain-unknown");
    let odd = dir.join("heights.xyz");
    std::fs::write(&odd, b"0 0 0").unwrap();
    let out = areo(&["terrain", "info", odd.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("heights.xyz: unknown DEM format") && err.contains(".tif/.tiff"), "{err}");
    assert!(!err.contains("Moving AI"), "{err}");
    let shadow = dir.join("shadow.tif");
    let args = ["terrain", "shadow", odd.to_str().unwrap(), "--sun-azimuth", "90", "--sun-elevation", "120", "-o"];
    let out = areo(&[&args[..], &[shadow.to_str().unwrap()]].concat());
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--sun-elevation 120: allowed -90..=90"), "{err}");
}

#[test]
fn terrain_info_json_has_plain_names_and_completions_print() {
    let dem = root().join("crates/terrain/tests/data/gale_mola_crop_64.tif");
    let out = areo(&["terrain", "info", dem.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let info: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(info["projection"], "equirectangular");
    assert_eq!(info["body"], "Mars");
    assert!(info["cols"].is_u64() && info["radii_m"][0] == 3_396_000.0, "{info}");
    let text = String::from_utf8_lossy(&areo(&["terrain", "info", dem.to_str().unwrap()]).stdout).into_owned();
    assert!(
        text.contains("projection  equirectangular, standard parallel") && !text.contains("Equirectangular {"),
        "{text}"
    );
    let bash = areo(&["completions", "bash"]);
    assert!(bash.status.success() && String::from_utf8_lossy(&bash.stdout).contains("complete -F _areo"));
}

#[test]
fn grid_solves_a_moving_ai_file_and_replans() {
    let dir = root().join("crates/ise/tests/data/movingai");
    let map = dir.join("arena.map");
    let scen = dir.join("arena.map.scen");
    let out = areo(&[
        "grid",
        "--map",
        map.to_str().unwrap(),
        "--scen",
        scen.to_str().unwrap(),
        "--format",
        "csv",
        "--replan",
        "3",
        "--seed",
        "7",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(text.lines().next().unwrap(), "index,expected,found,expansions,replanned,fresh,replan_expansions");
    assert_eq!(text.lines().count(), 1 + 160 + 1);
    assert_eq!(text.lines().last().unwrap(), "160 solved, 0 mismatched");
    // Row 0 of arena.map.scen: 1 step, length 1.
    assert!(text.lines().nth(1).unwrap().starts_with("0,1,1.00000000,"));
}

#[test]
fn grid_rejects_a_corrupt_map_with_exit_2() {
    let dir = tmp("grid");
    let map = dir.join("bad.map");
    std::fs::write(&map, "type octile\nheight 3\nwidth 4\nmap\n....\n..\n....\n").unwrap();
    let scen = root().join("crates/ise/tests/data/movingai/arena.map.scen");
    let out = areo(&["grid", "--map", map.to_str().unwrap(), "--scen", scen.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.map") && err.contains("line 6"), "{err}");
}

#[test]
fn rover_check_reports_loads_margin_and_needed_friction() {
    let params = root().join("crates/rover/params/lsr1.ron");
    let out = areo(&["rover", "check", params.to_str().unwrap(), "--terrain", "flat"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("verdict: ok") && text.contains("100.0 % of flat ground"), "{text}");
    // W/6 = 7 × 9.81 / 6 = 11.445 N on every wheel.
    assert_eq!(text.matches("11.445").count(), 6, "{text}");
    // A 20° slope in JSON: pitch 20°, μ needed = tan 20° = 0.3640.
    let out = areo(&["rover", "check", params.to_str().unwrap(), "--terrain", "slope:20", "--format", "json"]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(v["verdict"], "ok");
    assert!((v["pose"]["pitch_deg"].as_f64().unwrap() - 20.0).abs() < 1e-6);
    assert!((v["mu_needed"].as_f64().unwrap() - 0.3640).abs() < 2e-4, "{v}");
    assert_eq!(v["wheels"].as_array().unwrap().len(), 6);
    // Too little friction for a vertical step: the verdict names slip, exit 0.
    let out = areo(&["rover", "check", params.to_str().unwrap(), "--terrain", "step:0.2", "--mu", "0.4"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("slip") && text.contains("smallest μ that holds here: 0.57"), "{text}");
    // And the climb over it, pose by pose.
    assert!(text.contains("climb over the step (101 poses") && text.contains("stopped at 0.00 m (slip)"), "{text}");
}

/// A TEMPEST resource model checked: its drive figures are the locomotor's formula
/// worked by hand (m·g·v·(c_rr·cos θ + sin θ)/η plus the high electronics level, the
/// speed falling linearly to a third at the maximum slope), its battery's the
/// state-of-charge window times the discharge efficiency. Before, `rover check` knew
/// only LSR-1 parameter files and refused these ("Expected struct `RoverParams`").
#[test]
fn rover_check_works_a_resource_model_by_hand() {
    let model = root().join("scenarios/rovers/mock-solar-rover.ron");
    let out = areo(&["rover", "check", model.to_str().unwrap(), "--terrain", "slope:10", "--format", "json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    // The file: 156 kg, 0.3 m/s, c_rr 0.15, η 0.5, 20° maximum, 3.711 m/s²; electronics
    // 20 / 80 / 150 W; 1000 Wh between 10 % and 100 %, 95 % delivered; 3.45 m² at 20 %.
    let weight = 156.0 * 3.711;
    let loco = |v: f64, deg: f64| {
        (weight * v * (0.15 * f64::cos(deg.to_radians()) + f64::sin(deg.to_radians())) / 0.5).max(0.0)
    };
    let rows = v["drives"].as_array().unwrap();
    let want = [("flat", 0.3, 0.0), ("up 10°", 0.2, 10.0), ("down 10°", 0.2, -10.0), ("up 20° (maximum)", 0.1, 20.0)];
    assert_eq!(rows.len(), want.len(), "{v}");
    for (row, (ground, speed, deg)) in rows.iter().zip(want) {
        assert_eq!(row["ground"], ground);
        let close = |key: &str, x: f64| assert!((row[key].as_f64().unwrap() - x).abs() < 1e-9, "{key} {row} vs {x}");
        close("speed_m_s", speed);
        close("locomotion_w", loco(speed, deg));
        close("battery_w", loco(speed, deg) + 150.0);
        close("wh_per_km", (loco(speed, deg) + 150.0) / speed / 3.6);
    }
    // Downhill at 10° the slope pays more than rolling costs: no locomotion power.
    assert_eq!(rows[2]["locomotion_w"].as_f64(), Some(0.0));
    assert!((v["array_w_per_w_m2"].as_f64().unwrap() - 0.69).abs() < 1e-12);
    assert_eq!((v["usable_wh"].as_f64(), v["deliverable_wh"].as_f64()), (Some(900.0), Some(855.0)));
    assert!((v["hibernate_h"].as_f64().unwrap() - 855.0 / 20.0).abs() < 1e-9);
    assert!((v["idle_h"].as_f64().unwrap() - 855.0 / 80.0).abs() < 1e-9);
    let flat_wh_km = (loco(0.3, 0.0) + 150.0) / 0.3 / 3.6;
    assert!((v["range_flat_km"].as_f64().unwrap() - 855.0 / flat_wh_km).abs() < 1e-9);
    assert_eq!(v["gravity_from"], "the file");
    // A model without gravity drives in the body's: the lunar rover on the Moon.
    let lunar = root().join("scenarios/rovers/lunar-polar-rover.ron");
    let out = areo(&["rover", "check", lunar.to_str().unwrap(), "--body", "moon"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && text.contains("gravity 1.622 m/s² (Moon)"), "{text}");
    assert!(text.contains("a full battery with no sunlight lasts"), "{text}");
    // What does not apply to a resource model is refused, and so is a slope it cannot drive.
    for terrain in ["step:0.2", "side-slope:5", "slope:25"] {
        let out = areo(&["rover", "check", model.to_str().unwrap(), "--terrain", terrain]);
        assert_eq!(out.status.code(), Some(2), "{terrain}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(&format!("--terrain {terrain}")), "{err}");
    }
}

#[test]
fn rover_check_rejects_bad_terrain_and_bad_parameters_with_exit_2() {
    let params = root().join("crates/rover/params/lsr1.ron");
    let out = areo(&["rover", "check", params.to_str().unwrap(), "--terrain", "slope:95"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("allowed: flat"));
    let bad = root().join("tests/rover/bad_gear.ron");
    let out = areo(&["rover", "check", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad_gear.ron") && err.contains("drive.gear_efficiency") && err.contains("1.5"), "{err}");
    let out = areo(&["rover", "check", "no/such/params.ron"]);
    assert_eq!(out.status.code(), Some(2), "a missing input is bad input");
    assert!(String::from_utf8_lossy(&out.stderr).contains("no/such/params.ron"));
}
