//! Plots of a TEMPEST run, as SVG and PNG (pure Rust; the PNG's text uses the Noto
//! Sans font compiled into the binary, so no system font or library is needed).
//!
//! - [`route`]: the routes over a hillshade with cast shadows (Figures 5 and 8).
//! - [`time`]: quantities against time with nights shaded — the straight-line distance
//!   to the final goal with the fastest possible approach (Figure 6), and required
//!   battery energy and battery charge (Figure 7).
//! - [`profile`] and [`histogram`]: the action planner's side profile and stability
//!   plots.

use std::path::{Path, PathBuf};
use std::sync::Once;

use base64::Engine;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::layout::{Bounds, legend_place, place_labels};
use crate::error::{Error, Result};
use crate::report::plots::{
    Drawing, HistogramPlot, Plot, ProfilePlot, ProfileRover, RoutePlot, Series, TimePlot, TimeTicks,
};

impl TimeTicks {
    fn label(&self, hours: f64) -> String {
        match *self {
            TimeTicks::Numbers => format!("{hours}"),
            TimeTicks::Utc { epoch_unix_s } => {
                let (_, mo, d, h, mi, _, _) =
                    hifitime::Epoch::from_unix_seconds(epoch_unix_s + hours * 3600.0).to_gregorian_utc();
                format!("{mo:02}-{d:02} {h:02}:{mi:02}")
            }
            TimeTicks::LocalSolar { ltst0_h, day_h } => {
                let local = ltst0_h + hours * 24.0 / day_h;
                let sol = (local / 24.0).floor();
                let minutes = ((local - 24.0 * sol) * 60.0).round() as i64;
                format!("sol {sol:.0} {:02}:{:02}", (minutes / 60) % 24, minutes % 60)
            }
        }
    }
}

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is compiled in and valid; a failure would only lose PNG text.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, ttf_noto_sans::REGULAR);
    });
}

fn colour((r, g, b): (u8, u8, u8)) -> RGBColor {
    RGBColor(r, g, b)
}

/// What a drawing backend or the PNG encoder reported.
type DrawError = Box<dyn std::error::Error + Send + Sync>;
type DrawResult<T> = std::result::Result<T, DrawError>;

/// An axis tick as a reader writes it: "3000", "0.25", "-1.5" — not plotters' "3000.0"
/// nor a float's "0.30000000000000004".
fn axis_number(v: &f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    // From +0: "-0" on an axis reads as a sign that is not there.
    format!("{}", r + 0.0)
}

fn draw_err<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> DrawError {
    e.to_string().into()
}

/// A chart builder with the plots' common title, margin and label areas.
fn titled<'a, 'b, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    title: &'b str,
    y_label_area: u32,
) -> ChartBuilder<'a, 'b, DB> {
    let mut b = ChartBuilder::on(root);
    b.caption(title, ("sans-serif", 20)).margin(12).x_label_area_size(40).y_label_area_size(y_label_area);
    b
}

type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws each series as a line with its legend entry.
fn draw_lines<'a, DB: DrawingBackend + 'a>(chart: &mut Chart<'a, DB>, series: &[Series]) -> DrawResult<()> {
    for s in series {
        let style = colour(s.rgb).stroke_width(s.width);
        chart
            .draw_series(LineSeries::new(s.points.iter().copied(), style))
            .map_err(draw_err)?
            .label(&s.label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
    }
    Ok(())
}

/// The legend's font, and plotters' legend margin and sample width, px.
const LEGEND_FONT: (&str, u32) = ("sans-serif", 13);
const LEGEND_MARGIN: i32 = 10;
const LEGEND_SAMPLE: i32 = 30;
/// Marker labels' font size and the markers' radius, px.
const MARKER_FONT: u32 = 15;
const MARKER_RADIUS: i32 = 6;

/// The size of the legend box of `labels`, px, as plotters lays it out.
fn legend_size(labels: &[&str]) -> DrawResult<(i32, i32)> {
    let font: TextStyle<'_> = LEGEND_FONT.into_font().into();
    let mut text = MultiLineText::<_, &str>::new((0, 0), &font);
    for l in labels {
        text.push_line(*l);
    }
    let (w, h) = text.estimate_dimension().map_err(|e| e.to_string())?;
    Ok((w + LEGEND_SAMPLE + 2 * LEGEND_MARGIN, h + 2 * LEGEND_MARGIN))
}

/// The plotting area of `chart`, px.
fn area_of<DB: DrawingBackend>(chart: &Chart<'_, DB>) -> Bounds {
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    Bounds { x: xr.start, y: yr.start, w: xr.end - xr.start, h: yr.end - yr.start }
}

/// Draws the legend box at `at` (page px).
fn draw_legend<'a, DB: DrawingBackend + 'a>(chart: &mut Chart<'a, DB>, at: Bounds) -> DrawResult<()> {
    let area = area_of(chart);
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(LEGEND_FONT)
        .margin(LEGEND_MARGIN as u32)
        .legend_area_size(LEGEND_SAMPLE as u32)
        .position(SeriesLabelPosition::Coordinate(at.x - area.x, at.y - area.y))
        .draw()
        .map_err(draw_err)
}

/// Where the plotting area of a chart lies, px: (x, y, width, height).
type PixelRect = (i32, i32, i32, i32);

fn draw_route<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    p: &RoutePlot,
    paint_background: bool,
) -> DrawResult<PixelRect> {
    // Without the painted background (the SVG), the caller lays the white page and the
    // map image under this drawing.
    if paint_background {
        root.fill(&WHITE).map_err(draw_err)?;
    }
    let (w, h) = p.extent;
    let (x0, y0) = p.origin;
    let mut chart = titled(root, &p.title, 60).build_cartesian_2d(x0..x0 + w, y0..y0 + h).map_err(draw_err)?;
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let rect = (xr.start, yr.start, xr.end - xr.start, yr.end - yr.start);
    if paint_background && p.cols > 0 && p.rows > 0 {
        for py in yr.clone() {
            let row = (((py - yr.start) as f64 + 0.5) / rect.3 as f64 * p.rows as f64) as usize;
            for px in xr.clone() {
                let col = (((px - xr.start) as f64 + 0.5) / rect.2 as f64 * p.cols as f64) as usize;
                let i = 3 * (row.min(p.rows - 1) * p.cols + col.min(p.cols - 1));
                root.draw_pixel((px, py), &RGBColor(p.background[i], p.background[i + 1], p.background[i + 2]))
                    .map_err(draw_err)?;
            }
        }
    }
    chart
        .configure_mesh()
        .disable_mesh()
        .x_label_formatter(&axis_number)
        .y_label_formatter(&axis_number)
        .x_desc("east, m")
        .y_desc("north, m")
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(draw_err)?;
    draw_lines(&mut chart, &p.series)?;
    // The legend goes where it hides no marker's label and the least of the routes;
    // each label then beside its marker, clear of the legend and of the other labels.
    let area = area_of(&chart);
    let font: TextStyle<'_> = ("sans-serif", MARKER_FONT).into_font().into();
    let mut anchors = Vec::with_capacity(p.markers.len());
    for m in &p.markers {
        let (w, h) = root.estimate_text_size(&m.label, &font).map_err(draw_err)?;
        // plotters' estimate runs a little short of the drawn text: keep a margin.
        anchors.push((chart.backend_coord(&m.at), ((w as f64 * 1.2) as i32 + 4, h as i32 + 2)));
    }
    let halos: Vec<Bounds> = anchors
        .iter()
        .map(|&((x, y), (w, h))| Bounds {
            x: x - w - 2 * MARKER_RADIUS,
            y: y - h - 2 * MARKER_RADIUS,
            w: 2 * w + 4 * MARKER_RADIUS,
            h: 2 * h + 4 * MARKER_RADIUS,
        })
        .collect();
    let points: Vec<(i32, i32)> =
        p.series.iter().flat_map(|s| s.points.iter().map(|q| chart.backend_coord(q))).collect();
    let labels: Vec<&str> = p.series.iter().map(|s| s.label.as_str()).collect();
    let legend = legend_place(&area, legend_size(&labels)?, &halos, &points);
    let boxes = place_labels(&area, &anchors, MARKER_RADIUS, &[legend]);
    for (m, b) in p.markers.iter().zip(&boxes) {
        let c = colour(m.rgb);
        chart
            .draw_series([
                Circle::new(m.at, MARKER_RADIUS as u32, c.filled()).into_dyn(),
                Circle::new(m.at, MARKER_RADIUS as u32, BLACK.stroke_width(1)).into_dyn(),
            ])
            .map_err(draw_err)?;
        root.draw(&Text::new(m.label.clone(), (b.x, b.y), font.clone())).map_err(draw_err)?;
    }
    draw_legend(&mut chart, legend)?;
    root.present().map_err(draw_err)?;
    Ok(rect)
}

fn draw_time<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, p: &TimePlot) -> DrawResult<()> {
    root.fill(&WHITE).map_err(draw_err)?;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for s in &p.series {
        for &(_, y) in &s.points {
            lo = lo.min(y);
            hi = hi.max(y);
        }
    }
    if !lo.is_finite() {
        (lo, hi) = (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-6);
    let (y0, y1) = (lo.min(0.0) - pad, hi + pad);
    // Headroom above the data for the legend: the plotting area's height is the page's
    // less the margins, the title and the x labels.
    let mut labels: Vec<&str> = Vec::new();
    if !p.nights.is_empty() {
        labels.push("night");
    }
    if !p.windows.is_empty() {
        labels.push(p.windows_label.as_str());
    }
    labels.extend(p.series.iter().map(|s| s.label.as_str()));
    let legend = legend_size(&labels)?;
    let (_, page_h) = root.dim_in_pixel();
    let title_h = root.estimate_text_size(&p.title, &("sans-serif", 20).into_font().into()).map_err(draw_err)?.1;
    let area_h = (f64::from(page_h) - 2.0 * 12.0 - f64::from(title_h) - 40.0 - 10.0).max(100.0);
    let free = (f64::from(legend.1 + 12) / area_h).min(0.6);
    let y1 = y0 + (y1 - y0) / (1.0 - free);
    let (x0, x1) = (p.x_range.0, p.x_range.1.max(p.x_range.0 + 1e-6));
    let mut chart = titled(root, &p.title, 70).build_cartesian_2d(x0..x1, y0..y1).map_err(draw_err)?;
    let ticks = p.x_ticks;
    let tick_label = move |h: &f64| ticks.label(*h);
    chart
        .configure_mesh()
        .light_line_style(RGBColor(235, 235, 235))
        .x_label_formatter(&tick_label)
        .y_label_formatter(&axis_number)
        .x_labels(if ticks == TimeTicks::Numbers { 10 } else { 7 })
        .x_desc(&p.x_label)
        .y_desc(&p.y_label)
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(draw_err)?;
    let night = RGBColor(40, 40, 90).mix(0.15).filled();
    if !p.nights.is_empty() {
        chart
            .draw_series(p.nights.iter().map(|&(a, b)| Rectangle::new([(a.max(x0), y0), (b.min(x1), y1)], night)))
            .map_err(draw_err)?
            .label("night")
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], night));
    }
    if !p.windows.is_empty() {
        let shade = RGBColor(40, 160, 60).mix(0.18).filled();
        chart
            .draw_series(p.windows.iter().map(|&(a, b)| Rectangle::new([(a.max(x0), y0), (b.min(x1), y1)], shade)))
            .map_err(draw_err)?
            .label(p.windows_label.as_str())
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], shade));
    }
    if p.dots {
        for s in &p.series {
            let c = colour(s.rgb);
            chart
                .draw_series(s.points.iter().map(|&q| Circle::new(q, 4, c.filled())))
                .map_err(draw_err)?
                .label(&s.label)
                .legend(move |(x, y)| Circle::new((x + 10, y), 4, c.filled()));
        }
    } else {
        draw_lines(&mut chart, &p.series)?;
    }
    let points: Vec<(i32, i32)> =
        p.series.iter().flat_map(|s| s.points.iter().map(|q| chart.backend_coord(q))).collect();
    let at = legend_place(&area_of(&chart), legend, &[], &points);
    draw_legend(&mut chart, at)?;
    root.present().map_err(draw_err)?;
    Ok(())
}

fn plot_error(path: &Path, e: DrawError) -> Error {
    Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e) }
}

/// Writes the plot as `dir/NAME.svg` and `dir/NAME.png`.
pub(crate) fn write(dir: &Path, plot: &Plot) -> Result<Vec<PathBuf>> {
    match &plot.drawing {
        Drawing::Route(p) => route(dir, &plot.name, p),
        Drawing::Time(p) => time(dir, &plot.name, p),
        Drawing::Profile(p) => profile(dir, &plot.name, p),
        Drawing::Histogram(p) => histogram(dir, &plot.name, p),
    }
}

/// Writes the route plot as `dir/NAME.svg` and `dir/NAME.png`.
fn route(dir: &Path, name: &str, p: &RoutePlot) -> Result<Vec<PathBuf>> {
    let width = 900u32;
    // Square metres: the plot area keeps the map's aspect (within the label margins).
    let height = ((f64::from(width) - 96.0) * p.extent.1 / p.extent.0 + 104.0).clamp(300.0, 1400.0) as u32;
    // The PNG paints the background pixel by pixel. The SVG is a page of three layers:
    // a white rectangle, the background as one embedded PNG image over the plotting
    // area, and plotters' drawing (left unfilled) as a nested <svg> on top.
    let layers = |drawing: String, rect: PixelRect| -> DrawResult<String> {
        let mut png = Vec::new();
        crate::output::png::encode_png(&mut png, p.cols, p.rows, &p.background)?;
        Ok(format!(
            concat!(
                r#"<svg width="{w}" height="{h}" viewBox="0 0 {w} {h}" xmlns="http://www.w3.org/2000/svg">"#,
                "\n",
                r#"<rect x="0" y="0" width="{w}" height="{h}" fill="white"/>"#,
                "\n",
                r#"<image x="{x}" y="{y}" width="{iw}" height="{ih}" preserveAspectRatio="none" href="data:image/png;base64,{data}"/>"#,
                "\n{drawing}\n</svg>\n"
            ),
            w = width,
            h = height,
            x = rect.0,
            y = rect.1,
            iw = rect.2,
            ih = rect.3,
            data = base64::engine::general_purpose::STANDARD.encode(&png),
            drawing = drawing.trim_end(),
        ))
    };
    both_with(dir, name, (width, height), |r| draw_route(r, p, false), layers, |r| draw_route(r, p, true).map(|_| ()))
}

/// Writes a time plot as `dir/NAME.svg` and `dir/NAME.png`.
fn time(dir: &Path, name: &str, p: &TimePlot) -> Result<Vec<PathBuf>> {
    both(dir, name, (900, 500), |r| draw_time(r, p), |r| draw_time(r, p))
}

fn draw_profile<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, p: &ProfilePlot) -> DrawResult<()> {
    root.fill(&WHITE).map_err(draw_err)?;
    let xs = p.ground.iter().map(|q| q.0).chain(p.rovers.iter().flat_map(|r| r.wheels.iter().map(|w| w.0)));
    let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    let (x0, x1) = (x0 - 0.15, x1 + 0.15);
    let (z0, z1) =
        p.ground.iter().map(|q| q.1).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| (a.min(z), b.max(z)));
    let (x0, x1) = if x0.is_finite() { (x0, x1.max(x0 + 1e-3)) } else { (0.0, 1.0) };
    let (z0, z1) = if z0.is_finite() { (z0 - 0.1, z1 + 0.6) } else { (0.0, 1.0) };
    let mut chart = titled(root, &p.title, 60).build_cartesian_2d(x0..x1, z0..z1).map_err(draw_err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_label_formatter(&axis_number)
        .y_label_formatter(&axis_number)
        .x_desc("distance along the path, m")
        .y_desc("height, m")
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(draw_err)?;
    let brown = RGBColor(150, 110, 70);
    chart
        .draw_series(AreaSeries::new(p.ground.iter().copied(), z0, brown.mix(0.35)).border_style(brown))
        .map_err(draw_err)?;
    let px_per_m = 800.0 / (x1 - x0).max(1e-9);
    let r_px = ((p.wheel_radius_m * px_per_m).round() as i32).max(2);
    for ProfileRover { wheels, body, label } in &p.rovers {
        let blue = RGBColor(30, 90, 220);
        // Rocker: rear axle – body – middle; bogie: middle – front (one side).
        let links = [vec![wheels[2], *body, wheels[1]], vec![wheels[1], wheels[0]]];
        for l in links {
            chart.draw_series(LineSeries::new(l, blue.stroke_width(2))).map_err(draw_err)?;
        }
        chart
            .draw_series(wheels.iter().take(3).map(|&c| Circle::new(c, r_px, blue.stroke_width(2))))
            .map_err(draw_err)?;
        chart
            .draw_series([Text::new(label.clone(), (body.0, body.1 + 0.15), ("sans-serif", 13).into_font())])
            .map_err(draw_err)?;
    }
    root.present().map_err(draw_err)?;
    Ok(())
}

fn draw_histogram<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, p: &HistogramPlot) -> DrawResult<()> {
    root.fill(&WHITE).map_err(draw_err)?;
    let all = || p.series.iter().flat_map(|(v, _)| v.iter().copied());
    let (w, centred) = p.bin_width.map_or((1.0, true), |w| (w, false));
    let lo = all().min().unwrap_or(0).min(if centred { 0 } else { i64::MAX });
    let hi = all().max().unwrap_or(1).max(if centred { 1 } else { i64::MIN });
    let counts: Vec<std::collections::BTreeMap<i64, u32>> = p
        .series
        .iter()
        .map(|(values, _)| {
            let mut c = std::collections::BTreeMap::new();
            for v in values {
                *c.entry(*v).or_insert(0u32) += 1;
            }
            c
        })
        .collect();
    let top = counts.iter().flat_map(|c| c.values().copied()).max().unwrap_or(1);
    // Bin k spans [left(k), left(k) + w).
    let left = |k: i64| if centred { k as f64 - 0.5 } else { k as f64 * w };
    let mut chart = titled(root, &p.title, 60)
        .build_cartesian_2d(left(lo)..(left(hi) + w), 0.0..(f64::from(top) * 1.1))
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_label_formatter(&axis_number)
        .y_label_formatter(&axis_number)
        .x_desc(&p.x_label)
        .y_desc(&p.y_label)
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(draw_err)?;
    let n = p.series.len().max(1) as f64;
    let bar = 0.8 * w / n;
    for (j, (c, (_, (r, g, b)))) in counts.iter().zip(&p.series).enumerate() {
        let colour = RGBColor(*r, *g, *b);
        let x0 = |k: i64| left(k) + 0.1 * w + j as f64 * bar;
        chart
            .draw_series(
                c.iter().map(|(&k, &count)| {
                    Rectangle::new([(x0(k), 0.0), (x0(k) + bar, f64::from(count))], colour.filled())
                }),
            )
            .map_err(draw_err)?;
    }
    root.present().map_err(draw_err)?;
    Ok(())
}

/// Writes `dir/NAME.svg` and `dir/NAME.png` with `draw` on each backend.
fn both(
    dir: &Path,
    name: &str,
    size: (u32, u32),
    draw_svg: impl Fn(&DrawingArea<SVGBackend<'_>, Shift>) -> DrawResult<()>,
    draw_png: impl Fn(&DrawingArea<BitMapBackend<'_>, Shift>) -> DrawResult<()>,
) -> Result<Vec<PathBuf>> {
    both_with(dir, name, size, draw_svg, |svg, ()| Ok(svg), draw_png)
}

/// [`both`], with the SVG text passed through `finish_svg` (given what `draw_svg`
/// returned) before it is written.
fn both_with<T>(
    dir: &Path,
    name: &str,
    (width, height): (u32, u32),
    draw_svg: impl Fn(&DrawingArea<SVGBackend<'_>, Shift>) -> DrawResult<T>,
    finish_svg: impl FnOnce(String, T) -> DrawResult<String>,
    draw_png: impl Fn(&DrawingArea<BitMapBackend<'_>, Shift>) -> DrawResult<()>,
) -> Result<Vec<PathBuf>> {
    register_font();
    let svg_path = dir.join(format!("{name}.svg"));
    let mut svg = String::new();
    let drawn = {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        draw_svg(&root).map_err(|m| plot_error(&svg_path, m))?
    };
    // plotters escapes the specials; a character XML forbids is replaced.
    let svg = crate::output::escape::xml_chars(finish_svg(svg, drawn).map_err(|m| plot_error(&svg_path, m))?);
    crate::output::write_file(&svg_path, svg.as_bytes())?;
    let png_path = dir.join(format!("{name}.png"));
    let mut buf = vec![0u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        draw_png(&root).map_err(|m| plot_error(&png_path, m))?;
    }
    crate::output::png::write_png(&png_path, width as usize, height as usize, &buf)?;
    Ok(vec![svg_path, png_path])
}

/// Writes a side profile as SVG and PNG.
fn profile(dir: &Path, name: &str, p: &ProfilePlot) -> Result<Vec<PathBuf>> {
    both(dir, name, (900, 450), |r| draw_profile(r, p), |r| draw_profile(r, p))
}

/// Writes a histogram as SVG and PNG.
fn histogram(dir: &Path, name: &str, p: &HistogramPlot) -> Result<Vec<PathBuf>> {
    both(dir, name, (700, 450), |r| draw_histogram(r, p), |r| draw_histogram(r, p))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_ticks_read_as_utc_and_local_solar_time() {
        let epoch = areo_ephemeris::parse_utc("2012-08-06T05:17:57Z").unwrap();
        assert_eq!(TimeTicks::Utc { epoch_unix_s: epoch.to_unix_seconds() }.label(20.0), "08-07 01:17");
        // A Mars sol of 24.6597 h: 14:00 at the start, one sol and 6 h later 20:00 of sol 1.
        let sol_h = areo_ephemeris::SOL_S / 3600.0;
        let ticks = TimeTicks::LocalSolar { ltst0_h: 14.0, day_h: sol_h };
        assert_eq!(ticks.label(0.0), "sol 0 14:00");
        assert_eq!(ticks.label(sol_h + 6.0 * sol_h / 24.0), "sol 1 20:00");
        assert_eq!(TimeTicks::Numbers.label(2.5), "2.5");
    }

    #[test]
    fn axis_numbers_carry_no_spurious_decimals_or_signs() {
        assert_eq!(axis_number(&3000.0), "3000");
        assert_eq!(axis_number(&(0.1 + 0.2)), "0.3");
        assert_eq!(axis_number(&-1.5), "-1.5");
        assert_eq!(axis_number(&-0.0), "0");
        assert_eq!(axis_number(&-1e-9), "0");
        assert_eq!(axis_number(&0.125), "0.125");
    }
}
