//! An 8-connected weighted grid as an ISE [`Domain`]: the Moving AI benchmark rules
//! (straight step 1, diagonal √2, no corner cutting) with per-cell weights for
//! re-planning experiments.
//!
//! A step between adjacent free cells a and b costs its length × (w(a) + w(b)) / 2, with
//! every weight ≥ 1 so that the octile distance stays an admissible heuristic. A
//! diagonal step needs both orthogonal neighbours free.

use crate::domain::{Domain, Predecessor};

/// Offsets of the 8 moves: N, NE, E, SE, S, SW, W, NW (x right, y down as in the files).
const MOVES: [(i32, i32); 8] = [(0, -1), (1, -1), (1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1)];

/// A grid of free and blocked cells with weights.
///
/// Cells are stored with a one-cell blocked border, so a move is a constant index
/// offset with no bounds test; cell indices ([`Grid::cell`]) are indices into that
/// padded array.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    width: u32,
    height: u32,
    /// Padded width: `width + 2`.
    stride: u32,
    free: Vec<bool>,
    weight: Vec<f32>,
    offsets: [i64; 8],
    /// ⌊2⁶⁴ / stride⌋ + 1, to split indices into rows and columns without a division.
    inv_stride: u64,
    start: u32,
    start_xy: (f64, f64),
}

/// Why a grid could not be built from text.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum GridError {
    /// The header (`type`, `height H`, `width W`, `map`) is missing or malformed.
    #[error("line {line}: {message}")]
    Header {
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A map row has the wrong length or the map has the wrong number of rows.
    #[error("line {line}: {message}")]
    Shape {
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
}

impl Grid {
    /// An all-free grid of unit weight; start at (0, 0).
    pub fn new(width: u32, height: u32) -> Grid {
        let stride = width + 2;
        let n = (stride as usize) * (height as usize + 2);
        let mut free = vec![false; n];
        for y in 0..height {
            let row = ((y + 1) * stride + 1) as usize;
            free[row..row + width as usize].fill(true);
        }
        let offsets = MOVES.map(|(dx, dy)| i64::from(dy) * i64::from(stride) + i64::from(dx));
        Grid {
            width,
            height,
            stride,
            free,
            weight: vec![1.0; n],
            offsets,
            inv_stride: u64::MAX / u64::from(stride) + 1,
            start: stride + 1,
            start_xy: (1.0, 1.0),
        }
    }

    /// Reads a Moving AI `.map` text (`type octile`, `height`, `width`, `map`, rows).
    /// `.`, `G` and `S` are free; every other character is blocked. CRLF is accepted.
    pub fn parse_movingai(text: &str) -> Result<Grid, GridError> {
        let mut lines = text.lines().map(|l| l.trim_end_matches('\r')).enumerate();
        let (mut width, mut height) = (None, None);
        for (i, line) in lines.by_ref() {
            let mut parts = line.split_whitespace();
            match (parts.next(), parts.next()) {
                (Some("type"), Some("octile")) => {}
                (Some("type"), t) => {
                    return Err(GridError::Header {
                        line: i + 1,
                        message: format!("type {}: only `type octile` (8-connected) is solved", t.unwrap_or("(none)")),
                    });
                }
                (Some("height"), Some(v)) => height = v.parse::<u32>().ok(),
                (Some("width"), Some(v)) => width = v.parse::<u32>().ok(),
                (Some("map"), None) => break,
                _ => {
                    return Err(GridError::Header { line: i + 1, message: format!("unexpected header line {line:?}") });
                }
            }
        }
        let (Some(width), Some(height)) = (width, height) else {
            return Err(GridError::Header { line: 1, message: "missing or invalid `height`/`width`".into() });
        };
        if width == 0 || height == 0 || (width as u64) * (height as u64) > u32::MAX as u64 / 2 {
            return Err(GridError::Header { line: 1, message: format!("unsupported size {width}x{height}") });
        }
        // One byte per cell: a header that declares more cells than the text holds is
        // refused before the grid is allocated.
        if (width as u64) * (height as u64) > text.len() as u64 {
            return Err(GridError::Shape {
                line: 1,
                message: format!("{width}x{height} cells declared, but the file has only {} bytes", text.len()),
            });
        }
        let mut grid = Grid::new(width, height);
        let mut rows = 0u32;
        for (i, line) in lines {
            if rows == height {
                if line.trim().is_empty() {
                    continue;
                }
                return Err(GridError::Shape { line: i + 1, message: format!("more than {height} rows") });
            }
            if line.len() != width as usize {
                return Err(GridError::Shape {
                    line: i + 1,
                    message: format!("row {rows} has {} cells, expected {width}", line.len()),
                });
            }
            for (x, c) in line.bytes().enumerate() {
                let cell = grid.cell(x as u32, rows);
                grid.free[cell as usize] = matches!(c, b'.' | b'G' | b'S');
            }
            rows += 1;
        }
        if rows != height {
            return Err(GridError::Shape { line: 0, message: format!("{rows} rows, expected {height}") });
        }
        Ok(grid)
    }

    /// Width in cells.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in cells.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The cell index of (x, y), which must lie on the grid.
    pub fn cell(&self, x: u32, y: u32) -> u32 {
        (y + 1) * self.stride + x + 1
    }

    /// (x, y) of a cell index.
    pub fn xy(&self, cell: u32) -> (u32, u32) {
        (cell % self.stride - 1, cell / self.stride - 1)
    }

    /// Every cell index of the grid, row by row.
    pub fn cells(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.height).flat_map(move |y| (0..self.width).map(move |x| self.cell(x, y)))
    }

    /// Whether (x, y) lies on the grid.
    pub fn contains(&self, x: i64, y: i64) -> bool {
        x >= 0 && y >= 0 && x < self.width as i64 && y < self.height as i64
    }

    /// Whether a cell is free.
    pub fn is_free(&self, cell: u32) -> bool {
        self.free[cell as usize]
    }

    /// Blocks or frees a cell.
    pub fn set_free(&mut self, cell: u32, free: bool) {
        let (x, y) = self.xy(cell);
        debug_assert!(x < self.width && y < self.height, "the border stays blocked");
        self.free[cell as usize] = free;
    }

    /// A cell's weight.
    pub fn weight(&self, cell: u32) -> f32 {
        self.weight[cell as usize]
    }

    /// The states to pass to [`crate::Search::update`] after changing `cell`: the cell
    /// itself, and — when its free/blocked status changed — its four orthogonal
    /// neighbours, because the no-corner-cutting rule makes the diagonal moves between
    /// them depend on it.
    pub fn changed_states(&self, cell: u32, status_changed: bool) -> Vec<u32> {
        let mut out = vec![cell];
        if status_changed {
            let (x, y) = self.xy(cell);
            for (dx, dy) in [(0i64, -1i64), (1, 0), (0, 1), (-1, 0)] {
                let (nx, ny) = (i64::from(x) + dx, i64::from(y) + dy);
                if self.contains(nx, ny) {
                    out.push(self.cell(nx as u32, ny as u32));
                }
            }
        }
        out
    }

    /// Sets a cell's weight; values below 1 are raised to 1 (the heuristic needs it).
    pub fn set_weight(&mut self, cell: u32, weight: f32) {
        self.weight[cell as usize] = weight.max(1.0);
    }

    /// The start cell.
    pub fn start(&self) -> u32 {
        self.start
    }

    /// Moves the start (tell the search with `start_moved`).
    pub fn set_start(&mut self, cell: u32) {
        self.start = cell;
        self.start_xy = self.padded_xy(cell);
    }

    /// Padded (column, row) of a cell as floats. The row is `cell / stride` by one
    /// integer multiplication with a 64-bit reciprocal (exact for every u32 cell: the
    /// reciprocal's error times the cell stays below one part in 2³²), which the
    /// heuristic's chain of conversions waited on as a float product.
    #[inline]
    fn padded_xy(&self, cell: u32) -> (f64, f64) {
        let row = ((u128::from(cell) * u128::from(self.inv_stride)) >> 64) as u32;
        (f64::from(cell - row * self.stride), f64::from(row))
    }

    /// The neighbour reached from `a` by move `m` and the move's cost, or `None` if the
    /// move is not allowed.
    #[inline]
    fn step_cost(&self, a: u32, m: usize) -> Option<(u32, f64)> {
        if !self.free[a as usize] {
            return None;
        }
        // `a` is free, so it is an inner cell and every neighbour index is in the array.
        let b = (i64::from(a) + self.offsets[m]) as u32;
        if !self.free[b as usize] {
            return None;
        }
        let len = if m % 2 == 1 {
            // No corner cutting: both orthogonal neighbours must be free.
            let horizontal = (i64::from(a) + i64::from(MOVES[m].0)) as usize;
            let vertical = (i64::from(a) + i64::from(MOVES[m].1) * i64::from(self.stride)) as usize;
            if !self.free[horizontal] || !self.free[vertical] {
                return None;
            }
            std::f64::consts::SQRT_2
        } else {
            1.0
        };
        Some((b, len * 0.5 * f64::from(self.weight[a as usize] + self.weight[b as usize])))
    }

    /// Octile distance between two cells.
    pub fn octile(&self, a: u32, b: u32) -> f64 {
        let (ax, ay) = self.xy(a);
        let (bx, by) = self.xy(b);
        let dx = f64::from(ax.abs_diff(bx));
        let dy = f64::from(ay.abs_diff(by));
        dx.max(dy) + (std::f64::consts::SQRT_2 - 1.0) * dx.min(dy)
    }

    /// The forward neighbours of `cell` with move costs (used by peers and tests).
    pub fn neighbours(&self, cell: u32) -> impl Iterator<Item = (u32, f64)> + '_ {
        (0..8).filter_map(move |m| self.step_cost(cell, m))
    }
}

impl Domain for Grid {
    type State = u32;
    type Label = ();
    type Key = ();
    type Move = u8;

    /// The 8 moves (a blocked cell has none). Move m leads from the predecessor to
    /// `state`: the predecessor lies one move in the opposite direction, and moves are
    /// symmetric in legality and cost.
    #[inline]
    fn expand(
        &self,
        state: u32,
        _label: &(),
        wanted: impl Fn(u8) -> bool,
        mut visit: impl FnMut(u8, Predecessor<Grid>),
    ) {
        if !self.free[state as usize] {
            return;
        }
        for via in 0..8u8 {
            if wanted(via)
                && let Some((pred, cost)) = self.step_cost(state, (via as usize + 4) % 8)
            {
                visit(via, Predecessor { state: pred, label: (), cost });
            }
        }
    }

    fn successors(&self, state: u32, out: &mut Vec<u32>) {
        let (x, y) = self.xy(state);
        for (dx, dy) in MOVES {
            let (nx, ny) = (i64::from(x) + i64::from(dx), i64::from(y) + i64::from(dy));
            if self.contains(nx, ny) {
                out.push(self.cell(nx as u32, ny as u32));
            }
        }
    }

    fn dense_index(&self, state: u32) -> Option<u32> {
        Some(state)
    }

    fn key(&self, _state: u32, _label: &()) {}

    fn is_start(&self, state: u32, _label: &()) -> bool {
        state == self.start
    }

    fn start_state(&self) -> Option<u32> {
        Some(self.start)
    }

    #[inline]
    fn heuristic(&self, state: u32, _label: &()) -> f64 {
        let (x, y) = self.padded_xy(state);
        let dx = (x - self.start_xy.0).abs();
        let dy = (y - self.start_xy.1).abs();
        dx.max(dy) + (std::f64::consts::SQRT_2 - 1.0) * dx.min(dy)
    }

    /// The octile distance is a metric: no state's heuristic falls by more than the
    /// distance the start moved.
    fn heuristic_drop(&self, previous: u32) -> Option<f64> {
        Some(self.heuristic(previous, &()))
    }
}

/// One line of a Moving AI `.scen` file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scenario {
    /// Bucket number (floor of the optimal length / 4).
    pub bucket: u32,
    /// Start column.
    pub start_x: u32,
    /// Start row.
    pub start_y: u32,
    /// Goal column.
    pub goal_x: u32,
    /// Goal row.
    pub goal_y: u32,
    /// The published optimal path length.
    pub optimal: f64,
}

/// Reads a Moving AI `.scen` text (`version 1` then 9 tab-separated fields a line).
pub fn parse_scenarios(text: &str) -> Result<Vec<Scenario>, GridError> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim_end_matches('\r');
        if line.trim().is_empty() || (i == 0 && line.starts_with("version")) {
            continue;
        }
        let f: Vec<&str> = line.split('\t').collect();
        let bad = |what: &str| GridError::Shape { line: i + 1, message: format!("{what}: {line:?}") };
        if f.len() != 9 {
            return Err(bad("expected 9 tab-separated fields"));
        }
        let u = |s: &str| s.trim().parse::<u32>().map_err(|_| bad("not a non-negative integer"));
        let optimal = f[8]
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v >= 0.0)
            .ok_or_else(|| bad("bad optimal length: need a finite number ≥ 0"))?;
        out.push(Scenario {
            bucket: u(f[0])?,
            start_x: u(f[4])?,
            start_y: u(f[5])?,
            goal_x: u(f[6])?,
            goal_y: u(f[7])?,
            optimal,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The multiplicative row split equals integer division, for grids from the
    /// smallest to the largest the parser accepts, at their first and last cells and
    /// across the range in between.
    #[test]
    fn rows_by_reciprocal_equal_division() {
        for (width, height) in [(1, 1), (3, 7), (510, 512), (1022, 1024), (65_534, 32_767), (1_000_000, 2147)] {
            let grid = Grid { width, height, ..Grid::new(1, 1) };
            let stride = width + 2;
            let grid = Grid { stride, inv_stride: u64::MAX / u64::from(stride) + 1, ..grid };
            let last = stride * (height + 2) - 1;
            let cells = (0..2000u32.min(last))
                .chain((0..2000).map(|k| last.saturating_sub(k)))
                .chain((0..4000).map(|k| last / 4000 * k));
            for cell in cells {
                let (x, y) = grid.padded_xy(cell);
                assert_eq!(
                    (x, y),
                    (f64::from(cell % stride), f64::from(cell / stride)),
                    "stride {stride}, cell {cell}"
                );
            }
        }
    }
}
