//! `areo terrain …`: what was computed and which files were written.

use std::path::{Path, PathBuf};

/// `wrote FILE` lines.
pub(crate) fn wrote(files: &[PathBuf]) -> String {
    files.iter().map(|f| format!("wrote {}\n", f.display())).collect()
}

/// The DEM's summary, one fact a line under its path.
pub(crate) fn info(path: &Path, lines: &[String]) -> String {
    let mut s = format!("{}\n", path.display());
    for line in lines {
        s += &format!("  {line}\n");
    }
    s
}

/// A fraction of the valid cells, as a sentence.
pub(crate) fn fraction(fraction: f64, what: &str) -> String {
    format!("{:.2} % of the valid cells {what}\n", 100.0 * fraction)
}
