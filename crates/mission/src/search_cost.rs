//! What a TEMPEST search is expected to cost, in the units a work budget counts: an
//! expansion against a horizon ray of one cell and sector ([`EXPANSION_STEPS`]), and
//! the cells a guided search spreads over around each leg ([`leg_footprint`]). The
//! scenario layer's budget adds the job's other work (worlds, clones, executions) and
//! holds the searches to what is left as they run.

use areo_terrain::Dem;

/// Work steps one label expansion counts for, a step being one horizon ray of a cell
/// and sector, so that a work budget bounds time whichever kind of work spends it: an
/// expansion (the Sun at the label's time, the light and slope checks, eight drives
/// with their settles to the tick and a wait, each label kept placed on its instant's
/// staircase) takes about as long as this many rays. `cargo xtask bench budget`
/// measures the ratio on the shipped TEMPEST scenarios and prints it beside this
/// figure (`docs/benchmarks.md`).
pub const EXPANSION_STEPS: u64 = 100;

/// How far a guided search spreads around the straight line between a leg's ends: the
/// cells inside the ellipse whose foci are the leg's ends and whose major axis is this
/// many times the leg's length (plus [`CORRIDOR_CELLS`] on each side). The 2-D cost
/// bound keeps the search near routes no dearer than the plan; measured footprints
/// are in `docs/benchmarks.md`.
pub const DETOUR: f64 = 2.0;

/// Cells added around each leg's ellipse, so a short leg still counts a corridor.
pub const CORRIDOR_CELLS: f64 = 10.0;

/// The map a search runs on, as far as its cost goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchMap {
    /// Cells of the map (or of the planning region).
    pub cells: u64,
    /// Area of one cell, m².
    pub cell_m2: f64,
}

impl SearchMap {
    /// The map of `dem`'s cells.
    pub fn of(dem: &Dem) -> SearchMap {
        SearchMap { cells: (dem.cols() * dem.rows()) as u64, cell_m2: dem.dx().abs() * dem.dy().abs() }
    }
}

/// The cells a guided search from `from` to `to` (m) is expected to reach on `map`:
/// the detour ellipse between them, with a corridor, at most the whole map.
pub fn leg_footprint(from: (f64, f64), to: (f64, f64), map: SearchMap) -> f64 {
    let half = (to.0 - from.0).hypot(to.1 - from.1) / 2.0;
    let a = DETOUR * half + CORRIDOR_CELLS * map.cell_m2.sqrt();
    let b = (a * a - half * half).max(0.0).sqrt();
    (std::f64::consts::PI * a * b / map.cell_m2).min(map.cells as f64)
}

/// The labels one search through `stops` (the start, then each goal, m) is expected to
/// expand on `map`: every leg's footprint × the time steps of the horizon (`horizon_s`
/// over `step_s`, the tick or the time class). An expectation, not a bound either way:
/// a static route expands far fewer, a search whose battery is too low to move floods
/// the map.
pub fn expected_labels(stops: &[(f64, f64)], map: SearchMap, horizon_s: f64, step_s: f64) -> f64 {
    let time_steps = (horizon_s / step_s).ceil().max(1.0);
    let footprint: f64 = stops.windows(2).map(|w| leg_footprint(w[0], w[1], map)).sum();
    footprint.max(1.0) * time_steps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_legs_footprint_is_its_ellipse_in_cells_at_most_the_map() {
        // A 1000 m leg on 10 m cells: semi-axes a = 2 · 500 + 10 · 10 = 1100 m and
        // b = √(1100² − 500²) m, π·a·b / 100 m² cells.
        let map = SearchMap { cells: 1_000_000, cell_m2: 100.0 };
        let b = (1100.0f64 * 1100.0 - 500.0 * 500.0).sqrt();
        let want = std::f64::consts::PI * 1100.0 * b / 100.0;
        assert!((leg_footprint((0.0, 0.0), (1000.0, 0.0), map) - want).abs() < 1e-6 * want);
        // A small map caps it.
        let small = SearchMap { cells: 500, cell_m2: 100.0 };
        assert_eq!(leg_footprint((0.0, 0.0), (1000.0, 0.0), small), 500.0);
        // Two legs add, and the horizon's time steps multiply.
        let two = expected_labels(&[(0.0, 0.0), (1000.0, 0.0), (1000.0, 1000.0)], map, 3600.0, 60.0);
        assert!((two - 2.0 * want * 60.0).abs() < 1e-6 * two);
    }
}
