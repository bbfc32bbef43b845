//! The horizon of a terrain that differs from a map's in a few places, traced only where
//! it can differ.
//!
//! A cell's horizon in a sector is a blend of the ray lines that pass within a line
//! spacing of it, and a line's tangents depend on nothing but the heights it samples
//! (the two cells straddling each crossing) and its observers' heights (the nearest
//! cell). A line that samples no changed cell gives bit for bit the tangents it gave on
//! the map, so only the lines within a cell of a changed cell ("touched") are traced,
//! with the lines next to them that the cells they reach also blend; only the cells a
//! touched line reaches are compared. The answer is [`HorizonMap::changes`]'s, cell for
//! cell and bit for bit (`tests.rs`), at a cost that grows with the changed area's
//! breadth across each sector's lines instead of with the map.

use rayon::prelude::*;

use super::{
    Accumulator, Codes, Elevations, HorizonChanges, HorizonMap, SPACING, decode, decode_narrow, encode_one, narrow,
    trace_lines,
};
use crate::dem::Dem;
use crate::error::{Error, Result};
use crate::shadow::Curvature;

/// The share of changed cells above which every line is traced anyway: past it, most
/// lines of every sector would be touched.
const MOST_CHANGED: f64 = 0.25;

/// Transverse slack, cells, on the windows of lines that sample a changed cell: the
/// crossing's arithmetic rounds, a line a hair outside is traced too.
const SLACK: f64 = 0.01;

/// The part of a sector's line family to trace: the lines near changed cells, and the
/// cells the touched ones reach.
pub(super) struct Part<'a> {
    /// The changed cells, row-major.
    changed: &'a [usize],
    /// The grid, columns and rows.
    grid: (usize, usize),
    /// Per cell in the accumulator's layout: whether a touched line reached it.
    reached: Vec<bool>,
}

/// Windows of a line's offset t0 (cells across the lines at the family's first step).
pub(super) struct Windows {
    /// Lines to trace: the touched ones and their neighbours (sorted, disjoint).
    traced: Vec<(f64, f64)>,
    /// Lines that sample a changed cell (sorted, disjoint).
    touched: Vec<(f64, f64)>,
}

impl Part<'_> {
    /// The windows of the family whose lines are t = t0 − shift·j (j along them, t
    /// across; `along_cols`: j is the column).
    pub(super) fn windows(&self, along_cols: bool, (cols, _rows): (usize, usize), shift: f64) -> Windows {
        let at = |i: usize| {
            let (col, row) = ((i % cols) as f64, (i / cols) as f64);
            if along_cols { row + shift * col } else { col + shift * row }
        };
        let centres: Vec<f64> = self.changed.iter().map(|&i| at(i)).collect();
        // A line samples cells floor(t) and floor(t) + 1 and observes the nearest: within
        // one cell of t. A cell it reaches blends it with lines within two spacings.
        let touched = merged(centres.iter().map(|&u| (u - 1.0 - SLACK, u + 1.0 + SLACK)).collect());
        let wide = 1.0 + 2.0 * SPACING + 2.0 * SLACK;
        let traced = merged(centres.iter().map(|&u| (u - wide, u + wide)).collect());
        Windows { traced, touched }
    }

    /// Marks the observer cells of a touched line (`usize::MAX`: none at that step).
    pub(super) fn reach(&mut self, cells: &[usize]) {
        for &c in cells {
            if c != usize::MAX {
                self.reached[c] = true;
            }
        }
    }
}

impl Windows {
    /// Whether the line at offset `t0` is traced.
    pub(super) fn traces(&self, t0: f64) -> bool {
        within(&self.traced, t0)
    }

    /// Whether the line at offset `t0` samples a changed cell.
    pub(super) fn touches(&self, t0: f64) -> bool {
        within(&self.touched, t0)
    }
}

/// Closed intervals merged into sorted, disjoint ones.
fn merged(mut spans: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    spans.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(spans.len());
    for (a, b) in spans {
        match out.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => out.push((a, b)),
        }
    }
    out
}

fn within(spans: &[(f64, f64)], x: f64) -> bool {
    let k = spans.partition_point(|s| s.1 < x);
    k < spans.len() && spans[k].0 <= x
}

impl HorizonMap {
    /// [`HorizonMap::changes`] of `dem` where this map is `before`'s horizon map: the
    /// same cells and angles, tracing only the lines through cells whose height (or
    /// presence) differs between the two (all of them past a quarter of the map changed).
    pub fn changes_from(&self, before: &Dem, dem: &Dem, curvature: Curvature) -> Result<HorizonChanges> {
        let (cols, rows) = (self.cols, self.rows);
        for d in [before, dem] {
            if d.cols() != cols || d.rows() != rows {
                return Err(Error::BadGrid(format!(
                    "{}×{} cells against a horizon map of {cols}×{rows}: they must share one grid",
                    d.cols(),
                    d.rows()
                )));
            }
        }
        let cells = cols * rows;
        let (za, zb) = (before.elevations(), dem.elevations());
        let (va, vb) = (before.valid_mask(), dem.valid_mask());
        let changed: Vec<usize> =
            (0..cells).filter(|&i| va[i] != vb[i] || (vb[i] && za[i].to_bits() != zb[i].to_bits())).collect();
        if changed.len() as f64 > MOST_CHANGED * cells as f64 {
            return self.changes(dem, curvature);
        }
        if changed.is_empty() {
            return Ok(self.profiles_of(Vec::new()));
        }
        let zn = Elevations::of(dem);
        let sectors = self.sectors;
        let paired = sectors.is_multiple_of(2);
        let jobs = if paired { sectors / 2 } else { sectors };
        let found: Vec<Vec<(u32, u16, f64)>> = (0..jobs)
            .into_par_iter()
            .map_init(
                || (Accumulator::default(), Accumulator::default()),
                |(toward, away), s| {
                    let az = s as f64 * 360.0 / sectors as f64;
                    let mut part = Part { changed: &changed, grid: (cols, rows), reached: vec![false; cells] };
                    let opposite = paired.then_some(&mut *away);
                    trace_lines(dem, &zn, az, curvature, (0, 0), Some(&mut *toward), opposite, Some(&mut part));
                    let mut out = self.compared(toward, &part, &zn, s);
                    if paired {
                        out.extend(self.compared(away, &part, &zn, s + jobs));
                    }
                    out
                },
            )
            .collect();
        Ok(self.profiles_of(found.into_iter().flatten().collect()))
    }

    /// The cells a touched line reached whose code in sector `s` differs from this map's:
    /// (row-major cell, sector, the new angle in degrees at the map's precision).
    fn compared(&self, acc: &Accumulator, part: &Part<'_>, zn: &Elevations, s: usize) -> Vec<(u32, u16, f64)> {
        let (cols, rows) = part.grid;
        let z = if acc.transposed { &zn.cols_first } else { &zn.rows_first };
        let mut out = Vec::new();
        for (a, _) in part.reached.iter().enumerate().filter(|(_, r)| **r) {
            let i = if acc.transposed { (a % rows) * cols + a / rows } else { a };
            if let Some(deg) = self.differs(s, i, encode_one(acc.cells[a], z[a])) {
                out.push((i as u32, s as u16, deg));
            }
        }
        out
    }

    /// The angle of `code` in sector `s` at cell `i` (row-major), degrees at this map's
    /// precision, where it differs from this map's.
    pub(super) fn differs(&self, s: usize, i: usize, code: u16) -> Option<f64> {
        let k = s * self.cols * self.rows + i;
        match &self.angles {
            Codes::Wide(a) => (code != a[k]).then(|| decode(code)),
            Codes::Narrow(a) => (narrow(code) != a[k]).then(|| decode_narrow(narrow(code))),
        }
    }

    /// The changes as profiles: each changed cell's angles in every sector, this map's
    /// where they did not change.
    pub(super) fn profiles_of(&self, changed: Vec<(u32, u16, f64)>) -> HorizonChanges {
        let mut profiles: std::collections::HashMap<u32, Box<[f32]>> = std::collections::HashMap::new();
        for (i, s, v) in changed {
            let profile = profiles.entry(i).or_insert_with(|| self.cell_profile(i as usize).into_boxed_slice());
            profile[s as usize] = v as f32;
        }
        HorizonChanges { sectors: self.sectors, profiles }
    }
}
