//! The no-go mask end to end: a wall drawn on a raster forces the detour a plain
//! breadth-first search on the same grid finds, inflation grows the mask by the disc it
//! names, and masks that cannot be used — on the start, around a goal, off the map, on
//! another CRS, with holes — are errors naming what is wrong.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

mod layers;
use layers::{ascii_grid, csv, root, run, scratch, stderr};

const COLS: usize = 30;
const ROWS: usize = 20;
const CELL: f64 = 50.0;

/// A flat 30 × 20 map of 50 m cells, from `start` to `goal` (map metres), with the
/// no-go block `no_go` (RON) if given.
fn scenario(dir: &Path, start: (f64, f64), goal: (f64, f64), no_go: &str) -> PathBuf {
    let path = dir.join("walled.ron");
    std::fs::write(
        &path,
        format!(
            r#"Scenario(version: 1, description: "a wall", job: Tempest(body: Mars,
            terrain: Synth(cols: {COLS}, rows: {ROWS}, cell_m: {CELL}, seed: 1, noise: (amplitude_m: 0.0, wavelength_m: 400.0, octaves: 1), features: []),
            site: (lat_deg: -4.6, lon_east_deg: 137.4), start_utc: "2012-08-06T22:00:00Z", horizon_h: 12,
            start: (x_m: {}, y_m: {}), start_battery_above_floor_wh: 600,
            goals: [(name: "east", x_m: {}, y_m: {})],
            {no_go}))"#,
            start.0, start.1, goal.0, goal.1
        ),
    )
    .unwrap();
    path
}

/// An ESRI ASCII mask on the map's grid: `marked(col, row)` (row 0 north) is kept out.
fn mask(dir: &Path, name: &str, marked: impl Fn(usize, usize) -> bool) -> String {
    ascii_grid(dir, name, (COLS, ROWS, CELL), |c, r| if marked(c, r) { "1" } else { "0" }.to_string())
}

/// Fewest 8-connected steps from `a` to `b` (col, row) over cells `open` allows.
fn fewest_steps(a: (usize, usize), b: (usize, usize), open: impl Fn(usize, usize) -> bool) -> Option<usize> {
    let mut dist = vec![usize::MAX; COLS * ROWS];
    dist[a.1 * COLS + a.0] = 0;
    let mut queue = VecDeque::from([a]);
    while let Some((c, r)) = queue.pop_front() {
        if (c, r) == b {
            return Some(dist[r * COLS + c]);
        }
        for dr in -1i64..=1 {
            for dc in -1i64..=1 {
                let (nc, nr) = (c as i64 + dc, r as i64 + dr);
                if (dc, dr) == (0, 0) || nc < 0 || nr < 0 || nc >= COLS as i64 || nr >= ROWS as i64 {
                    continue;
                }
                let (nc, nr) = (nc as usize, nr as usize);
                if open(nc, nr) && dist[nr * COLS + nc] == usize::MAX {
                    dist[nr * COLS + nc] = dist[r * COLS + c] + 1;
                    queue.push_back((nc, nr));
                }
            }
        }
    }
    None
}

#[test]
fn a_wall_in_the_mask_forces_the_detour_a_breadth_first_search_finds() {
    let dir = scratch("no-go-tests", "wall");
    // A wall down column 15 from the north edge, open in the southern row only.
    let wall = |c: usize, r: usize| c == 15 && r < 19;
    let file = mask(&dir, "wall.asc", wall);
    let (start, goal) = ((2, 2), (27, 2));
    let at = |(c, r): (usize, usize)| ((c as f64 + 0.5) * CELL, (ROWS as f64 - r as f64 - 0.5) * CELL);
    let path = scenario(&dir, at(start), at(goal), &format!("no_go: (file: \"{file}\")"));
    let out = dir.join("out");
    let o = run(&path, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let plan = csv(&out.join("walled/plan.csv"));
    // Never on the wall, and as few drives as the shortest way round it.
    for w in &plan {
        let (c, r): (usize, usize) = (w["col"].parse().unwrap(), w["row"].parse().unwrap());
        assert!(!wall(c, r), "the plan enters the wall at ({c}, {r})");
    }
    let drives = plan.iter().filter(|w| w["action"].starts_with("drive")).count();
    let around = fewest_steps(start, goal, |c, r| !wall(c, r)).unwrap();
    let straight = fewest_steps(start, goal, |_, _| true).unwrap();
    assert!(around > straight, "the wall must cost steps: {around} vs {straight}");
    assert_eq!(drives, around, "drives of the plan against the fewest steps round the wall");
    // The facts and the layer say so.
    let facts: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("walled/facts.json")).unwrap()).unwrap();
    assert_eq!(facts["no_go.masked_cells"], 19);
    assert_eq!(facts["no_go.inflated_cells"], 0);
    assert_eq!(facts["no_go.island_cells"], 0);
    assert!(out.join("walled/no_go.tif").exists());
    // The viewer tints the same 19 cells (its image is the whole 30 × 20 map here).
    let html = std::fs::read_to_string(out.join("walled/view.html")).unwrap();
    let start = html.find("type=\"application/json\">").unwrap() + "type=\"application/json\">".len();
    let data: serde_json::Value =
        serde_json::from_str(&html[start..start + html[start..].find("</script>").unwrap()].replace("<\\/", "</"))
            .unwrap();
    use base64::Engine;
    let bits = base64::engine::general_purpose::STANDARD.decode(data["no_go"].as_str().unwrap()).unwrap();
    let (w, h) = (data["width"].as_u64().unwrap() as usize, data["height"].as_u64().unwrap() as usize);
    assert_eq!((w, h), (COLS, ROWS));
    let marked: Vec<(usize, usize)> =
        (0..w * h).filter(|&i| (bits[i / 8] >> (i % 8)) & 1 == 1).map(|i| (i % w, i / w)).collect();
    assert_eq!(marked, (0..19).map(|r| (15, r)).collect::<Vec<_>>());
    assert!(String::from_utf8_lossy(&o.stdout).contains("no-go mask wall.asc: 19 cells kept out"));
}

#[test]
fn inflation_grows_the_mask_by_its_disc_and_a_closed_ring_makes_an_island() {
    let dir = scratch("no-go-tests", "inflate");
    let file = mask(&dir, "dot.asc", |c, r| (c, r) == (20, 3));
    // 120 m around a cell of 50 m: the cells whose centres lie within it, the lattice
    // points with 2500 (dc² + dr²) ≤ 14 400, 21 of them with the dot.
    let path = scenario(&dir, (125.0, 525.0), (1375.0, 525.0), &format!("no_go: (file: \"{file}\", inflate_m: 120)"));
    let out = dir.join("out");
    let o = run(&path, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let facts: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("walled/facts.json")).unwrap()).unwrap();
    assert_eq!(facts["no_go.masked_cells"], 1);
    assert_eq!(facts["no_go.inflated_cells"], 20);
    // A ring round the north-east corner: the cells inside it are an island, reported.
    let ring = |c: usize, r: usize| (c == 24 && r <= 4) || (r == 4 && c >= 24);
    let file = mask(&dir, "ring.asc", ring);
    let path = scenario(&dir, (125.0, 525.0), (1375.0, 525.0), &format!("no_go: (file: \"{file}\")"));
    let o = run(&path, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let facts: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("walled/facts.json")).unwrap()).unwrap();
    assert_eq!(facts["no_go.island_cells"], 5 * 4, "columns 25–29 of rows 0–3");
}

#[test]
fn masks_that_cannot_be_used_are_errors_naming_what_is_wrong() {
    let dir = scratch("no-go-tests", "bad");
    let wall = mask(&dir, "wall.asc", |c, r| c == 15 && r < 17);
    let out = dir.join("out");
    // Each: the no_go block, the start, the goal (map metres), what the error says.
    type Case = (String, (f64, f64), (f64, f64), &'static str);
    let cases: Vec<Case> = vec![
        // The start on the wall.
        (format!("no_go: (file: \"{wall}\")"), (775.0, 525.0), (1375.0, 525.0), "field `job.start`"),
        // The goal within the inflation.
        (format!("no_go: (file: \"{wall}\", inflate_m: 100)"), (125.0, 525.0), (825.0, 525.0), "within inflate_m"),
        // A goal inside a closed ring.
        (
            format!("no_go: (file: \"{}\")", mask(&dir, "ring.asc", |c, r| (c == 24 && r <= 4) || (r == 4 && c >= 24))),
            (125.0, 525.0),
            (1425.0, 925.0),
            "cut off from the start by the no-go mask",
        ),
        // Inflation out of range.
        (format!("no_go: (file: \"{wall}\", inflate_m: -5)"), (125.0, 525.0), (1375.0, 525.0), "inflate_m"),
    ];
    for (block, start, goal, want) in cases {
        let o = run(&scenario(&dir, start, goal, &block), &out);
        assert_eq!(o.status.code(), Some(2), "{block}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{block}: {}", stderr(&o));
    }
    // Off the map.
    std::fs::write(
        dir.join("far.asc"),
        format!("ncols 2\nnrows 2\nxllcorner 100000\nyllcorner 0\ncellsize {CELL}\n1 1\n1 1\n"),
    )
    .unwrap();
    // Holes (no-data) where it covers the map.
    let holes = std::fs::read_to_string(dir.join("wall.asc")).unwrap().replacen(" 0 ", " -9999 ", 1);
    std::fs::write(dir.join("holes.asc"), holes).unwrap();
    // Another CRS: the Gale crop is equirectangular on Mars; the map is a local frame.
    let gale = root().join("crates/terrain/tests/data/gale_mola_crop_64.tif");
    std::fs::copy(gale, dir.join("gale.tif")).unwrap();
    for (name, want) in [
        ("far.asc", "does not overlap the map"),
        ("holes.asc", "1 cells of the map fall on cells of the mask with no value"),
        ("gale.tif", "the raster's CRS"),
        ("missing.asc", "missing.asc"),
    ] {
        let o = run(&scenario(&dir, (125.0, 525.0), (1375.0, 525.0), &format!("no_go: (file: \"{name}\")")), &out);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        assert!(stderr(&o).contains(want) && stderr(&o).contains("job.no_go.file"), "{name}: {}", stderr(&o));
    }
}

/// Mask codes of any magnitude are values (a UInt32 code of 4e9, a float of 1e8 keep
/// out, as any non-zero does), an inflation of any radius the scenario allows costs one
/// distance per cell (10 km on a map of 1 m cells: a disc of cells per masked cell was
/// 3 × 10⁸ offsets, and the process aborted), and a start in the mask is placed in the
/// scenario's own metres, with the map's beside them.
#[test]
fn masks_of_any_value_and_inflations_of_any_radius_are_read_or_refused_in_words() {
    let dir = scratch("no-go-tests", "extreme");
    let codes = ascii_grid(&dir, "codes.asc", (COLS, ROWS, CELL), |c, r| match (c, r) {
        (15, 0..=9) => "4000000000".into(),
        (15, 10..=18) => "1e8".into(),
        _ => "0".into(),
    });
    let at = |(c, r): (usize, usize)| ((c as f64 + 0.5) * CELL, (ROWS as f64 - r as f64 - 0.5) * CELL);
    let out = dir.join("out");
    let o = run(&scenario(&dir, at((2, 2)), at((27, 2)), &format!("no_go: (file: \"{codes}\")")), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let facts: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("walled/facts.json")).unwrap()).unwrap();
    assert_eq!(facts["no_go.masked_cells"], 19);
    let plan = csv(&out.join("walled/plan.csv"));
    assert!(plan.iter().any(|w| w["col"] == "15" && w["row"] == "19"), "round the wall's open end");

    // 10 km of inflation around one cell of a 300 × 300 map of 1 m cells: every cell is
    // within it, the start too — refused in words, at once.
    let one_m =
        ascii_grid(&dir, "dot.asc", (300, 300, 1.0), |c, r| if (c, r) == (150, 150) { "1" } else { "0" }.into());
    let path = dir.join("fine.ron");
    std::fs::write(
        &path,
        format!(
            r#"Scenario(version: 1, description: "fine", job: Tempest(body: Mars,
            terrain: Synth(cols: 300, rows: 300, cell_m: 1.0, seed: 1, noise: (amplitude_m: 0.0, wavelength_m: 40.0, octaves: 1), features: []),
            site: (lat_deg: -4.6, lon_east_deg: 137.4), start_utc: "2012-08-06T22:00:00Z", horizon_h: 2,
            start: (x_m: 5.5, y_m: 5.5), start_battery_above_floor_wh: 600,
            goals: [(name: "east", x_m: 290.5, y_m: 5.5)],
            no_go: (file: "{one_m}", inflate_m: 10000)))"#
        ),
    )
    .unwrap();
    let o = run(&path, &out);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("(5.5, 5.5) m") && stderr(&o).contains("within inflate_m"), "{}", stderr(&o));

    // On the Gale crop (a map whose metres start far from 0) a mask without a CRS is in
    // the scenario's metres: the start on it is said in those, the map's beside them.
    std::fs::copy(root().join("scenarios/data/gale_mola_crop_64.tif"), dir.join("gale.tif")).unwrap();
    let all = ascii_grid(&dir, "all.asc", (64, 64, 470.0), |_, _| "1".into());
    let path = dir.join("gale.ron");
    std::fs::write(
        &path,
        format!(
            r#"Scenario(version: 1, description: "gale", job: Tempest(terrain: File("gale.tif"),
            site: (lat_deg: -5.2734, lon_east_deg: 137.6719), start_utc: "2012-08-06T22:15:00Z", horizon_h: 12,
            start: (x_m: 18670, y_m: 24770), start_battery_above_floor_wh: 600,
            goals: [(name: "north_west", x_m: 14000, y_m: 26000)],
            no_go: (file: "{all}")))"#
        ),
    )
    .unwrap();
    let o = run(&path, &out);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("(18670.0, 24770.0) m (the map's (8127674.4, -302611.8) m) is in the no-go mask"), "{err}");
}
