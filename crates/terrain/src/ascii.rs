//! ESRI ASCII grid (`.asc`): a short header (`ncols`, `nrows`, `xllcorner`/`xllcenter`,
//! `yllcorner`/`yllcenter`, `cellsize` — or GDAL's `dx`/`dy` — and optional
//! `NODATA_value`) followed by rows of numbers from north to south.

use std::path::Path;

use crate::dem::Dem;
use crate::error::{Error, Result};

/// Reads an ESRI ASCII grid, and the `.prj` beside it where that says the grid is in
/// longitude and latitude (a WKT `GEOGCS`, as GDAL writes one): then the grid is read
/// as the equirectangular grid it is, on the `.prj`'s sphere, like a geographic
/// GeoTIFF — before, its degrees were read as metres. Another `.prj` (a projected CRS)
/// leaves the grid in its own metres, with no place on a body.
pub fn read(path: &Path) -> Result<Dem> {
    let text = crate::input::read_text(path, crate::input::RASTER_LIMIT)
        .map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
    let dem = parse(&text, path)?;
    let prj = path.with_extension("prj");
    match crate::input::read_text(&prj, 1 << 20) {
        Ok(wkt) if wkt.trim_start().starts_with("GEOGCS[") => geographic(dem, &wkt, &prj),
        _ => Ok(dem),
    }
}

/// `dem`, in degrees, as metres on the sphere the WKT's `SPHEROID["name", a, 1/f]`
/// gives (its equatorial radius, as areo's projections use).
fn geographic(dem: Dem, wkt: &str, prj: &Path) -> Result<Dem> {
    let bad = |m: String| Error::format(prj, m);
    let numbers: Vec<f64> = wkt
        .split_once("SPHEROID[")
        .map(|(_, rest)| rest.split(']').next().unwrap_or(""))
        .map(|inside| inside.split(',').skip(1).filter_map(|v| v.trim().parse().ok()).collect())
        .unwrap_or_default();
    let (a, inv_f) = match numbers[..] {
        [a, inv_f, ..] if (1e3..=1e8).contains(&a) && (0.0..1e9).contains(&inv_f) => (a, inv_f),
        _ => return Err(bad("a GEOGCS without a SPHEROID[name, semi-major axis 1 km..100 000 km, 1/f]".into())),
    };
    let b = if inv_f == 0.0 { a } else { a * (1.0 - 1.0 / inv_f) };
    let surface = crate::Spheroid { equatorial_radius_m: a, polar_radius_m: b };
    let ([dx, dy, x0, y_top], projection) = crate::projection::equirectangular_from_degrees(
        (dem.cols(), dem.rows()),
        (dem.x0(), dem.y_top()),
        (dem.dx(), dem.dy()),
        &surface,
    )
    .map_err(bad)?;
    Dem::new(dem.cols(), dem.rows(), dx, dy, x0, y_top, dem.elevations().to_vec())
        .and_then(|d| d.with_mask(dem.valid_mask().to_vec()))
        .map(|d| d.with_georef(crate::Georef { projection, surface }))
        .map_err(|e| bad(e.to_string()))
}

/// The header keys of an ESRI ASCII grid, as read (each `None` until given).
struct Header {
    ncols: Option<f64>,
    nrows: Option<f64>,
    dx: Option<f64>,
    dy: Option<f64>,
    xll: Option<f64>,
    yll: Option<f64>,
    /// The lower-left is a cell's centre (`xllcenter`), not its corner.
    centre: bool,
    nodata: Option<f64>,
}

/// Reads the header lines of `lines` up to the first line of data (left unread).
fn read_header(
    lines: &mut std::iter::Peekable<std::iter::Enumerate<std::str::Lines<'_>>>,
    path: &Path,
) -> Result<Header> {
    let bad = |line: usize, m: String| Error::format(path, format!("line {line}: {m}"));
    let (mut ncols, mut nrows, mut dx, mut dy) = (None, None, None, None);
    let (mut xll, mut yll, mut centre) = (None, None, false);
    let mut nodata: Option<f64> = None;
    while let Some((i, line)) = lines.peek().copied() {
        let mut parts = line.split_whitespace();
        let Some(key) = parts.next() else {
            lines.next();
            continue;
        };
        if key.parse::<f64>().is_ok() {
            break; // the data starts
        }
        let value = parts.next().ok_or_else(|| bad(i + 1, format!("`{key}` has no value")))?;
        let num = value.parse::<f64>().map_err(|_| bad(i + 1, format!("`{key}` = {value:?} is not a number")))?;
        match key.to_ascii_lowercase().as_str() {
            "ncols" => ncols = Some(num),
            "nrows" => nrows = Some(num),
            "cellsize" => {
                dx = Some(num);
                dy = Some(num);
            }
            "dx" => dx = Some(num),
            "dy" => dy = Some(num),
            "xllcorner" => xll = Some(num),
            "yllcorner" => yll = Some(num),
            "xllcenter" => {
                xll = Some(num);
                centre = true;
            }
            "yllcenter" => yll = Some(num),
            "nodata_value" => nodata = Some(num),
            other => return Err(bad(i + 1, format!("unknown header key `{other}`"))),
        }
        lines.next();
    }
    Ok(Header { ncols, nrows, dx, dy, xll, yll, centre, nodata })
}

/// Reads an ESRI ASCII grid of values that are not heights (a mask, a class map) as
/// [`crate::Values`]: each number as written, of any magnitude; missing only where it
/// is not finite or is the grid's `NODATA_value`.
pub fn read_values(path: &Path) -> Result<crate::Values> {
    let text = crate::input::read_text(path, crate::input::RASTER_LIMIT)
        .map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
    let (grid, values) = parse_grid(&text, path, true)?;
    let prj = path.with_extension("prj");
    let grid = match crate::input::read_text(&prj, 1 << 20) {
        Ok(wkt) if wkt.trim_start().starts_with("GEOGCS[") => geographic(grid, &wkt, &prj)?,
        _ => grid,
    };
    crate::Values::new(grid, values)
}

/// Parses ESRI ASCII grid text; `path` labels errors.
pub fn parse(text: &str, path: &Path) -> Result<Dem> {
    parse_grid(text, path, false).map(|(dem, _)| dem)
}

/// The grid of ESRI ASCII text and its values (NaN where missing). As heights
/// (`values` false) the DEM holds them; as values it holds 0 where one is given, the
/// values being beyond what heights may be.
fn parse_grid(text: &str, path: &Path, values: bool) -> Result<(Dem, Vec<f64>)> {
    let bad = |line: usize, m: String| Error::format(path, format!("line {line}: {m}"));
    let mut lines = text.lines().enumerate().peekable();
    let Header { ncols, nrows, dx, dy, xll, yll, centre, nodata } = read_header(&mut lines, path)?;
    let need = |v: Option<f64>, name: &str| v.ok_or_else(|| bad(1, format!("header lacks `{name}`")));
    let (ncols, nrows) = (need(ncols, "ncols")?, need(nrows, "nrows")?);
    let (dx, dy) = (need(dx, "cellsize")?, need(dy, "cellsize")?);
    let (xll, yll) = (need(xll, "xllcorner")?, need(yll, "yllcorner")?);
    if !(ncols >= 1.0 && nrows >= 1.0 && ncols.fract() == 0.0 && nrows.fract() == 0.0 && ncols * nrows < 4e9) {
        return Err(bad(1, format!("ncols = {ncols}, nrows = {nrows}: need positive whole numbers")));
    }
    let (cols, rows) = (ncols as usize, nrows as usize);
    // Every value takes at least two bytes (a digit and a separator): a header that
    // declares more cells than the file can hold is refused before anything is
    // allocated for them.
    if cols * rows > text.len() / 2 + 1 {
        return Err(bad(
            1,
            format!(
                "ncols × nrows = {cols} × {rows} cells, but the file's {} bytes can hold at most {} values",
                text.len(),
                text.len() / 2 + 1
            ),
        ));
    }
    for (name, v) in [("cellsize", dx), ("cellsize", dy)] {
        if !(v > 0.0 && v <= 1e7) {
            return Err(bad(1, format!("`{name}` = {v}: allowed 0 (exclusive)..=1e7")));
        }
    }
    for (name, v) in [("xllcorner", xll), ("yllcorner", yll)] {
        if !(v.abs() <= 1e9) {
            return Err(bad(1, format!("`{name}` = {v}: allowed -1e9..=1e9")));
        }
    }
    let mut z = Vec::with_capacity(cols * rows);
    for (i, line) in lines {
        for tok in line.split_whitespace() {
            let v = tok.parse::<f64>().map_err(|_| bad(i + 1, format!("{tok:?} is not a number")))?;
            z.push(v);
        }
    }
    if z.len() != cols * rows {
        return Err(bad(0, format!("{} values for {cols} x {rows} cells", z.len())));
    }
    let valid: Vec<bool> = z.iter().map(|v| v.is_finite() && nodata.is_none_or(|nd| *v != nd)).collect();
    let heights: Vec<f32> = (z.iter().zip(&valid))
        .map(|(v, ok)| {
            if !*ok {
                f32::NAN
            } else if values {
                0.0
            } else {
                *v as f32
            }
        })
        .collect();
    let exact: Vec<f64> =
        if values { z.iter().zip(&valid).map(|(v, ok)| if *ok { *v } else { f64::NAN }).collect() } else { Vec::new() };
    let (x0, y0) = if centre { (xll - dx / 2.0, yll - dy / 2.0) } else { (xll, yll) };
    let dem = Dem::new(cols, rows, dx, dy, x0, y0 + rows as f64 * dy, heights)
        .and_then(|d| d.with_mask(valid))
        .map_err(|e| Error::format(path, e.to_string()))?;
    Ok((dem, exact))
}

/// Writes an ESRI ASCII grid (`cellsize` when dx = dy, else GDAL's `dx`/`dy`);
/// missing cells as -9999.
pub fn write(dem: &Dem, path: &Path) -> Result<()> {
    let mut s = String::with_capacity(dem.cols() * dem.rows() * 10 + 200);
    s.push_str(&format!("ncols {}\nnrows {}\n", dem.cols(), dem.rows()));
    s.push_str(&format!("xllcorner {}\nyllcorner {}\n", dem.x0(), dem.y_top() - dem.rows() as f64 * dem.dy()));
    if dem.dx() == dem.dy() {
        s.push_str(&format!("cellsize {}\n", dem.dx()));
    } else {
        s.push_str(&format!("dx {}\ndy {}\n", dem.dx(), dem.dy()));
    }
    s.push_str("NODATA_value -9999\n");
    for r in 0..dem.rows() {
        let row: Vec<String> =
            (0..dem.cols()).map(|c| dem.z(c, r).map_or_else(|| "-9999".to_string(), |v| v.to_string())).collect();
        s.push_str(&row.join(" "));
        s.push('\n');
    }
    std::fs::write(path, s).map_err(|source| Error::Io { path: path.to_path_buf(), source })
}
