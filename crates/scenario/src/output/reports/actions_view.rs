//! An actions run's `view.html`: the best plan step by step in one self-contained page
//! (data, script and styles inline; nothing fetched) written from the report's
//! [`ActionsView`]. A slider and play/pause move through the modules; the page shows the
//! terrain from above with the rover's wheels, the ground along the path in profile
//! with the rover's pose, arm and wheel loads, and beside them the stability margin,
//! the wheel loads and the friction needed against μ by step, with a cursor. The step
//! is in the link (`view.html#step=12`); a link whose step is not one of the plan's
//! shows the first and says why. The page keeps its state in `#state`'s data
//! attributes (`data-step`, `data-body-x`/`data-body-y` and `data-top-x`/`data-top-y`
//! in canvas pixels, `data-loads`, `data-margin`, `data-error`) for a test or a script
//! to read.

use std::path::Path;

use base64::Engine;
use serde::Serialize;

use crate::error::Result;
use crate::report::actions_view::{ActionsView, ActionsViewStep};

/// The page, with `__DATA__` where its data goes.
const TEMPLATE: &str = include_str!("actions_view.html");

/// What the page's script reads.
#[derive(Serialize)]
struct Page<'a> {
    run: &'a str,
    rover: &'a str,
    mu: f64,
    stability_floor: f64,
    wheel_radius_m: f64,
    body_half_m: (f64, f64, f64),
    width: usize,
    height: usize,
    /// The hillshade's bytes, base64.
    hillshade: String,
    map_origin_m: (f64, f64),
    map_size_m: (f64, f64),
    start: (f64, f64, f64),
    target: (f64, f64, f64),
    samples: &'a [(f64, f64)],
    rocks: &'a [(f64, f64, f64)],
    ground: &'a [(f64, f64)],
    section_half_step_m: (f64, f64),
    steps: &'a [ActionsViewStep],
    about: String,
}

/// Writes `view.html` for `view` at `path`; returns its size, bytes.
pub(super) fn write(path: &Path, view: &ActionsView) -> Result<usize> {
    let hillshade = base64::engine::general_purpose::STANDARD.encode(&view.hillshade.values);
    let page = |bytes: usize| Page {
        run: &view.run,
        rover: &view.rover,
        mu: view.mu,
        stability_floor: view.stability_floor,
        wheel_radius_m: view.wheel_radius_m,
        body_half_m: view.body_half_m,
        width: view.hillshade.cols,
        height: view.hillshade.rows,
        hillshade: hillshade.clone(),
        map_origin_m: view.map_origin_m,
        map_size_m: view.map_size_m,
        start: view.start,
        target: view.target,
        samples: &view.samples,
        rocks: &view.rocks,
        ground: &view.ground,
        section_half_step_m: view.section_half_step_m,
        steps: &view.steps,
        about: format!(
            "One self-contained file of {:.2} MB (data, script and styles inline; nothing is fetched): the best plan's \
             {} modules as the quasi-static model executed them at μ = {}.",
            bytes as f64 / 1e6,
            view.steps.len(),
            view.mu
        ),
    };
    super::view::write_page(path, TEMPLATE, &page)
}
