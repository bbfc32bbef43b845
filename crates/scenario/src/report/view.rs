//! What a TEMPEST run's plan viewer (`view.html`) shows, as plain data: the terrain
//! shaded and its direct sun at a series of instants, downsampled to at most
//! [`VIEW_PIXELS`] a side; the planned route, the re-plans that changed it and the
//! executed route; the goals; and the rover's track in time with its battery, the Sun
//! and what it was doing. The image frames the routes, the start and the goals with a
//! margin (the whole map when they span it). Positions are in the image's pixels: x
//! east from its west edge, y south from its north edge.

use serde::Serialize;

use super::Raster;

/// The longest side of the viewer's image, pixels: a larger map is downsampled by whole
/// cells (the routes are not).
pub const VIEW_PIXELS: usize = 600;

/// The most shadow frames a viewer holds.
pub const VIEW_FRAMES: usize = 240;

/// The terrain classes on the viewer's image.
#[derive(Debug, Clone, Serialize)]
pub struct ViewClasses {
    /// The classes' names, in the order the pixels index them.
    pub names: Vec<String>,
    /// Base64 of a byte per pixel (row-major from the north-west): its class's index in
    /// `names`, 255 where unclassified.
    pub pixels: String,
}

/// The viewer's data.
#[derive(Debug, Clone, Serialize)]
pub struct ViewData {
    /// The scenario's name.
    pub name: String,
    /// The body ("Mars", "Moon", "Earth").
    pub body: String,
    /// The map's cells (columns, rows).
    pub map_cols_rows: (usize, usize),
    /// The image's north-west cell (column, row): the image is the map around the
    /// routes, the start and the goals, with a margin.
    pub origin_cells: (usize, usize),
    /// Map cells per image pixel along each axis.
    pub cells_per_pixel: usize,
    /// A cell's size, m (east, north).
    pub cell_m: (f64, f64),
    /// The true terrain shaded from the north-west, grey, a byte per pixel.
    pub hillshade: Raster<u8>,
    /// Each pixel's elevation on the true terrain, m: base64 of little-endian float32
    /// (NaN where the map has no data), row-major from the north-west.
    pub elevation_m: String,
    /// Each pixel's slope on the true terrain, degrees, in the same form.
    pub slope_deg: String,
    /// Where true north points in the image: the clockwise angle from up, degrees, at
    /// the image's middle (not zero on a polar map).
    pub north_deg: f64,
    /// The battery's floor and capacity, Wh (absolute, as the track's).
    pub battery_floor_wh: f64,
    /// The battery's capacity, Wh.
    pub battery_capacity_wh: f64,
    /// The instants of the direct-sun frames, s since 1970-01-01T00:00:00 UTC.
    pub frame_unix_s: Vec<f64>,
    /// The same instants, ISO 8601 UTC.
    pub frame_utc: Vec<String>,
    /// The Sun's elevation at the site at each frame's instant, degrees.
    pub frame_sun_elevation_deg: Vec<f64>,
    /// Each frame's direct sun on the true terrain: base64 of a bitset, pixel i (row-
    /// major from the north-west) at bit i % 8 of byte i / 8, set where the ground is
    /// in direct sun.
    pub frames: Vec<String>,
    /// With a no-go mask, the ground it keeps out (marked, inflated or cut off), as the
    /// same kind of bitset as a frame.
    pub no_go: Option<String>,
    /// With terrain classes, each pixel's class.
    pub classes: Option<ViewClasses>,
    /// The routes: `plan`, then the `replan`s that changed the route (at most six), then
    /// `executed`.
    pub routes: Vec<ViewRoute>,
    /// The start.
    pub start: ViewPlace,
    /// The goals, in order.
    pub goals: Vec<ViewPlace>,
    /// The rover in time: the start, then where and when each action ended (a plan's
    /// waypoints without a simulation); the rover moves linearly between.
    pub track: Vec<ViewTrackPoint>,
    /// Where the map lies on the body, for the readout's latitude and longitude.
    pub geo: ViewGeo,
    /// The local true solar time at the start's longitude at each frame's instant, h.
    pub frame_ltst_h: Vec<f64>,
    /// The local day (sol on Mars) at the start's longitude at each frame's instant.
    pub frame_sol: Vec<i64>,
    /// Off the Earth, whether the Earth is in view (above the terrain's horizon) from
    /// where the rover is at each frame's instant.
    pub frame_earth_in_view: Option<Vec<bool>>,
    /// The scheduled Communicate sessions, (start, end) s since 1970-01-01T00:00:00 UTC.
    pub sessions: Vec<(f64, f64)>,
}

/// How map cells relate to latitude and longitude: the map's projection on its sphere.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ViewGeo {
    /// `equirectangular`, `polar_north`, `polar_south`, or `local` (no geography).
    pub projection: String,
    /// The sphere's radius, m.
    pub radius_m: f64,
    /// The standard parallel (equirectangular), degrees.
    pub lat_ts_deg: f64,
    /// The central meridian, degrees east.
    pub lon0_deg: f64,
    /// The map's west edge and north edge in projected metres (cell (0, 0)'s corner).
    pub x0_m: f64,
    /// See `x0_m`.
    pub y_top_m: f64,
    /// The CRS's name.
    pub crs_name: String,
}

/// A route through the image.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ViewRoute {
    /// Its legend.
    pub name: String,
    /// `plan`, `replan` or `executed`.
    pub kind: String,
    /// Its vertices, pixels.
    pub points: Vec<(f64, f64)>,
}

/// A named place in the image.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ViewPlace {
    /// Its name.
    pub name: String,
    /// Pixels east of the west edge.
    pub x: f64,
    /// Pixels south of the north edge.
    pub y: f64,
}

/// The rover at one instant of its track.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ViewTrackPoint {
    /// The instant, s since 1970-01-01T00:00:00 UTC.
    pub unix_s: f64,
    /// The same instant, ISO 8601 UTC.
    pub utc: String,
    /// Pixels east of the west edge.
    pub x: f64,
    /// Pixels south of the north edge.
    pub y: f64,
    /// The battery, Wh (absolute).
    pub battery_wh: f64,
    /// The Sun's elevation at the site, degrees.
    pub sun_elevation_deg: f64,
    /// What the rover did to get here (`start` first), or for a plan's waypoint what it
    /// does next.
    pub activity: String,
}
