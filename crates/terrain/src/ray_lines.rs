//! Ray lines: which family of grid lines a direction traces ([`LineGeometry`]), and
//! a grid read and written one line — a row or a column — at a time ([`Lines`]).
//!
//! Walking a column of a row-major grid cell by cell touches a new memory page at
//! every cell, and the page misses cost more than the trace's arithmetic. Columns are
//! therefore read and written in blocks of [`BLOCK`] columns, copied column-major:
//! each row of the grid is touched once per block.

use crate::dem::Dem;

/// Columns per block: each row of the grid is read in runs of 64 heights (16 gave
/// a third of the exact trace's time to these reads, 128 no gain over 64).
const BLOCK: usize = 64;

/// The family of ray lines for a direction: columns or rows, whichever the direction
/// crosses faster, so that a step from one line to the next moves at most one cell
/// along the lines.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LineGeometry {
    /// Lines are columns (else rows).
    pub(crate) along_cols: bool,
    /// Number of lines, and of cells on each.
    pub(crate) n_lines: usize,
    pub(crate) n_cells: usize,
    /// Metres travelled along the direction from one line to the next.
    pub(crate) step_m: f64,
    /// Change of position along the lines (cells) over that step.
    pub(crate) shift: f64,
    /// The direction points toward higher line indices.
    pub(crate) toward_higher_line: bool,
}

impl LineGeometry {
    /// The lines for a direction `azimuth_deg` (clockwise from north) over `dem`.
    pub(crate) fn toward(dem: &Dem, azimuth_deg: f64) -> LineGeometry {
        let a = azimuth_deg.to_radians();
        // Index steps per metre: columns grow east, rows grow south. A component of
        // 1e-16 (a cardinal direction's rounding) is none.
        let snap = |v: f64| if v.abs() < 1e-12 { 0.0 } else { v };
        let (pc, pr) = (snap(a.sin() / dem.dx()), snap(-a.cos() / dem.dy()));
        let along_cols = pc.abs() >= pr.abs();
        let (n_lines, n_cells, step_m, shift, toward_higher_line) = if along_cols {
            (dem.cols(), dem.rows(), 1.0 / pc.abs(), pr / pc.abs(), pc > 0.0)
        } else {
            (dem.rows(), dem.cols(), 1.0 / pr.abs(), pc / pr.abs(), pr > 0.0)
        };
        LineGeometry { along_cols, n_lines, n_cells, step_m, shift, toward_higher_line }
    }
}

/// One trace's access to a DEM's heights and to its per-cell output.
pub(crate) struct Lines<'a> {
    z: &'a [f32],
    valid: &'a [bool],
    cols: usize,
    rows: usize,
    columns: bool,
    /// Heights of the columns from `block_at`, column-major, NaN where missing.
    block: Vec<f64>,
    block_at: Option<usize>,
    /// Results of the columns from `out_at`, column-major, not yet in the output.
    out: Vec<bool>,
    out_at: Option<usize>,
}

impl<'a> Lines<'a> {
    /// Lines are the DEM's columns if `columns`, else its rows.
    pub(crate) fn new(dem: &'a Dem, columns: bool) -> Lines<'a> {
        let (cols, rows) = (dem.cols(), dem.rows());
        let block_len = if columns { BLOCK * rows } else { 0 };
        Lines {
            z: dem.elevations(),
            valid: dem.valid_mask(),
            cols,
            rows,
            columns,
            block: vec![f64::NAN; block_len],
            block_at: None,
            out: vec![false; block_len],
            out_at: None,
        }
    }

    /// Line `line`'s heights into `dst` (one per cell of the line), NaN where missing.
    pub(crate) fn read(&mut self, line: usize, dst: &mut [f64]) {
        if !self.columns {
            let (z, valid) = (&self.z[line * self.cols..][..self.cols], &self.valid[line * self.cols..][..self.cols]);
            for ((d, &z), &v) in dst.iter_mut().zip(z).zip(valid) {
                *d = if v { f64::from(z) } else { f64::NAN };
            }
            return;
        }
        let at = line / BLOCK * BLOCK;
        if self.block_at != Some(at) {
            let width = BLOCK.min(self.cols - at);
            for r in 0..self.rows {
                let i = r * self.cols + at;
                for (c, (&z, &v)) in self.z[i..i + width].iter().zip(&self.valid[i..i + width]).enumerate() {
                    let i = self.slot(c, r);
                    self.block[i] = if v { f64::from(z) } else { f64::NAN };
                }
            }
            self.block_at = Some(at);
        }
        dst.copy_from_slice(&self.block[(line - at) * self.rows..][..self.rows]);
    }

    /// Line `line`'s results (one per cell of the line) into `out`, the whole grid's.
    /// Call [`Lines::finish`] after the last line.
    pub(crate) fn write(&mut self, line: usize, src: &[bool], out: &mut [bool]) {
        if !self.columns {
            out[line * self.cols..][..self.cols].copy_from_slice(src);
            return;
        }
        let at = line / BLOCK * BLOCK;
        if self.out_at != Some(at) {
            self.finish(out);
            self.out_at = Some(at);
        }
        self.out[(line - at) * self.rows..][..self.rows].copy_from_slice(src);
    }

    /// Where column c (of the block) of row r sits in a block.
    #[inline]
    fn slot(&self, c: usize, r: usize) -> usize {
        c * self.rows + r
    }

    /// Writes out the last block of columns.
    pub(crate) fn finish(&mut self, out: &mut [bool]) {
        if let Some(at) = self.out_at.take() {
            let width = BLOCK.min(self.cols - at);
            for r in 0..self.rows {
                let row = &mut out[r * self.cols + at..][..width];
                for (c, o) in row.iter_mut().enumerate() {
                    *o = self.out[self.slot(c, r)];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_and_rows_read_and_write_the_grid() {
        // 37 columns: two full blocks and a partial one; a missing cell reads NaN.
        let mut valid = vec![true; 37 * 5];
        valid[2 * 37 + 3] = false;
        let dem = Dem::from_fn(37, 5, 1.0, 1.0, |x, y| x * 100.0 + y).unwrap().with_mask(valid).unwrap();
        for columns in [true, false] {
            let mut lines = Lines::new(&dem, columns);
            let (n_lines, n_cells) = if columns { (37, 5) } else { (5, 37) };
            let mut out = vec![false; 37 * 5];
            let mut buf = vec![0.0; n_cells];
            // Trace backward, as traces toward a western or northern Sun do.
            for line in (0..n_lines).rev() {
                lines.read(line, &mut buf);
                for (k, h) in buf.iter().enumerate() {
                    let (c, r) = if columns { (line, k) } else { (k, line) };
                    match dem.z(c, r) {
                        Some(z) => assert_eq!(*h, f64::from(z)),
                        None => assert!(h.is_nan()),
                    }
                }
                let marks: Vec<bool> = (0..n_cells).map(|k| (line + k) % 3 == 0).collect();
                lines.write(line, &marks, &mut out);
            }
            lines.finish(&mut out);
            for r in 0..5 {
                for c in 0..37 {
                    assert_eq!(out[r * 37 + c], (c + r) % 3 == 0, "columns {columns}: cell ({c}, {r})");
                }
            }
        }
    }
}
