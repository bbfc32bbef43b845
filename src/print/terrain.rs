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

/// A tiled shadow run: the lit fraction, the halo it rested on, what was written.
pub(crate) fn tiled_horizon(run: &areo_scenario::terrain::TiledHorizon) -> String {
    format!(
        "{} sectors, horizons below {}° stored as {}° (degrees = code x 180/65535 - 90)\n{} tiles, each read with a halo of {} x {} cells on every side ({:.0} m){}\n",
        run.sectors,
        run.lowest_deg,
        run.lowest_deg,
        run.tiles,
        run.halo_cells.0,
        run.halo_cells.1,
        run.halo_m,
        if run.bigtiff { "; BigTIFF" } else { "" }
    ) + &wrote(std::slice::from_ref(&run.file))
}

pub(crate) fn tiled_shadow(run: &areo_scenario::terrain::TiledShadow) -> String {
    fraction(run.lit_fraction, "in direct sun")
        + &format!(
            "{} tiles, each read with a halo of {} x {} cells toward the Sun (the longest possible shadow: {:.0} m){}\n",
            run.tiles,
            run.halo_cells.0,
            run.halo_cells.1,
            run.halo_m,
            if run.bigtiff { "; BigTIFF" } else { "" }
        )
        + &wrote(std::slice::from_ref(&run.file))
}
