//! `areo terrain …`: what was computed and which files were written.

use std::path::PathBuf;

use areo_scenario::terrain::DemInfo;

/// `wrote FILE` lines.
pub(crate) fn wrote(files: &[PathBuf]) -> String {
    files.iter().map(|f| format!("wrote {}\n", f.display())).collect()
}

/// The DEM's summary, one fact a line under its path.
pub(crate) fn info(i: &DemInfo) -> String {
    let [west, east, south, north] = i.extent_m;
    let mut lines = vec![
        format!("size        {} × {} cells ({} valid, {} missing)", i.cols, i.rows, i.valid_cells, i.missing_cells),
        format!("cell size   {} m × {} m", i.cell_m[0], i.cell_m[1]),
        format!("extent      x {west} .. {east} m, y {south} .. {north} m"),
        match i.elevation_m {
            Some([lo, hi, mean]) => format!("elevation   {lo} .. {hi} m (mean {mean:.2} m)"),
            None => "elevation   none: every cell is missing".to_string(),
        },
    ];
    let mut projection = format!("projection  {}", i.projection);
    if let Some(crs) = &i.crs_not_read {
        projection += &format!(" (the file's CRS, {crs}, is a projection areo does not read)");
    }
    if let Some(lat) = i.lat_ts_deg {
        projection += &format!(", standard parallel {lat}°");
    }
    if let Some(pole) = i.pole {
        projection += &format!(", {pole} pole");
    }
    if let Some(lon) = i.lon0_deg {
        projection += &format!(", central meridian {lon}°E");
    }
    lines.push(projection);
    lines.push(format!(
        "body        {}a = {} m, b = {} m",
        i.body.map_or(String::new(), |b| format!("{b}, ")),
        i.radii_m[0],
        i.radii_m[1]
    ));
    if let Some([lat, lon]) = i.centre_deg {
        lines.push(format!("centre      {lat:.6}°, {lon:.6}°E"));
    }
    let mut s = format!("{}\n", i.file.display());
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
        "{} sectors, horizons below {}° stored as {}° (degrees = code x 180/65535 - 90)\n{} tiles, each read with a halo of {} × {} cells on every side ({:.0} m){}\n",
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
            "{} tiles, each read with a halo of {} × {} cells toward the Sun (the longest possible shadow: {:.0} m){}\n",
            run.tiles,
            run.halo_cells.0,
            run.halo_cells.1,
            run.halo_m,
            if run.bigtiff { "; BigTIFF" } else { "" }
        )
        + &wrote(std::slice::from_ref(&run.file))
}

/// Where `--utc` put the Sun.
pub(crate) fn sun_over(sun: &areo_scenario::terrain::SunOver) -> String {
    format!(
        "Sun at {} over the map's middle ({:.4}°, {:.4}°E on {}): azimuth {:.2}°{}, elevation {:.2}°{}\n",
        sun.utc,
        sun.lat_deg,
        sun.lon_east_deg,
        sun.body,
        sun.azimuth_deg,
        areo_scenario::output::grid_azimuth_said(sun.azimuth_deg, sun.grid_azimuth_deg),
        sun.elevation_deg,
        if sun.elevation_deg <= 0.0 { " (below the horizon: the map is dark)" } else { "" }
    )
}
