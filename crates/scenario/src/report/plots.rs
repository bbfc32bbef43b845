//! A report's plots as plain data: what each plot draws (polylines, markers, a
//! raster background, shaded intervals, histogram bins), with its file name. The
//! output layer draws them as SVG and PNG; Python and `--json` see them as they are.
//!
//! Coordinates are those of the plot's axes: local map metres east and north of the
//! map's south-west corner for [`RoutePlot`]s, hours (or modules, generations,
//! metres along a climb — as the axis label says) and values for [`TimePlot`]s.

use serde::Serialize;

/// A plot and the name of its files (`NAME.svg`, `NAME.png`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plot {
    /// The files' stem.
    pub name: String,
    /// What the plot draws.
    pub drawing: Drawing,
}

/// What a plot draws, by kind.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Drawing {
    /// Routes over a raster background.
    Route(RoutePlot),
    /// Series against time (or another axis) with intervals shaded.
    Time(TimePlot),
    /// The ground along a path with the rover drawn on it.
    Profile(ProfilePlot),
    /// Counted bins.
    Histogram(HistogramPlot),
}

impl Plot {
    /// A route plot named `name`.
    pub fn route(name: impl Into<String>, plot: RoutePlot) -> Plot {
        Plot { name: name.into(), drawing: Drawing::Route(plot) }
    }

    /// A time plot named `name`.
    pub fn time(name: impl Into<String>, plot: TimePlot) -> Plot {
        Plot { name: name.into(), drawing: Drawing::Time(plot) }
    }

    /// A side profile named `name`.
    pub fn profile(name: impl Into<String>, plot: ProfilePlot) -> Plot {
        Plot { name: name.into(), drawing: Drawing::Profile(plot) }
    }

    /// A histogram named `name`.
    pub fn histogram(name: impl Into<String>, plot: HistogramPlot) -> Plot {
        Plot { name: name.into(), drawing: Drawing::Histogram(plot) }
    }
}

/// A polyline to draw: local map metres (or hours and values for the time plots).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Points.
    pub points: Vec<(f64, f64)>,
    /// Colour (RGB).
    pub rgb: (u8, u8, u8),
    /// Line width, px.
    pub width: u32,
}

/// A labelled marker.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Marker {
    /// Label.
    pub label: String,
    /// Position.
    pub at: (f64, f64),
    /// Colour (RGB).
    pub rgb: (u8, u8, u8),
}

/// The route plot's data: a raster background (RGB, `cols` × `rows`, row 0 north)
/// spanning `extent` = (width, height) m east and north of `origin`, the routes and
/// the markers (in the same metres).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RoutePlot {
    /// Title.
    pub title: String,
    /// Background pixels, RGB row by row, north row first.
    pub background: Vec<u8>,
    /// Background size, cells.
    pub cols: usize,
    /// Background size, cells.
    pub rows: usize,
    /// South-west corner of the background, m.
    pub origin: (f64, f64),
    /// Background width and height, m.
    pub extent: (f64, f64),
    /// Routes, drawn in order.
    pub series: Vec<Series>,
    /// Start and goals.
    pub markers: Vec<Marker>,
}

/// A time plot: series against hours, with night intervals shaded.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TimePlot {
    /// Title.
    pub title: String,
    /// X-axis label.
    pub x_label: String,
    /// Y-axis label.
    pub y_label: String,
    /// Series (x in hours).
    pub series: Vec<Series>,
    /// Night intervals, hours.
    pub nights: Vec<(f64, f64)>,
    /// Other intervals to shade (contact sessions), hours, with their legend label.
    pub windows: Vec<(f64, f64)>,
    /// The legend label of `windows`.
    pub windows_label: String,
    /// X range, hours.
    pub x_range: (f64, f64),
    /// Draw the series as dots (separate runs), not lines.
    pub dots: bool,
    /// How x values (hours) are labelled.
    pub x_ticks: TimeTicks,
}

/// How a time plot labels its hours.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum TimeTicks {
    /// As numbers (hours since the start, or whatever the axis holds).
    #[default]
    Numbers,
    /// As UTC `MM-DD HH:MM`, hour 0 being `epoch_unix_s`.
    Utc {
        /// The instant of hour 0, s since 1970-01-01T00:00:00 UTC.
        epoch_unix_s: f64,
    },
    /// As local solar time `sol N HH:MM`: hour 0 at `ltst0_h` of sol 0, `day_h` hours
    /// a solar day (the equation of time's drift over a plot, under a minute a sol, is
    /// left out).
    LocalSolar {
        /// Local solar time at hour 0, h.
        ltst0_h: f64,
        /// The solar day, h.
        day_h: f64,
    },
}

/// The rover drawn in a side profile: six wheel axles (distance, height), the body
/// reference, and a label.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProfileRover {
    /// Wheel axles (left front, middle, rear, right front, middle, rear), m.
    pub wheels: [(f64, f64); 6],
    /// Body reference, m.
    pub body: (f64, f64),
    /// Label.
    pub label: String,
}

/// A side profile: the ground along the path and the rover drawn at some steps.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProfilePlot {
    /// Title.
    pub title: String,
    /// Ground (distance along the path, height), m.
    pub ground: Vec<(f64, f64)>,
    /// Rovers to draw.
    pub rovers: Vec<ProfileRover>,
    /// Wheel radius, m.
    pub wheel_radius_m: f64,
}

/// A histogram of counted bins: each series' values are bin numbers, bin k covering
/// [k·w, (k + 1)·w) of the x axis with w the bin width (1 and integer values: one bar
/// per integer, centred on it). Several series stand side by side in each bin, each in
/// its colour (named in the title).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HistogramPlot {
    /// Title.
    pub title: String,
    /// X-axis label.
    pub x_label: String,
    /// Y-axis label (what is counted).
    pub y_label: String,
    /// Bin width in x units; `None`: integer values, one bar centred on each.
    pub bin_width: Option<f64>,
    /// The values, as bin numbers, and each series' colour.
    pub series: Vec<(Vec<i64>, (u8, u8, u8))>,
}
