//! The plan viewer (`view.html`) in a real browser: Debian's headless Chromium loads a
//! run's page at instants given in the link and the tests read what it drew — its
//! screenshots and the state the page keeps in `#state` — against the run's own files:
//! the rover where executed.csv (or the plan) puts it, the shadows changed where the
//! frames say the direct sun changed, a link whose time is not the run's showing the
//! start with the reason, the readout's place, zoom and pan, the local-time axis, the
//! activities' names and the relief under the tints.
//!
//! Without Chromium the tests fail where `AREO_REQUIRE_CHROMIUM` is set (CI, whose
//! `.ci/run` installs it) and say they did not run otherwise.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Whether Chromium runs here.
// Saying that the test did not run is the point of its one message.
#[allow(clippy::print_stderr)]
fn chromium_here() -> bool {
    match Command::new("chromium").arg("--version").output() {
        Ok(o) if o.status.success() => true,
        other if std::env::var_os("AREO_REQUIRE_CHROMIUM").is_some() => {
            panic!("AREO_REQUIRE_CHROMIUM is set but chromium cannot run: {other:?}")
        }
        _ => {
            eprintln!("not run: no chromium here; .ci/run installs Debian's chromium and requires it");
            false
        }
    }
}

/// Runs `scenario` into a fresh directory; returns the run's output directory.
fn run(scenario: &str) -> PathBuf {
    let name = Path::new(scenario).file_stem().unwrap().to_string_lossy().into_owned();
    let out = root().join("target").join("view-tests").join(&name);
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_areo"))
        .args(["-q", "run", root().join(scenario).to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out.join(name)
}

/// The page at `#fragment`: its DOM after the script ran, and its console's errors.
fn dom(page: &Path, fragment: &str) -> (String, String) {
    let url = format!("file://{}#{fragment}", page.display());
    let o = Command::new("chromium")
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--enable-logging=stderr", "--v=0"])
        .args(["--virtual-time-budget=5000", "--window-size=1300,820", "--dump-dom", &url])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    let console: Vec<&str> = err.lines().filter(|l| l.contains("CONSOLE") || l.contains("Uncaught")).collect();
    (String::from_utf8_lossy(&o.stdout).into_owned(), console.join("\n"))
}

/// A screenshot of the page at `#fragment`: width, height and RGBA pixels.
fn screenshot(page: &Path, fragment: &str, name: &str) -> (usize, usize, Vec<u8>) {
    let png = page.with_file_name(format!("{name}.png"));
    let url = format!("file://{}#{fragment}", page.display());
    let o = Command::new("chromium")
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--window-size=1300,820"])
        .args(["--virtual-time-budget=5000", &format!("--screenshot={}", png.display()), &url])
        .output()
        .unwrap();
    assert!(png.exists(), "no screenshot: {}", String::from_utf8_lossy(&o.stderr));
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let rgba: Vec<u8> = match info.color_type {
        png::ColorType::Rgba => buf[..info.buffer_size()].to_vec(),
        png::ColorType::Rgb => buf[..info.buffer_size()].chunks(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect(),
        other => panic!("screenshot colour type {other:?}"),
    };
    (info.width as usize, info.height as usize, rgba)
}

/// `#state`'s data attributes in a dumped DOM.
fn state(dom: &str) -> HashMap<String, String> {
    let at = dom.find("id=\"state\"").expect("#state in the page");
    let tag = &dom[dom[..at].rfind('<').unwrap()..at + dom[at..].find('>').unwrap()];
    let mut out = HashMap::new();
    for part in tag.split(" data-").skip(1) {
        if let Some((k, v)) = part.split_once("=\"") {
            out.insert(k.to_string(), v.split('"').next().unwrap_or("").replace("&quot;", "\""));
        }
    }
    out
}

/// The page's data: the JSON in its `#data` script.
fn page_data(page: &Path) -> serde_json::Value {
    let html = std::fs::read_to_string(page).unwrap();
    let start = html.find("type=\"application/json\">").unwrap() + "type=\"application/json\">".len();
    let end = start + html[start..].find("</script>").unwrap();
    serde_json::from_str(&html[start..end].replace("<\\/", "</")).unwrap()
}

/// A CSV file's rows by header name (no quoted commas in the columns read here).
fn csv(path: &Path) -> Vec<HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines.map(|l| header.iter().cloned().zip(l.split(',').map(String::from)).collect()).collect()
}

fn num(s: &str) -> f64 {
    s.parse().unwrap_or_else(|e| panic!("{s:?}: {e}"))
}

/// The pixel of map metres (x east, y north of the south-west corner) in the page's
/// image, from its data: cells from its north-west cell, over cells per pixel.
fn pixel(data: &serde_json::Value, (x_m, y_m): (f64, f64)) -> (f64, f64) {
    let k = data["cells_per_pixel"].as_f64().unwrap();
    let (dx, dy) = (data["cell_m"][0].as_f64().unwrap(), data["cell_m"][1].as_f64().unwrap());
    let (c0, r0) = (data["origin_cells"][0].as_f64().unwrap(), data["origin_cells"][1].as_f64().unwrap());
    let rows = data["map_rows"].as_f64().unwrap();
    ((x_m / dx - c0) / k, ((rows * dy - y_m) / dy - r0) / k)
}

/// Checks the page at instants `a` and `b`, where the rover stands at `rover_a` and
/// `rover_b` (map metres): no script error, the rover marker drawn there, and the
/// screenshots differing where the direct sun changed between the instants' frames.
fn check_two_instants(page: &Path, (a, rover_a): (&str, (f64, f64)), (b, rover_b): (&str, (f64, f64))) {
    let data = page_data(page);
    let mut frames = Vec::new();
    let mut shots = Vec::new();
    for (t, at, name) in [(a, rover_a, "shot_a"), (b, rover_b, "shot_b")] {
        let (page_dom, console) = dom(page, &format!("t={t}"));
        assert!(console.is_empty(), "the page's console at {t}:\n{console}");
        let s = state(&page_dom);
        assert_eq!(s.get("error").map(String::as_str), Some(""), "{t}: {s:?}");
        assert!((num(&s["t"]) - unix_s(t)).abs() < 1e-3, "{t}: {}", s["t"]);
        let (want_x, want_y) = pixel(&data, at);
        let (x, y) = (num(&s["rover-x"]), num(&s["rover-y"]));
        assert!(
            (x - want_x).abs() <= 1.0 && (y - want_y).abs() <= 1.0,
            "{t}: rover at ({x}, {y}), want ({want_x}, {want_y})"
        );
        // The marker is drawn there: the screenshot is magenta at its centre.
        let (w, _, rgba) = screenshot(page, &format!("t={t}"), name);
        let scale = num(&s["scale"]);
        let (left, top) = (num(&s["map-left"]), num(&s["map-top"]));
        let (sx, sy) = ((left + x * scale) as usize, (top + y * scale) as usize);
        let p = &rgba[4 * (sy * w + sx)..4 * (sy * w + sx) + 3];
        assert!(p[0] > 200 && p[1] < 60 && p[2] > 200, "{t}: the marker's pixel is {p:?}");
        frames.push(num(&s["frame"]) as usize);
        shots.push((w, rgba, scale, left, top));
    }
    // Where the frames' direct sun differs, so does the picture.
    let bits = |k: usize| {
        use base64::Engine;
        base64::engine::general_purpose::STANDARD.decode(data["frames"][k].as_str().unwrap()).unwrap()
    };
    let (fa, fb) = (bits(frames[0]), bits(frames[1]));
    let width = data["width"].as_u64().unwrap() as usize;
    let height = data["height"].as_u64().unwrap() as usize;
    let (mut changed, mut shown) = (0, 0);
    for i in 0..width * height {
        let (la, lb) = ((fa[i / 8] >> (i % 8)) & 1, (fb[i / 8] >> (i % 8)) & 1);
        if la == lb {
            continue;
        }
        changed += 1;
        let sample = |(w, rgba, scale, left, top): &(usize, Vec<u8>, f64, f64, f64)| {
            let (sx, sy) = (
                (left + ((i % width) as f64 + 0.5) * scale) as usize,
                (top + ((i / width) as f64 + 0.5) * scale) as usize,
            );
            let o = 4 * (sy * w + sx);
            (rgba[o] as i32, rgba[o + 2] as i32)
        };
        // Lit ground is grey (blue no stronger than red); ground without direct sun is
        // blue-tinted.
        let ((ra, ba), (rb, bb)) = (sample(&shots[0]), sample(&shots[1]));
        if (la == 1) == (ba - ra < 20) && (lb == 1) == (bb - rb < 20) {
            shown += 1;
        }
    }
    assert!(changed > 50, "the direct sun changes at {changed} pixels between {a} and {b}");
    // Routes and markers cover some of them.
    assert!(shown as f64 >= 0.9 * changed as f64, "{shown} of {changed} changed pixels drawn so");
}

/// `t` (ISO 8601 UTC, `YYYY-MM-DDTHH:MM:SS(.sss)Z`) as Unix seconds.
fn unix_s(t: &str) -> f64 {
    let (date, time) = t.trim_end_matches('Z').split_once('T').unwrap();
    let d: Vec<i64> = date.split('-').map(|v| v.parse().unwrap()).collect();
    let h: Vec<f64> = time.split(':').map(|v| v.parse().unwrap()).collect();
    // Days from 1970-01-01 (the proleptic Gregorian calendar's civil-from-days inverse).
    let (y, m) = if d[1] <= 2 { (d[0] - 1, d[1] + 9) } else { (d[0], d[1] - 3) };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let doy = (153 * m + 2) / 5 + d[2] - 1;
    let days = era * 146_097 + yoe * 365 + yoe / 4 - yoe / 100 + doy - 719_468;
    days as f64 * 86_400.0 + h[0] * 3600.0 + h[1] * 60.0 + h[2]
}

/// `unix` s as ISO 8601 UTC to the second (the days' civil date: the inverse of
/// [`unix_s`]'s).
fn iso(unix: f64) -> String {
    let (days, secs) = ((unix / 86_400.0).floor() as i64, unix.rem_euclid(86_400.0).round() as i64);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z", secs / 3600, secs % 3600 / 60, secs % 60)
}

/// The executed row whose action spans `t` (ISO 8601): its start, as map metres.
fn executed_at(rows: &[HashMap<String, String>], t: &str) -> (f64, f64) {
    let row = rows.iter().find(|r| r["utc"].as_str() <= t && t < r["end_utc"].as_str()).expect("an action then");
    assert!(row["action"] == "wait" || row["action"] == "hibernate", "the rover stands still then: {row:?}");
    (num(&row["x_m"]), num(&row["y_m"]))
}

#[test]
fn valley_detours_viewer_shows_the_night_the_waiting_rover_and_its_battery() {
    if !chromium_here() {
        return;
    }
    let dir = run("scenarios/valley-detour.ron");
    let page = dir.join("view.html");
    let rows = csv(&dir.join("executed.csv"));
    // In the afternoon waiting at the wall, and in the night that follows.
    let (a, b) = ("2012-08-07T04:30:00.000Z", "2012-08-07T14:00:00.000Z");
    check_two_instants(&page, (a, executed_at(&rows, a)), (b, executed_at(&rows, b)));
    // Waiting at the wall in the afternoon sun it charges; waiting through the night it
    // sleeps (the activity as the planner means it, told by the ground's direct sun).
    for (t, doing) in [(a, "charge"), (b, "sleep")] {
        let (page_dom, _) = dom(&page, &format!("t={t}"));
        assert_eq!(state(&page_dom)["doing"], doing, "{t}");
    }
    // A bad link shows the start and says why.
    let (bad, console) = dom(&page, "t=yesterday");
    assert!(console.is_empty(), "{console}");
    let s = state(&bad);
    assert!(s["error"].contains("\"yesterday\", is not a time: showing the start"), "{s:?}");
    assert_eq!(s["utc"], rows[0]["utc"].replace(".000Z", "Z"));
    let (late, _) = dom(&page, "t=2030-01-01T00:00:00Z");
    assert!(state(&late)["error"].contains("is outside the run"));
    let size = std::fs::metadata(&page).unwrap().len();
    assert!(size < 25_000_000, "{size} bytes");
}

#[test]
fn the_lunar_plans_viewer_moves_the_shadows_and_the_rover_along_the_plan() {
    // Two waypoints a day apart: the rover is at each at its instant.
    let Some(page) = check_plan_viewer("scenarios/lunar-south-pole.ron", |dt| dt > 86_400.0) else { return };
    a_stay_in_a_session_communicates(&page);
    relief_reads_under_every_tint(&page);
}

/// A waypoint inside a scheduled Communicate session, where the plan stands still, is
/// named `communicate`; the Earth lane has a value per frame.
fn a_stay_in_a_session_communicates(page: &Path) {
    let data = page_data(page);
    let plan = csv(&page.with_file_name("plan.csv"));
    let sessions: Vec<(f64, f64)> = serde_json::from_value(data["sessions"].clone()).unwrap();
    let (t0, t1) = (unix_s(&plan[0]["utc"]), unix_s(&plan[plan.len() - 1]["utc"]));
    let &(a, b) = sessions.iter().find(|&&(a, b)| t0 < a && b < t1).expect("a session within the plan");
    let (during, after) = (0.5 * (a + b), b + 0.5 * (b - a));
    assert_eq!(unix_s(&iso(during.round())), during.round(), "the calendar");
    let row = |t: f64| plan.iter().rev().find(|w| unix_s(&w["utc"]) <= t).unwrap();
    assert!(!row(during)["action"].starts_with("drive"), "the plan stands still in a session: {:?}", row(during));
    assert_eq!(state(&dom(page, &format!("t={}", iso(during))).0)["doing"], "communicate", "{:?}", row(during));
    if row(after)["action"] == "wait" && !sessions.iter().any(|&(a, b)| a <= after && after < b) {
        assert_ne!(state(&dom(page, &format!("t={}", iso(after))).0)["doing"], "communicate", "{:?}", row(after));
    }
    let lane = data["frame_earth_in_view"].as_array().expect("an Earth lane off the Earth");
    assert_eq!(lane.len(), data["frame_unix_s"].as_array().unwrap().len());
}

/// Under every tint the drawn map keeps the hillshade's relief: in each group of
/// pixels under the same tints, luminance grows in proportion to the hillshade (the
/// page's measure over the pixels it drew: 0.70 with the classes mixed a third in).
fn relief_reads_under_every_tint(page: &Path) {
    let s = state(&dom(page, "relief").0);
    let least = num(&s["relief-least"]);
    assert!(least > 0.95 && least < 1.05, "{s:?}");
}

#[test]
fn the_relief_reads_under_the_terrain_classes() {
    if !chromium_here() {
        return;
    }
    let page = run("scenarios/gale-ground.ron").join("view.html");
    assert!(page_data(&page)["classes"].is_object(), "gale-ground's map has classes");
    relief_reads_under_every_tint(&page);
}

/// Checks the viewer of `scenario` (a plan without a simulation) at its second waypoint
/// and the first after it whose time since it, s, `apart` accepts: the rover at each
/// waypoint at its instant, the shadows moving between.
fn check_plan_viewer(scenario: &str, apart: impl Fn(f64) -> bool) -> Option<PathBuf> {
    if !chromium_here() {
        return None;
    }
    let dir = run(scenario);
    let page = dir.join("view.html");
    let plan = csv(&dir.join("plan.csv"));
    let first = &plan[1];
    let later = plan.iter().find(|w| apart(num(&w["t_s"]) - num(&first["t_s"]))).expect("a waypoint far enough on");
    let at = |w: &HashMap<String, String>| (w["utc"].clone(), (num(&w["x_m"]), num(&w["y_m"])));
    let ((ta, pa), (tb, pb)) = (at(first), at(later));
    check_two_instants(&page, (&ta, pa), (&tb, pb));
    pointing_reads_the_cell_and_a_click_seeks(&dir, &page, &plan);
    the_place_under_the_pointer_stays_through_zoom_and_follows_a_drag(&page, &plan);
    local_time_ticks_are_the_plans_local_times(&page, &plan);
    Some(page)
}

/// The readout's latitude and longitude are plan.csv's at a waypoint's cell; four notches
/// of the wheel zoom 1.25⁴ about the pointer (the same cell under it, the scale bar's
/// metres per pixel divided by as much); a drag moves the view by as many image pixels
/// as the pointer moved over the zoom, the cell under the pointer with it.
fn the_place_under_the_pointer_stays_through_zoom_and_follows_a_drag(page: &Path, plan: &[HashMap<String, String>]) {
    let data = page_data(page);
    let k = data["cells_per_pixel"].as_f64().unwrap();
    let scale = num(&state(&dom(page, "").0)["scale"]);
    let w = &plan[plan.len() / 2];
    let (px, py) = pixel(&data, (num(&w["x_m"]), num(&w["y_m"])));
    let (cx, cy) = (px * scale, py * scale);
    let flat = state(&dom(page, &format!("point={cx},{cy}")).0);
    if (num(&flat["hover-col"]), num(&flat["hover-row"])) == (num(&w["col"]), num(&w["row"])) {
        assert!((num(&flat["hover-lat"]) - num(&w["lat_deg"])).abs() < 1e-6, "{flat:?} for {w:?}");
        assert!((num(&flat["hover-lon"]) - num(&w["lon_deg"])).abs() < 1e-6, "{flat:?} for {w:?}");
    } else {
        // Another cell of the waypoint's block: within the block's size of it.
        let (dlat, dlon) = (num(&flat["hover-lat"]) - num(&w["lat_deg"]), num(&flat["hover-lon"]) - num(&w["lon_deg"]));
        let radius = data["geo"]["radius_m"].as_f64().unwrap();
        let metres = radius * dlat.to_radians().hypot(dlon.to_radians() * num(&w["lat_deg"]).to_radians().cos());
        assert!(metres < 2.0 * k * data["cell_m"][0].as_f64().unwrap(), "{flat:?} for {w:?}");
    }
    let zoomed = state(&dom(page, &format!("wheel={cx},{cy},4&point={cx},{cy}")).0);
    assert_eq!((&zoomed["hover-col"], &zoomed["hover-row"]), (&flat["hover-col"], &flat["hover-row"]), "{zoomed:?}");
    let zoom = 1.25_f64.powi(4);
    assert!((num(&zoomed["zoom"]) - zoom).abs() < 1e-12, "{zoomed:?}");
    let per_px = |s: &HashMap<String, String>| num(&s["scale-bar-m"]) / num(&s["scale-bar-px"]);
    assert!((per_px(&flat) / per_px(&zoomed) - zoom).abs() < 1e-9, "{flat:?} {zoomed:?}");
    // Drag 120 canvas pixels towards the side with room, then point where it started.
    let room = num(&zoomed["pan-x"]) > 120.0 / (scale * zoom);
    let to = if room { cx + 120.0 } else { cx - 120.0 };
    let dragged = state(&dom(page, &format!("wheel={cx},{cy},4&drag={cx},{cy},{to},{cy}&point={cx},{cy}")).0);
    let moved = num(&zoomed["pan-x"]) - num(&dragged["pan-x"]);
    assert!((moved - (to - cx) / (scale * zoom)).abs() < 1e-9, "{zoomed:?} {dragged:?}");
    let col = data["origin_cells"][0].as_f64().unwrap() + (num(&dragged["pan-x"]) + cx / (scale * zoom)).floor() * k;
    assert_eq!(num(&dragged["hover-col"]), col, "{dragged:?}");
    assert!((num(&dragged["hover-col"]) - num(&flat["hover-col"])).abs() >= (120.0 / (scale * zoom)).floor() * k - k);
}

/// Every tick of the chart's local-time axis is where plan.csv's local solar time,
/// carried to the start's longitude (an hour for every 15° east), is the tick's hour.
fn local_time_ticks_are_the_plans_local_times(page: &Path, plan: &[HashMap<String, String>]) {
    let s = state(&dom(page, "").0);
    let ticks: Vec<serde_json::Value> = serde_json::from_str(&s["local-ticks"]).unwrap();
    assert!(!ticks.is_empty(), "{s:?}");
    let lon0 = num(&plan[0]["lon_deg"]);
    let at_start = |r: &HashMap<String, String>| {
        let shift = ((lon0 - num(&r["lon_deg"]) + 180.0).rem_euclid(360.0) - 180.0) / 15.0;
        num(&r["ltst_h"]) + shift
    };
    for tick in &ticks {
        let t = tick["t"].as_f64().unwrap();
        let Some(i) = plan.windows(2).position(|p| unix_s(&p[0]["utc"]) <= t && t <= unix_s(&p[1]["utc"])) else {
            continue;
        };
        let (a, b) = (&plan[i], &plan[i + 1]);
        let f = (t - unix_s(&a["utc"])) / (unix_s(&b["utc"]) - unix_s(&a["utc"])).max(1e-9);
        let (la, lb) = (at_start(a), at_start(b));
        let lb = la + (lb - la + 12.0).rem_euclid(24.0) - 12.0;
        let local = la + f * (lb - la);
        let hour = tick["hour"].as_f64().unwrap();
        let off = (local - hour + 12.0).rem_euclid(24.0) - 12.0;
        assert!(off.abs() < 0.02, "tick {tick}: the plan's local time there is {local} h");
    }
}

/// Pointing at the map over a waypoint reads out the cell under the pointer (its block's
/// north-west cell) with dem.tif's elevation there; a click half-way across the chart
/// moves the rover to the middle of the run, where the plan puts it; the scale bar is
/// the map's scale and the north arrow is up on an equirectangular map, turned on a
/// polar one.
fn pointing_reads_the_cell_and_a_click_seeks(dir: &Path, page: &Path, plan: &[HashMap<String, String>]) {
    let data = page_data(page);
    let (dom0, _) = dom(page, "");
    let scale = num(&state(&dom0)["scale"]);
    let w = &plan[plan.len() / 2];
    let (px, py) = pixel(&data, (num(&w["x_m"]), num(&w["y_m"])));
    let (pointed, console) = dom(page, &format!("point={},{}", px * scale, py * scale));
    assert!(console.is_empty(), "{console}");
    let s = state(&pointed);
    let k = data["cells_per_pixel"].as_f64().unwrap();
    let (col, row) = (num(&s["hover-col"]), num(&s["hover-row"]));
    assert!(
        (0.0..k).contains(&(num(&w["col"]) - col)) && (0.0..k).contains(&(num(&w["row"]) - row)),
        "{s:?} for {w:?}"
    );
    let dem = areo_dem(&dir.join("dem.tif"));
    let want = dem.1[row as usize * dem.0 + col as usize];
    assert!((num(&s["hover-elevation"]) - f64::from(want)).abs() < 1e-3, "{s:?}: dem.tif {want}");
    assert!(pointed.contains("elevation ") && pointed.contains("slope "), "the readout says it");
    // A click half-way across the chart's plot (560 px wide, 46 and 40 px margins).
    let (clicked, _) = dom(page, &format!("click={},{}", 46.0 + 0.5 * (560.0 - 86.0), 100));
    let s = state(&clicked);
    let (t0, t1) = (unix_s(&plan[0]["utc"]), unix_s(&plan[plan.len() - 1]["utc"]));
    let t = num(&s["t"]);
    assert!((t - 0.5 * (t0 + t1)).abs() < 1.0, "clicked to {t}, the middle is {}", 0.5 * (t0 + t1));
    let i = plan.iter().rposition(|r| unix_s(&r["utc"]) <= t).unwrap();
    let (a, b) = (&plan[i], &plan[(i + 1).min(plan.len() - 1)]);
    let f = if unix_s(&b["utc"]) > unix_s(&a["utc"]) {
        (t - unix_s(&a["utc"])) / (unix_s(&b["utc"]) - unix_s(&a["utc"]))
    } else {
        0.0
    };
    let (ax, ay) = pixel(&data, (num(&a["x_m"]), num(&a["y_m"])));
    let (bx, by) = pixel(&data, (num(&b["x_m"]), num(&b["y_m"])));
    let (x, y) = (num(&s["rover-x"]), num(&s["rover-y"]));
    assert!((x - (ax + f * (bx - ax))).hypot(y - (ay + f * (by - ay))) < 0.05, "rover at ({x}, {y}) at {t}");
    // The scale bar is as long as the map says; north is up unless the map is polar.
    let per_px = data["cell_m"][0].as_f64().unwrap() * k / scale;
    assert!((num(&s["scale-bar-m"]) / num(&s["scale-bar-px"]) - per_px).abs() < 1e-9 * per_px, "{s:?}");
    // devon-island's map is equirectangular (75° N): north is up. (lunar-south-pole's is
    // polar stereographic, centred on the site's meridian, where north is up too within
    // a tenth of a degree at the image's middle.)
    let north = num(&s["north-deg"]);
    assert!(if data["body"] == "Earth" { north == 0.0 } else { north.abs() < 0.5 }, "{s:?}");
}

/// dem.tif's columns and its elevations, row-major.
fn areo_dem(path: &Path) -> (usize, Vec<f32>) {
    let mut dec = tiff::decoder::Decoder::new(std::fs::File::open(path).unwrap()).unwrap();
    let (cols, _) = dec.dimensions().unwrap();
    match dec.read_image().unwrap() {
        tiff::decoder::DecodingResult::F32(v) => (cols as usize, v),
        _ => panic!("dem.tif is float32"),
    }
}

/// The least distance from `p` to the polyline through `points`.
fn to_polyline(p: (f64, f64), points: &[(f64, f64)]) -> f64 {
    points
        .windows(2)
        .map(|w| {
            let ((x1, y1), (x2, y2)) = (w[0], w[1]);
            let (vx, vy) = (x2 - x1, y2 - y1);
            let t = (((p.0 - x1) * vx + (p.1 - y1) * vy) / (vx * vx + vy * vy)).clamp(0.0, 1.0);
            (p.0 - x1 - t * vx).hypot(p.1 - y1 - t * vy)
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn the_actions_viewer_shows_the_pose_the_wheel_loads_and_the_margin_step_by_step() {
    if !chromium_here() {
        return;
    }
    let dir = run("scenarios/ditch-and-hill.ron").join("task1");
    let page = dir.join("view.html");
    let rows = csv(&dir.join("plan.csv"));
    let data = page_data(&page);
    let steps = data["steps"].as_array().unwrap();
    assert_eq!(steps.len(), rows.len());
    // Every wheel the page draws stands on the ground it draws under its side: the
    // axle a wheel radius from that section (the pose solved on the terrain, and the
    // page's projection of both, agree).
    let r = data["wheel_radius_m"].as_f64().unwrap();
    let (half, spacing) =
        (data["section_half_step_m"][0].as_f64().unwrap(), data["section_half_step_m"][1].as_f64().unwrap());
    let mut worst = 0.0f64;
    for s in steps {
        let along = s["along_m"].as_f64().unwrap();
        for (side, wheels) in [("left_ground_m", 0..3), ("right_ground_m", 3..6)] {
            let section: Vec<(f64, f64)> = (s[side].as_array().unwrap().iter().enumerate())
                .filter_map(|(j, z)| Some((along - half + j as f64 * spacing, z.as_f64()?)))
                .collect();
            for i in wheels {
                let w = &s["wheels_profile_m"][i];
                let d = to_polyline((w[0].as_f64().unwrap(), w[1].as_f64().unwrap()), &section);
                worst = worst.max((d - r).abs());
            }
        }
    }
    assert!(worst < 0.01, "a wheel {worst} m off a wheel radius from its ground");
    let along = along_the_path(&dir, &rows);
    // In the ditch (the lowest body) and on the hill (the steepest pitch).
    let lowest = (0..rows.len()).min_by(|&a, &b| num(&rows[a]["z_m"]).total_cmp(&num(&rows[b]["z_m"]))).unwrap();
    let steepest = (0..rows.len())
        .max_by(|&a, &b| num(&rows[a]["pitch_deg"]).abs().total_cmp(&num(&rows[b]["pitch_deg"]).abs()))
        .unwrap();
    assert!(num(&rows[steepest]["pitch_deg"]).abs() > 15.0, "the hill is climbed");
    let mut shots = Vec::new();
    for k in [lowest, steepest] {
        let fragment = format!("step={}", k + 1);
        let (page_dom, console) = dom(&page, &fragment);
        assert!(console.is_empty(), "the page's console at {fragment}:\n{console}");
        let s = state(&page_dom);
        assert_eq!(s["error"], "", "{s:?}");
        assert_eq!(s["step"], (k + 1).to_string());
        assert_eq!(s["code"], rows[k]["code"]);
        loads_and_margin_are_the_plans(&s, &rows[k], &fragment);
        let rgba = markers_where_the_plan_puts_them(&page, (&s, &data), (&rows[k], along[k]), (k, &fragment));
        shots.push(rgba);
    }
    // The rover moved between the two steps: the pictures differ.
    let differing = shots[0].chunks(4).zip(shots[1].chunks(4)).filter(|(a, b)| a != b).count();
    assert!(differing > 5_000, "{differing} pixels differ between the ditch and the hill");
    // A bad link shows step 1 and says why.
    for (fragment, why) in
        [("step=zero", "\"zero\", is not a step number: showing step 1"), ("step=999", "is outside the plan")]
    {
        let (bad, console) = dom(&page, fragment);
        assert!(console.is_empty(), "{console}");
        let s = state(&bad);
        assert!(s["error"].contains(why), "{fragment}: {s:?}");
        assert_eq!(s["step"], "1");
    }
    let size = std::fs::metadata(&page).unwrap().len();
    assert!(size < 2_000_000, "{size} bytes");
}

#[test]
fn the_earth_plans_viewer_moves_the_shadows_and_the_rover_along_the_plan() {
    // Two waypoints twelve hours apart under the Arctic summer's low Sun.
    check_plan_viewer("scenarios/devon-island.ron", |dt| dt >= 12.0 * 3600.0);
}

/// The actions viewer at plan.csv's `row` (step `k`, `along` m down the path; `s` the
/// page's state, `data` its data) draws the body in profile at its distance and height
/// and the reference point from above where the row puts them, both markers magenta in
/// the screenshot, which it returns.
fn markers_where_the_plan_puts_them(
    page: &Path,
    (s, data): (&HashMap<String, String>, &serde_json::Value),
    (row, along): (&HashMap<String, String>, f64),
    (k, fragment): (usize, &str),
) -> Vec<u8> {
    // The body in profile where plan.csv puts it: its distance along the path and
    // its height, on the page's scale.
    let px = num(&s["profile-px-per-m"]);
    let want = (
        num(&s["profile-origin-x"]) + (along - num(&s["profile-d0"])) * px,
        num(&s["profile-origin-y"]) - (num(&row["z_m"]) - num(&s["profile-z0"])) * px,
    );
    let (bx, by) = (num(&s["body-x"]), num(&s["body-y"]));
    assert!(
        (bx - want.0).abs() <= 1.5 && (by - want.1).abs() <= 1.5,
        "{fragment}: body at ({bx}, {by}), want {want:?}"
    );
    // From above, the reference point where plan.csv puts it on the map.
    let top = from_above(data, row);
    let (tx, ty) = (num(&s["top-x"]), num(&s["top-y"]));
    assert!(
        (tx - top.0).abs() <= 1.0 && (ty - top.1).abs() <= 1.0,
        "{fragment}: from above at ({tx}, {ty}), want {top:?}"
    );
    // Both markers are drawn: magenta at their centres.
    let (sw, _, rgba) = screenshot(page, fragment, &format!("step_{}", k + 1));
    for (x, y) in [
        (num(&s["profile-left"]) + bx, num(&s["profile-top"]) + by),
        (num(&s["top-left"]) + tx, num(&s["top-top"]) + ty),
    ] {
        let o = 4 * (y as usize * sw + x as usize);
        let p = &rgba[o..o + 3];
        assert!(p[0] > 200 && p[1] < 60 && p[2] > 200, "{fragment}: the marker's pixel at ({x}, {y}) is {p:?}");
    }
    rgba
}

/// The distance along the actions plan's path at each of plan.csv's rows, from the
/// start in `commands.json`, m.
fn along_the_path(dir: &Path, rows: &[HashMap<String, String>]) -> Vec<f64> {
    let c: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("commands.json")).unwrap()).unwrap();
    let mut at = (c["start"]["x_m"].as_f64().unwrap(), c["start"]["y_m"].as_f64().unwrap());
    let mut total = 0.0;
    rows.iter()
        .map(|row| {
            let p = (num(&row["x_m"]), num(&row["y_m"]));
            total += (p.0 - at.0).hypot(p.1 - at.1);
            at = p;
            total
        })
        .collect()
}

/// The wheel loads and the stability margin the actions viewer shows (`s`, its state)
/// are plan.csv's `row`.
fn loads_and_margin_are_the_plans(s: &HashMap<String, String>, row: &HashMap<String, String>, fragment: &str) {
    let loads: Vec<f64> = s["loads"].split(',').map(num).collect();
    for (j, col) in ["load_lf_n", "load_lm_n", "load_lr_n", "load_rf_n", "load_rm_n", "load_rr_n"].iter().enumerate() {
        assert!((loads[j] - num(&row[*col])).abs() < 6e-4, "{fragment} {col}: {} vs {}", loads[j], row[*col]);
    }
    match row["stability"].as_str() {
        "" => assert_eq!(s["margin"], ""),
        m => assert!((num(&s["margin"]) - num(m)).abs() < 6e-5, "{fragment}: margin {} vs {m}", s["margin"]),
    }
}

/// Where the actions viewer's top view puts plan.csv's `row`, page pixels from the
/// view's corner.
fn from_above(data: &serde_json::Value, row: &HashMap<String, String>) -> (f64, f64) {
    let (w, h) = (data["width"].as_f64().unwrap(), data["height"].as_f64().unwrap());
    let scale = (360.0 / w).min(560.0 / h);
    let (x0, y0) = (data["map_origin_m"][0].as_f64().unwrap(), data["map_origin_m"][1].as_f64().unwrap());
    let (sx, sy) = (data["map_size_m"][0].as_f64().unwrap(), data["map_size_m"][1].as_f64().unwrap());
    ((num(&row["x_m"]) - x0) / sx * (w * scale).round(), (1.0 - (num(&row["y_m"]) - y0) / sy) * (h * scale).round())
}

/// A goal name and a description made of markup (`</script>`, `<!--<script>`, U+2028,
/// a bidi override) leave the viewer's page one whole script: Chromium runs it without
/// an error, no element is added, and the name reads back from the page's data as
/// written.
#[test]
fn a_name_made_of_markup_leaves_the_viewer_whole() {
    if !chromium_here() {
        return;
    }
    let name = "</script><!--<script>document.title='pwned'</script>\u{2028}\u{202E}&'\"";
    let out = root().join("target").join("view-tests").join("markup");
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_areo"))
        .args(["-q", "run", root().join("tests/tempest/small.ron").to_str().unwrap(), "--out", out.to_str().unwrap()])
        .args(["--set", &format!("job.goals[0].name={}", serde_json::to_string(name).unwrap())])
        .args(["--set", &format!("description={}", serde_json::to_string(name).unwrap())])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let page = out.join("small/view.html");
    let (dom, console) = dom(&page, "");
    assert!(console.is_empty(), "{console}");
    assert!(state(&dom).contains_key("utc"), "the script ran");
    let source = std::fs::read_to_string(&page).unwrap();
    assert_eq!(dom.matches("<script").count(), source.matches("<script").count(), "no element added");
    assert!(!dom.contains("<title>pwned"), "no script of the name's ran");
    fn holds(v: &serde_json::Value, s: &str) -> bool {
        match v {
            serde_json::Value::String(t) => t.contains(s),
            serde_json::Value::Array(a) => a.iter().any(|x| holds(x, s)),
            serde_json::Value::Object(o) => o.values().any(|x| holds(x, s)),
            _ => false,
        }
    }
    assert!(holds(&page_data(&page), name), "the name as written, in the page's data");
    // The actions viewer, with the description made of the same markup.
    let o = Command::new(env!("CARGO_BIN_EXE_areo"))
        .args(["-q", "run", root().join("tests/actions/small.ron").to_str().unwrap()])
        .args(["--out", out.join("actions").to_str().unwrap()])
        .args(["--set", &format!("description={}", serde_json::to_string(name).unwrap())])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let page = out.join("actions/small/view.html");
    let (drawn, console) = self::dom(&page, "");
    assert!(console.is_empty(), "{console}");
    assert!(drawn.contains("id=\"state\""), "the script ran");
    assert!(!drawn.contains("<title>pwned"));
    let source = std::fs::read_to_string(&page).unwrap();
    assert_eq!(drawn.matches("<script").count(), source.matches("<script").count(), "no element added");
}
