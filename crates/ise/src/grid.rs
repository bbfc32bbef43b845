//! An 8-connected weighted grid as an ISE [`Domain`]: the Moving AI benchmark rules
//! (straight step 1, diagonal √2, no corner cutting) with per-cell weights for
//! re-planning experiments.
//!
//! A step between adjacent free cells a and b costs its length × (w(a) + w(b)) / 2, with
//! every weight ≥ 1 so that the octile distance stays an admissible heuristic. A
//! diagonal step needs both orthogonal neighbours free.

use crate::domain::{Domain, Step};

/// Offsets of the 8 moves: N, NE, E, SE, S, SW, W, NW (x right, y down as in the files).
const MOVES: [(i32, i32); 8] = [(0, -1), (1, -1), (1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1)];

/// A grid of free and blocked cells with weights.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    width: u32,
    height: u32,
    free: Vec<bool>,
    weight: Vec<f32>,
    start: u32,
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
    /// An all-free grid of unit weight; start at cell 0.
    pub fn new(width: u32, height: u32) -> Grid {
        let n = (width as usize) * (height as usize);
        Grid { width, height, free: vec![true; n], weight: vec![1.0; n], start: 0 }
    }

    /// Reads a Moving AI `.map` text (`type octile`, `height`, `width`, `map`, rows).
    /// `.`, `G` and `S` are free; every other character is blocked. CRLF is accepted.
    pub fn parse_movingai(text: &str) -> Result<Grid, GridError> {
        let mut lines = text.lines().map(|l| l.trim_end_matches('\r')).enumerate();
        let (mut width, mut height) = (None, None);
        for (i, line) in lines.by_ref() {
            let mut parts = line.split_whitespace();
            match (parts.next(), parts.next()) {
                (Some("type"), _) => {}
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
                grid.free[(rows * width) as usize + x] = matches!(c, b'.' | b'G' | b'S');
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

    /// The cell index of (x, y).
    pub fn cell(&self, x: u32, y: u32) -> u32 {
        y * self.width + x
    }

    /// (x, y) of a cell index.
    pub fn xy(&self, cell: u32) -> (u32, u32) {
        (cell % self.width, cell / self.width)
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
    }

    /// The cost of the move from `a` to the neighbour `b` by move `m`, or `None` if it
    /// is not allowed.
    fn step_cost(&self, a: u32, m: usize) -> Option<(u32, f64)> {
        let (x, y) = self.xy(a);
        let (dx, dy) = MOVES[m];
        let (nx, ny) = (x as i64 + dx as i64, y as i64 + dy as i64);
        if !self.contains(nx, ny) {
            return None;
        }
        let b = self.cell(nx as u32, ny as u32);
        if !self.free[a as usize] || !self.free[b as usize] {
            return None;
        }
        let len = if dx != 0 && dy != 0 {
            // No corner cutting: both orthogonal neighbours must be free.
            if !self.free[self.cell(nx as u32, y) as usize] || !self.free[self.cell(x, ny as u32) as usize] {
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
    type Action = u8;

    fn actions(&self, _state: u32, _label: &(), out: &mut Vec<u8>) {
        out.extend(0..8u8);
    }

    fn predecessor(&self, state: u32, _label: &(), action: u8) -> Option<Step<Grid>> {
        // Action m leads from the predecessor to `state`: the predecessor lies one move
        // in the opposite direction, and the costs are symmetric.
        let back = (action as usize + 4) % 8;
        let (pred, _) = self.step_cost(state, back)?;
        let (_, cost) = self.step_cost(pred, action as usize)?;
        Some(Step { state: pred, label: (), cost })
    }

    fn successors(&self, state: u32, out: &mut Vec<u32>) {
        let (x, y) = self.xy(state);
        for (dx, dy) in MOVES {
            let (nx, ny) = (x as i64 + dx as i64, y as i64 + dy as i64);
            if self.contains(nx, ny) {
                out.push(self.cell(nx as u32, ny as u32));
            }
        }
    }

    fn key(&self, _state: u32, _label: &()) {}

    fn is_start(&self, state: u32, _label: &()) -> bool {
        state == self.start
    }

    fn start_state(&self) -> Option<u32> {
        Some(self.start)
    }

    fn heuristic(&self, state: u32, _label: &()) -> f64 {
        self.octile(state, self.start)
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
        let optimal = f[8].trim().parse::<f64>().map_err(|_| bad("bad optimal length"))?;
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
