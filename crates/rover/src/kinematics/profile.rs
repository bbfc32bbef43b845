//! The terrain as one side's wheel plane sees it: heights along the contact line,
//! squeezed by the sideways slope under each wheel, and the dilated terrain the axles
//! ride on.

use areo_terrain::Ground;

use super::WHEEL_SAMPLES;

/// A point on the dilated terrain: axle height, the contact's offset u along the line
/// and the terrain slope there (= dA/ds where A is smooth).
#[derive(Debug, Clone, Copy)]
pub(super) struct Dilated {
    pub(super) z: f64,
    pub(super) u: f64,
    pub(super) slope: f64,
    /// The maximising sample.
    pub(super) k: usize,
}

/// The ground along one side's contact line as its tilted wheel plane sees it: true
/// heights relative to the plane's reference height, squeezed by the sideways slope
/// under each wheel (front beyond `split.0`, rear behind `split.1`, middle between).
#[derive(Debug, Clone, Copy)]
pub(super) struct Line<'g, G> {
    pub(super) ground: &'g G,
    pub(super) origin: (f64, f64),
    pub(super) dir: (f64, f64),
    pub(super) zref: f64,
    pub(super) squeeze: [f64; 3],
    pub(super) split: (f64, f64),
}

impl<G: Ground> Line<'_, G> {
    /// Which wheel's stretch of the line s is in: 0 front, 1 middle, 2 rear.
    #[inline]
    pub(super) fn segment(&self, s: f64) -> usize {
        if s > self.split.0 {
            0
        } else if s < self.split.1 {
            2
        } else {
            1
        }
    }

    #[inline]
    pub(super) fn squeeze_at(&self, s: f64) -> f64 {
        self.squeeze[self.segment(s)]
    }

    #[inline]
    pub(super) fn at(&self, s: f64) -> Option<f64> {
        let h = self.ground.height(self.origin.0 + self.dir.0 * s, self.origin.1 + self.dir.1 * s)?;
        Some(self.zref + (h - self.zref) * self.squeeze_at(s))
    }

    /// The sample maximising (squeezed height at s0 + k·ds)·inv + rise[k] over the
    /// `rise.len()` samples, or `None` if any is off the terrain.
    #[inline]
    pub(super) fn argmax_along(&self, s0: f64, ds: f64, inv: f64, rise: &[f64; WHEEL_SAMPLES + 1]) -> Option<usize> {
        let mut h = [0.0; WHEEL_SAMPLES + 1];
        let start = (self.origin.0 + self.dir.0 * s0, self.origin.1 + self.dir.1 * s0);
        if !self.ground.heights_along(start, (self.dir.0 * ds, self.dir.1 * ds), &mut h) {
            return None;
        }
        let (first, last) = (self.segment(s0), self.segment(s0 + ds * WHEEL_SAMPLES as f64));
        let mut best = (f64::NEG_INFINITY, 0);
        if first == last {
            // One wheel's stretch (the usual case): one squeeze factor, and the constant
            // part of the squeezed height cannot change which sample is highest.
            let a = self.squeeze[first] * inv;
            for (k, (h, rise)) in h.iter().zip(rise).enumerate() {
                let z = h * a + rise;
                if z > best.0 {
                    best = (z, k);
                }
            }
        } else {
            for (k, (h, rise)) in h.iter().zip(rise).enumerate() {
                let z = (self.zref + (h - self.zref) * self.squeeze_at(s0 + ds * k as f64)) * inv + rise;
                if z > best.0 {
                    best = (z, k);
                }
            }
        }
        Some(best.1)
    }

    #[inline]
    pub(super) fn at_slope(&self, s: f64) -> Option<(f64, f64)> {
        let (x, y) = (self.origin.0 + self.dir.0 * s, self.origin.1 + self.dir.1 * s);
        let (h, g) = self.ground.height_slope(x, y, self.dir)?;
        let k = self.squeeze_at(s);
        Some((self.zref + (h - self.zref) * k, g * k))
    }
}
