//! Fixtures the tests of the layers a planner lays over the map share (no-go masks,
//! terrain classes): scratch folders, ESRI ASCII grids, a quiet run and its CSVs.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub(crate) fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// An empty folder `target/GROUP/NAME`.
pub(crate) fn scratch(group: &str, name: &str) -> PathBuf {
    let dir = root().join("target").join(group).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes the ESRI ASCII grid `name` in `dir`: `cols` × `rows` cells of `cell` m from
/// (0, 0), `value(col, row)` (row 0 north). Returns its name.
pub(crate) fn ascii_grid(
    dir: &Path,
    name: &str,
    (cols, rows, cell): (usize, usize, f64),
    value: impl Fn(usize, usize) -> String,
) -> String {
    let mut text =
        format!("ncols {cols}\nnrows {rows}\nxllcorner 0\nyllcorner 0\ncellsize {cell}\nNODATA_value -9999\n");
    for r in 0..rows {
        let row: Vec<String> = (0..cols).map(|c| value(c, r)).collect();
        text += &row.join(" ");
        text.push('\n');
    }
    std::fs::write(dir.join(name), text).unwrap();
    name.to_string()
}

/// `areo -q run PATH --out OUT`.
pub(crate) fn run(path: &Path, out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_areo"))
        .args(["-q", "run", path.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap()
}

/// A CSV's rows by column name.
pub(crate) fn csv(path: &Path) -> Vec<HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines.map(|l| header.iter().cloned().zip(l.split(',').map(String::from)).collect()).collect()
}

pub(crate) fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}
