//! `view.html`: a TEMPEST run's plan viewer, one self-contained page (its data, script
//! and styles inline; no library, nothing fetched) written from the report's
//! [`ViewData`]. A slider and play/pause move an instant through the run; the map shows
//! the terrain with its direct sun at that instant, the routes, the goals and the
//! rover; beside it the battery, the Sun's elevation and what the rover is doing, with
//! a cursor. The instant is in the link (`view.html#t=2012-08-07T03:00:00Z`); a link
//! whose time is not a time of the run shows the start and says why. The page keeps
//! its state in `#state`'s data attributes (`data-utc`, `data-rover-x`,
//! `data-rover-y` in the image's pixels, `data-frame`, `data-error`, `data-doing`, the
//! view's `data-zoom`/`data-pan-x`/`data-pan-y`, the readout's `data-hover-*`,
//! `data-local-ticks`) for a test or a script to read; the link's `wheel=X,Y,N`,
//! `drag=X,Y,X2,Y2`, `point=X,Y` and `click=X,Y` send those pointer events at canvas
//! pixels, and `relief` measures the relief the drawn map keeps.

use std::path::Path;

use base64::Engine;
use serde::Serialize;

use crate::error::Result;
use crate::output::write_file;
use crate::report::view::{ViewData, ViewPlace, ViewRoute, ViewTrackPoint};

/// The page, with `__DATA__` where its data goes.
const TEMPLATE: &str = include_str!("view.html");

/// What the page's script reads.
#[derive(Serialize)]
struct Page<'a> {
    name: &'a str,
    body: &'a str,
    map_cols: usize,
    map_rows: usize,
    /// The image's north-west cell (column, row).
    origin_cells: (usize, usize),
    cells_per_pixel: usize,
    /// A cell's size, m (east, north).
    cell_m: (f64, f64),
    width: usize,
    height: usize,
    /// The hillshade's bytes, base64.
    hillshade: String,
    /// Each pixel's elevation and slope, base64 of float32.
    elevation_m: &'a str,
    slope_deg: &'a str,
    /// True north's clockwise angle from up, degrees.
    north_deg: f64,
    /// The battery's floor and capacity, Wh.
    battery_floor_wh: f64,
    battery_capacity_wh: f64,
    frame_unix_s: &'a [f64],
    frame_sun_elevation_deg: &'a [f64],
    frames: &'a [String],
    /// The ground a no-go mask keeps out, base64 of a bitset.
    no_go: Option<&'a str>,
    /// The terrain classes, a byte per pixel.
    classes: Option<&'a crate::report::view::ViewClasses>,
    routes: &'a [ViewRoute],
    start: &'a ViewPlace,
    goals: &'a [ViewPlace],
    track: &'a [ViewTrackPoint],
    /// Whether the track is an executed run (a point's activity is what brought the
    /// rover there) or a plan (what it does next).
    executed: bool,
    about: String,
    geo: &'a crate::report::view::ViewGeo,
    frame_ltst_h: &'a [f64],
    frame_sol: &'a [i64],
    frame_earth_in_view: Option<&'a [bool]>,
    sessions: &'a [(f64, f64)],
    /// What a local day is called (`sol` on Mars, `day` elsewhere).
    day_name: &'a str,
}

/// Writes `view.html` (`executed`: a simulated run) at `path`;
/// returns its size, bytes.
pub(super) fn write(path: &Path, view: &ViewData, executed: bool) -> Result<usize> {
    let page = |about: String| Page {
        name: &view.name,
        body: &view.body,
        map_cols: view.map_cols_rows.0,
        map_rows: view.map_cols_rows.1,
        origin_cells: view.origin_cells,
        cells_per_pixel: view.cells_per_pixel,
        cell_m: view.cell_m,
        width: view.hillshade.cols,
        height: view.hillshade.rows,
        hillshade: base64::engine::general_purpose::STANDARD.encode(&view.hillshade.values),
        elevation_m: &view.elevation_m,
        slope_deg: &view.slope_deg,
        north_deg: view.north_deg,
        battery_floor_wh: view.battery_floor_wh,
        battery_capacity_wh: view.battery_capacity_wh,
        frame_unix_s: &view.frame_unix_s,
        frame_sun_elevation_deg: &view.frame_sun_elevation_deg,
        frames: &view.frames,
        no_go: view.no_go.as_deref(),
        classes: view.classes.as_ref(),
        routes: &view.routes,
        start: &view.start,
        goals: &view.goals,
        track: &view.track,
        executed,
        about,
        geo: &view.geo,
        frame_ltst_h: &view.frame_ltst_h,
        frame_sol: &view.frame_sol,
        frame_earth_in_view: view.frame_earth_in_view.as_deref(),
        sessions: &view.sessions,
        day_name: if view.body == "Mars" { "sol" } else { "day" },
    };
    let about = |bytes: usize| {
        format!(
            "One self-contained file of {:.1} MB (data, script and styles inline; nothing is fetched). {} shadow \
             frames from {} to {}; the map at one pixel per {} × {} cells, the routes at full resolution.",
            bytes as f64 / 1e6,
            view.frames.len(),
            view.track.first().map_or("", |p| p.utc.as_str()),
            view.track.last().map_or("", |p| p.utc.as_str()),
            view.cells_per_pixel,
            view.cells_per_pixel
        )
    };
    write_page(path, TEMPLATE, &|bytes| page(about(bytes)))
}

/// Writes `template` with its `__DATA__` replaced by `data`'s JSON at `path`; `data`
/// is given the file's size, bytes, so that the page can state it. Returns that size.
pub(super) fn write_page<T: Serialize>(path: &Path, template: &str, data: &dyn Fn(usize) -> T) -> Result<usize> {
    let html = |bytes: usize| -> Result<String> {
        let json = crate::output::json_for(path, &data(bytes), false)?;
        // Nothing in the data may close, comment out or open a script element.
        Ok(template.replace("__DATA__", &crate::output::escape::script_json(&json)))
    };
    // Measured once without the size, which the sentence changes by a few bytes.
    let first = html(0)?.len();
    let text = html(first)?;
    write_file(path, text.as_bytes())?;
    Ok(text.len())
}
