//! Writers: every output file goes through here, to a temporary name renamed into
//! place once complete, with errors that name the file.

pub(crate) mod bands;
pub mod csv;
pub mod escape;
pub(crate) mod geojson;
pub(crate) mod kml;
pub(crate) mod layout;
pub(crate) mod lock;
pub(crate) mod plots;
pub(crate) mod png;
pub(crate) mod reports;
pub(crate) mod staging;

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Writes `bytes` to `path` through a temporary file beside it, renamed into place
/// once complete: an interrupted run never leaves a truncated file under the real
/// name. Errors name the file.
pub(crate) fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |source| Error::Io { path: path.to_path_buf(), source };
    let partial = partial_name(path);
    let written = fresh(&partial).and_then(|mut f| {
        f.write_all(bytes)?;
        f.sync_all()
    });
    if let Err(e) = written.and_then(|()| std::fs::rename(&partial, path)) {
        // Best effort: the partial file is of no use to anyone.
        let _ = std::fs::remove_file(&partial);
        return Err(io(e));
    }
    Ok(())
}

/// Writes `path` through `write`, which is handed a temporary name beside it; the
/// file is renamed into place only if `write` succeeds (for writers that take a path,
/// like the GeoTIFF and plot writers).
pub(crate) fn write_with(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let partial = partial_name(path);
    // The writer opens the name itself: reserve it as a new, empty file of ours first.
    fresh(&partial).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
    match write(&partial)
        .and_then(|()| std::fs::rename(&partial, path).map_err(|source| Error::Io { path: path.to_path_buf(), source }))
    {
        Ok(()) => Ok(()),
        Err(e) => {
            // Best effort: the partial file is of no use to anyone.
            let _ = std::fs::remove_file(&partial);
            Err(e)
        }
    }
}

/// Creates `partial` as a new file: whatever was there (a file left by an interrupted
/// run, or a planted link to something to overwrite) is removed — the name, never what a
/// link points at — and the file is created exclusively, so a link made in between
/// makes the write fail rather than follow it.
fn fresh(partial: &Path) -> std::io::Result<std::fs::File> {
    match std::fs::remove_file(partial) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(e),
        _ => {}
    }
    std::fs::OpenOptions::new().write(true).create_new(true).open(partial)
}

/// A staging name beside `path`, this process's alone; stale ones of processes gone
/// are cleared first.
fn partial_name(path: &Path) -> PathBuf {
    staging::clear_stale(path);
    staging::staging_path(path, "partial")
}

/// `value` as JSON (pretty), or an error naming the file it was meant for.
pub(crate) fn json_for(path: &Path, value: &impl serde::Serialize, pretty: bool) -> Result<String> {
    let text = if pretty { serde_json::to_string_pretty(value) } else { serde_json::to_string(value) };
    text.map_err(|e| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e) })
}

/// " (137.20° on the grid, …)" where the map's north is not true north there (a polar map
/// whose central meridian is not the site's), else nothing.
pub fn grid_azimuth_said(true_deg: f64, grid_deg: f64) -> String {
    let turn = (grid_deg - true_deg + 540.0).rem_euclid(360.0) - 180.0;
    if turn.abs() < 5e-3 {
        String::new()
    } else {
        format!(" ({grid_deg:.2}° on the grid, whose north is not true north here)")
    }
}

/// `n` with its noun, singular for one: "1 charge", "3 charges", "0 samples".
pub(crate) fn counted(n: usize, noun: &str) -> String {
    if n == 1 { format!("1 {noun}") } else { format!("{n} {noun}s") }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Links planted at staging names (of a process that is gone) are removed, never
    /// followed: the file they point at keeps its contents.
    #[cfg(unix)]
    #[test]
    fn a_planted_link_at_a_staging_name_is_not_followed() {
        let dir = std::env::temp_dir().join(format!("areo-link-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let victim = dir.join("victim.txt");
        std::fs::write(&victim, "precious").unwrap();
        // Above any Linux pid_max: no such process.
        for name in ["plan.csv", "map.tif"] {
            let stale = format!(".{name}.partial-{}-4194305-0", staging::host());
            std::os::unix::fs::symlink(&victim, dir.join(stale)).unwrap();
        }
        let path = dir.join("plan.csv");
        write_file(&path, b"a,b\n").unwrap();
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b\n");
        let tif = dir.join("map.tif");
        write_with(&tif, |p| std::fs::write(p, "tiff").map_err(|source| Error::Io { path: p.to_path_buf(), source }))
            .unwrap();
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().map(|e| e.file_name()).collect();
        assert_eq!(left.len(), 3, "the links are gone: {left:?}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn files_are_written_whole_or_not_at_all() {
        let dir = std::env::temp_dir().join(format!("areo-write-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("plan.csv");
        write_file(&path, b"a,b\n1,2\n").unwrap();
        write_file(&path, b"a,b\n3,4\n").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b\n3,4\n");
        assert!(!dir.join("plan.csv.partial").exists());
        // Into a directory that does not exist: an error naming the file, nothing left.
        let missing = dir.join("no-such-dir").join("plan.json");
        let err = write_file(&missing, b"{}").unwrap_err();
        assert!(err.to_string().contains("no-such-dir/plan.json"), "{err}");
        assert!(!missing.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn json_that_cannot_be_written_is_an_error_naming_the_file() {
        // A map with non-string keys is not JSON.
        let bad: std::collections::HashMap<(u8, u8), u8> = [((1, 2), 3)].into_iter().collect();
        let err = json_for(Path::new("out/x/facts.json"), &bad, true).unwrap_err();
        assert!(err.to_string().contains("out/x/facts.json"), "{err}");
        assert_eq!(json_for(Path::new("f.json"), &[1, 2], false).unwrap(), "[1,2]");
    }

    #[test]
    fn counts_are_singular_for_one_only() {
        assert_eq!(super::counted(1, "charge"), "1 charge");
        assert_eq!(super::counted(0, "sample"), "0 samples");
        assert_eq!(super::counted(12, "re-plan"), "12 re-plans");
    }
}
