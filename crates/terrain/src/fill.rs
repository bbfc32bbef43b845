//! Filling nodata holes (stereo DTM gaps) with the harmonic surface that meets the
//! valid terrain around them: the discrete Laplace equation
//! (z_E − 2z + z_W)/dx² + (z_N − 2z + z_S)/dy² = 0 over the hole cells, with the valid
//! neighbours as fixed boundary values and no flux across the map edge. The system is
//! sparse, symmetric and positive definite; faer's sparse Cholesky solves it.

use faer::Mat;
use faer::prelude::Solve;
use faer::sparse::{SparseColMat, Triplet};

use crate::dem::Dem;
use crate::error::{Error, Result};

/// A DEM with its holes filled, and which cells were filled (planners treat those as
/// uncertain).
#[derive(Debug, Clone, PartialEq)]
pub struct Filled {
    /// The DEM, every cell valid except holes with no valid cell around them at all.
    pub dem: Dem,
    /// True where a value was interpolated.
    pub filled: Vec<bool>,
}

/// Fills every missing cell that is connected to valid terrain.
pub fn fill_holes(dem: &Dem) -> Result<Filled> {
    let (cols, rows) = (dem.cols(), dem.rows());
    let valid = dem.valid_mask();
    let z = dem.elevations();
    // Number the unknowns.
    let mut unknown = vec![usize::MAX; cols * rows];
    let mut cells = Vec::new();
    for (i, ok) in valid.iter().enumerate() {
        if !ok {
            unknown[i] = cells.len();
            cells.push(i);
        }
    }
    if cells.is_empty() {
        return Ok(Filled { dem: dem.clone(), filled: vec![false; cols * rows] });
    }
    if cells.len() == cols * rows {
        return Err(Error::BadGrid("every cell is missing: nothing to interpolate from".into()));
    }
    let (wx, wy) = (1.0 / (dem.dx() * dem.dx()), 1.0 / (dem.dy() * dem.dy()));
    let mut triplets = Vec::with_capacity(cells.len() * 5);
    let mut rhs = Mat::<f64>::zeros(cells.len(), 1);
    for (k, &i) in cells.iter().enumerate() {
        let (c, r) = (i % cols, i / cols);
        let mut diag = 0.0;
        let neighbours = [
            (c > 0).then(|| (i - 1, wx)),
            (c + 1 < cols).then(|| (i + 1, wx)),
            (r > 0).then(|| (i - cols, wy)),
            (r + 1 < rows).then(|| (i + cols, wy)),
        ];
        for (j, w) in neighbours.into_iter().flatten() {
            diag += w;
            if valid[j] {
                rhs[(k, 0)] += w * f64::from(z[j]);
            } else {
                triplets.push(Triplet::new(k, unknown[j], -w));
            }
        }
        triplets.push(Triplet::new(k, k, diag));
    }
    let n = cells.len();
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets)
        .map_err(|e| Error::BadGrid(format!("hole-filling system: {e:?}")))?;
    // A hole component with no valid neighbour anywhere is singular; report it.
    let llt = a
        .sp_cholesky(faer::Side::Lower)
        .map_err(|_| Error::BadGrid("a region of missing cells touches no valid cell".into()))?;
    let x = llt.solve(&rhs);
    let mut out = z.to_vec();
    let mut filled = vec![false; cols * rows];
    for (k, &i) in cells.iter().enumerate() {
        out[i] = x[(k, 0)] as f32;
        filled[i] = true;
    }
    let dem = Dem::new(cols, rows, dem.dx(), dem.dy(), dem.x0(), dem.y_top(), out)?.with_georef(*dem.georef());
    Ok(Filled { dem, filled })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn punch(dem: &Dem, holes: &[(usize, usize)]) -> Dem {
        let mut mask = vec![true; dem.cols() * dem.rows()];
        for &(c, r) in holes {
            mask[dem.index(c, r)] = false;
        }
        let mut z = dem.elevations().to_vec();
        for (v, ok) in z.iter_mut().zip(&mask) {
            if !ok {
                *v = f32::NAN;
            }
        }
        Dem::new(dem.cols(), dem.rows(), dem.dx(), dem.dy(), dem.x0(), dem.y_top(), z).unwrap().with_mask(mask).unwrap()
    }

    fn check(truth: &Dem, holes: &[(usize, usize)]) {
        let filled = fill_holes(&punch(truth, holes)).unwrap();
        for &(c, r) in holes {
            let got = filled.dem.z(c, r).unwrap();
            let want = truth.z(c, r).unwrap();
            assert!((got - want).abs() < 1e-6, "({c},{r}): {got} vs {want}");
            assert!(filled.filled[truth.index(c, r)]);
        }
        assert_eq!(filled.filled.iter().filter(|f| **f).count(), holes.len());
    }

    #[test]
    fn a_hole_in_a_plane_is_restored() {
        let plane = Dem::from_fn(12, 10, 2.0, 3.0, |x, y| 0.1 + 0.01 * x - 0.02 * y).unwrap();
        let holes: Vec<_> = (3..8).flat_map(|c| (2..6).map(move |r| (c, r))).collect();
        check(&plane, &holes);
    }

    #[test]
    fn a_hole_in_a_harmonic_function_is_restored_even_at_the_edge() {
        // x² − y² with dx ≠ dy is exactly harmonic for the discrete operator (second
        // differences of quadratics are exact). Values are kept small for f32.
        let f = Dem::from_fn(15, 11, 0.1, 0.2, |x, y| (x - 0.7) * (x - 0.7) - (y - 1.1) * (y - 1.1)).unwrap();
        let holes: Vec<_> = (4..10).flat_map(|c| (3..8).map(move |r| (c, r))).collect();
        check(&f, &holes);
    }

    #[test]
    fn an_all_missing_grid_is_an_error() {
        let dem = Dem::new(2, 2, 1.0, 1.0, 0.0, 2.0, vec![f32::NAN; 4]).unwrap();
        assert!(fill_holes(&dem).is_err());
    }
}
