//! The ground under a rover on the world: the terrain classes the map carries, and a
//! body's attitude on a cell's ground plane or on a drive between two cells.

use std::sync::Arc;

use super::World;
use crate::error::{Error, Result};
use crate::ground::{ClassMap, Factors};

impl World {
    /// Gives the map its terrain classes (one per cell of the map).
    pub fn set_ground(&mut self, ground: Arc<ClassMap>) -> Result<()> {
        if ground.cells() != self.cells() {
            return Err(Error::Config {
                field: "terrain_classes",
                message: format!("classes for {} cells on a map of {}", ground.cells(), self.cells()),
            });
        }
        self.ground = Some(ground);
        Ok(())
    }

    /// The terrain classes, if the map has them.
    pub fn ground(&self) -> Option<&ClassMap> {
        self.ground.as_deref()
    }

    /// What the class of `cell` does to a drive over it (the rover's own model where
    /// the map has no classes or the cell none).
    pub(crate) fn factors(&self, cell: u32) -> Factors {
        self.ground.as_ref().map_or(Factors::NOMINAL, |g| g.factors(cell))
    }

    /// The slowest and fastest speed factors of the map's classes (1 and 1 without).
    pub(crate) fn speed_factor_range(&self) -> (f64, f64) {
        self.ground.as_ref().map_or((1.0, 1.0), |g| g.speed_range())
    }

    /// The least power factor of the map's classes (1 without).
    pub(crate) fn least_power_factor(&self) -> f64 {
        self.ground.as_ref().map_or(1.0, |g| g.least_power())
    }

    /// The rover's attitude on the ground of `cell` heading `heading_deg` (clockwise from
    /// the grid's north): pitch (positive nose up) and roll (positive right side up),
    /// degrees, from the cell's ground normal — the attitude of a body resting on the
    /// plane through the cell with that heading.
    pub fn attitude_deg(&self, cell: u32, heading_deg: f64) -> (f64, f64) {
        let n = self.normal(cell);
        let (s, c) = heading_deg.to_radians().sin_cos();
        // Ahead (s, c, 0) and to the right (c, −s, 0) on the grid's (east, north, up).
        let ahead = n[0] * s + n[1] * c;
        let right = n[0] * c - n[1] * s;
        // The ground rises ahead where the normal leans back: pitch = atan(−n·d / n_z).
        // The body's lateral axis lies in the plane; its rise is the roll's sine.
        let pitch = (-ahead).atan2(n[2]).to_degrees();
        let roll = (-right).clamp(-1.0, 1.0).asin().to_degrees();
        (pitch, roll)
    }

    /// A drive from `from` to its neighbour `k` ([`crate::NEIGHBOURS`]): its pitch (the
    /// slope between the cells, positive uphill) and its roll (the larger across the
    /// heading of the two cells' ground, [`World::attitude_deg`]), degrees; `None` off
    /// the map or on missing data.
    pub fn drive_attitude_deg(&self, from: u32, k: u8) -> Option<(f64, f64)> {
        let (c, r) = self.col_row(from);
        let (dc, dr) = crate::NEIGHBOURS[k as usize % 8];
        let (nc, nr) = (c.checked_add_signed(dc as isize)?, r.checked_add_signed(dr as isize)?);
        if nc >= self.cols() || nr >= self.rows() {
            return None;
        }
        let to = self.cell(nc, nr);
        let rise = self.elevation(to)? - self.elevation(from)?;
        let run = (f64::from(dc) * self.dem.dx()).hypot(f64::from(dr) * self.dem.dy());
        let heading = f64::from(dc).atan2(-f64::from(dr)).to_degrees();
        let (a, b) = (self.attitude_deg(from, heading).1, self.attitude_deg(to, heading).1);
        Some(((rise / run).atan().to_degrees(), if b.abs() > a.abs() { b } else { a }))
    }
}
