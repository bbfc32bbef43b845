//! Names drawn from the whole of Unicode — every plane, control characters, the HTML,
//! XML and CSV specials, bidirectional controls, non-characters — through a TEMPEST run
//! (a goal's name and the description) and an actions run (the description): each is
//! refused at load naming its field, or every output of the run parses with a strict
//! parser — XML (KML, SVG) with roxmltree, JSON with serde_json, CSV with the csv crate
//! (every record as wide as the header, no text cell a spreadsheet would run as a
//! formula), and the viewers' data block holds no markup that could end, comment out or
//! open a script. (The browser's own reading of such a page is in the root crate's
//! `tests/view.rs`.)

use std::path::{Path, PathBuf};

use areo_scenario::budget::Budget;
use areo_scenario::format::load_set;
use areo_scenario::{NoProgress, RunOptions, run};
use rand::{RngExt, SeedableRng};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Pieces a hostile name is made of.
const SPECIALS: &[&str] = &[
    "</script>",
    "<!--",
    "<script>",
    "]]>",
    "&amp;",
    "\"",
    "'",
    "=HYPERLINK(\"x\")",
    "+1",
    "-cmd",
    "@SUM(A1)",
    "\t",
    "\r",
    "\n",
    "\u{2028}",
    "\u{2029}",
    "\u{202E}",
    "\u{2066}",
    "\u{200B}",
    "\u{FEFF}",
    "\u{FFFE}",
    "\u{FFFF}",
    "\u{1B}[31m",
    "\u{9B}",
    "\u{7F}",
    ",",
    "\\",
    "${x}",
];

/// A name of 1–6 pieces: specials and code points from every plane.
fn hostile(rng: &mut rand_chacha::ChaCha8Rng) -> String {
    let mut name = String::new();
    for _ in 0..rng.random_range(1..=6) {
        if rng.random_bool(0.5) {
            name += SPECIALS[rng.random_range(0..SPECIALS.len())];
        } else {
            let plane = [0u32, 0, 0, 1, 2, 3, 14, 15, 16][rng.random_range(0..9)];
            let c = (0..).find_map(|_| char::from_u32(plane * 0x10000 + rng.random_range(0..0x10000))).unwrap();
            name.push(c);
        }
    }
    name
}

/// What a strict reader says of each output under `dir` (recursively): `Err` names
/// the file and what is wrong.
fn check_outputs(dir: &Path, checked: &mut usize) -> Result<(), String> {
    for entry in std::fs::read_dir(dir).map_err(|e| e.to_string())? {
        let path = entry.map_err(|e| e.to_string())?.path();
        if path.is_dir() {
            check_outputs(&path, checked)?;
            continue;
        }
        let ext = path.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default();
        let bad = |m: String| format!("{}: {m}", path.display());
        match ext.as_str() {
            "kml" | "svg" => {
                let text = std::fs::read_to_string(&path).map_err(|e| bad(e.to_string()))?;
                roxmltree::Document::parse(&text).map_err(|e| bad(format!("not well-formed XML: {e}")))?;
            }
            "json" | "geojson" | "czml" => {
                let text = std::fs::read_to_string(&path).map_err(|e| bad(e.to_string()))?;
                serde_json::from_str::<serde_json::Value>(&text).map_err(|e| bad(format!("not JSON: {e}")))?;
            }
            "csv" => check_csv(&path).map_err(bad)?,
            "html" => check_page(&path).map_err(bad)?,
            _ => continue,
        }
        *checked += 1;
    }
    Ok(())
}

fn check_csv(path: &Path) -> Result<(), String> {
    let mut reader = csv::ReaderBuilder::new().flexible(true).from_path(path).map_err(|e| e.to_string())?;
    let width = reader.headers().map_err(|e| e.to_string())?.len();
    for record in reader.records() {
        let record = record.map_err(|e| e.to_string())?;
        if record.len() != width {
            return Err(format!("a record of {} fields under a header of {width}: {record:?}", record.len()));
        }
        if let Some(cell) =
            record.iter().find(|c| c.starts_with(['=', '+', '-', '@', '\t', '\r']) && c.trim().parse::<f64>().is_err())
        {
            return Err(format!("the cell {cell:?} would run as a formula"));
        }
    }
    Ok(())
}

/// The page's inline script (data block included) holds no `</script`, `<!--` or
/// `<script` past its opening tag, so the browser reads it as one script.
fn check_page(path: &Path) -> Result<(), String> {
    let page = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let lower = page.to_lowercase();
    let mut at = 0;
    while let Some(open) = lower[at..].find("<script").map(|i| at + i) {
        let body = lower[open..].find('>').map(|i| open + i + 1).ok_or("an unclosed <script tag")?;
        let close = lower[body..].find("</script").map(|i| body + i).ok_or("a script that never ends")?;
        let script = &lower[body..close];
        for bad in ["<!--", "<script", "\u{2028}", "\u{2029}"] {
            if script.contains(bad) {
                return Err(format!("{bad:?} inside a script"));
            }
        }
        at = close + 1;
    }
    Ok(())
}

/// Loads `scenario` with `field` set to `name`: `None` where the name is refused at
/// load, naming the field.
fn with_name(scenario: &str, field: &str, name: &str) -> Option<areo_scenario::format::ScenarioFile> {
    let value = ron::to_string(name).unwrap();
    match load_set(&root().join(scenario), &[format!("{field}={value}")]) {
        Ok(file) => Some(file),
        Err(e) => {
            let text = e.to_string();
            assert!(text.contains(field) || text.contains("name"), "{name:?}: refused without its field: {text}");
            None
        }
    }
}

fn run_checked(file: &areo_scenario::format::ScenarioFile, dir: &Path, name: &str) -> usize {
    let _ = std::fs::remove_dir_all(dir);
    let opts = RunOptions { out_dir: Some(dir), progress: &NoProgress, budget: Budget::for_this_machine() };
    let outcome = run(file, opts).unwrap_or_else(|e| panic!("{name:?}: {e}"));
    assert!(outcome.failure.is_none(), "{name:?}: {:?}", outcome.failure);
    let mut checked = 0;
    check_outputs(dir, &mut checked).unwrap_or_else(|e| panic!("{name:?}: {e}"));
    checked
}

#[test]
fn outputs_of_runs_with_names_from_all_of_unicode_parse_strictly() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2026);
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("hostile-names");
    let (mut ran, mut refused, mut files) = (0, 0, 0);
    for case in 0..10 {
        let (goal, description) = (hostile(&mut rng), hostile(&mut rng));
        let Some(file) = with_name("tests/tempest/small.ron", "job.goals[0].name", &goal) else {
            refused += 1;
            continue;
        };
        let text = ron::to_string(&description).unwrap();
        let Ok(file) = load_set(
            &file.path,
            &[format!("job.goals[0].name={}", ron::to_string(&goal).unwrap()), format!("description={text}")],
        ) else {
            refused += 1;
            continue;
        };
        files += run_checked(&file, &dir.join(format!("tempest-{case}")), &goal);
        ran += 1;
    }
    // Both kinds of outcome happen, and most names are carried, not refused.
    assert!(ran >= 5 && refused >= 1, "{ran} ran, {refused} refused");
    assert!(files >= ran * 8, "{files} files checked");
    for case in 0..3 {
        let description = hostile(&mut rng) + "</script><!--<script>=1+1\u{2028}";
        let file =
            with_name("tests/actions/small.ron", "description", &description).expect("a description is any text");
        let written = run_checked(&file, &dir.join(format!("actions-{case}")), &description);
        assert!(written >= 8, "{written} files of the actions run checked");
    }
    // A name that alone starts a formula is carried, defused in every CSV.
    let file = with_name("tests/tempest/small.ron", "job.goals[0].name", "=cmd|' /C calc'!A0").unwrap();
    run_checked(&file, &dir.join("formula"), "formula");
    let plan = std::fs::read_to_string(dir.join("formula/plan.csv")).unwrap();
    assert!(plan.contains("'=cmd|' /C calc'!A0"), "the goal's cell in plan.csv: {plan}");
}
