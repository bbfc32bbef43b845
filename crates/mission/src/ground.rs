//! Terrain classes: what the ground is, cell by cell — sand, bedrock, regolith — and
//! what that does to a drive: a factor on the rover's speed, a factor on its locomotion
//! power (rolling resistance and sinkage, lumped) and, optionally, a slope limit of its
//! own. A drive is costed half over each of the two cells it joins, as its slope is read
//! from both ([`crate::ActionModel::drive_geometry`]).
//!
//! Cells a class map does not cover are unclassified: the rover's own model holds there
//! (both factors 1, no slope limit beyond the rover's).

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// The class index of a cell no class covers.
pub const UNCLASSIFIED: u8 = u8::MAX;

/// One terrain class.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TerrainClass {
    /// A name for reports ("sand").
    pub name: String,
    /// Drive speed on it over the rover's speed on the same slope (0.01..=10).
    pub speed_factor: f64,
    /// Locomotion power on it over the rover's at the same speed and slope (0.01..=10).
    pub power_factor: f64,
    /// Steepest slope a drive may touch on it, degrees (0..90), beside the rover's own
    /// limit; applies where the drive's `max_slope` constraint does.
    pub max_slope_deg: Option<f64>,
}

/// What a class does to the half of a drive over one cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Factors {
    pub speed: f64,
    pub power: f64,
    /// The class's slope limit, degrees (infinite: none).
    pub max_slope_deg: f64,
}

impl Factors {
    /// The rover's own model (an unclassified cell).
    pub(crate) const NOMINAL: Factors = Factors { speed: 1.0, power: 1.0, max_slope_deg: f64::INFINITY };
}

/// The class of every cell of a map, and the classes.
#[derive(Debug, Clone, PartialEq)]
pub struct ClassMap {
    classes: Vec<TerrainClass>,
    factors: Vec<Factors>,
    /// Per cell: an index into `classes`, or [`UNCLASSIFIED`].
    cells: Vec<u8>,
    /// The slowest and fastest speed factors of the cells, and their least power
    /// factor (the rover's own 1 counted where a cell is unclassified): the search's
    /// bounds read them for every label.
    speed_range: (f64, f64),
    least_power: f64,
}

impl ClassMap {
    /// The ground of a map whose cell `i` has class `classes[cells[i]]` (or none:
    /// [`UNCLASSIFIED`]). At most 255 classes; factors in 0.01..=10; slope limits in
    /// (0, 90) degrees.
    pub fn new(classes: Vec<TerrainClass>, cells: Vec<u8>) -> Result<ClassMap> {
        let bad = |message: String| Err(Error::Config { field: "terrain_classes", message });
        if classes.len() >= usize::from(UNCLASSIFIED) {
            return bad(format!("{} classes: allowed at most {}", classes.len(), UNCLASSIFIED - 1));
        }
        for c in &classes {
            for (what, v) in [("speed_factor", c.speed_factor), ("power_factor", c.power_factor)] {
                if !(0.01..=10.0).contains(&v) {
                    return bad(format!("class {:?}: {what} {v}: allowed 0.01..=10", c.name));
                }
            }
            if let Some(s) = c.max_slope_deg
                && !(s > 0.0 && s < 90.0)
            {
                return bad(format!("class {:?}: max_slope_deg {s}: allowed 0..90 degrees", c.name));
            }
        }
        if let Some(&i) = cells.iter().find(|&&i| i != UNCLASSIFIED && usize::from(i) >= classes.len()) {
            return bad(format!("a cell of class index {i}, with {} classes", classes.len()));
        }
        let factors = classes
            .iter()
            .map(|c| Factors {
                speed: c.speed_factor,
                power: c.power_factor,
                max_slope_deg: c.max_slope_deg.unwrap_or(f64::INFINITY),
            })
            .collect();
        let mut ground = ClassMap { classes, factors, cells, speed_range: (1.0, 1.0), least_power: 1.0 };
        let (counts, none) = ground.counts();
        let present: Vec<Factors> = (ground.factors.iter().zip(&counts))
            .filter(|(_, n)| **n > 0)
            .map(|(f, _)| *f)
            .chain((none > 0).then_some(Factors::NOMINAL))
            .collect();
        if !present.is_empty() {
            let speeds = present.iter().map(|f| f.speed);
            ground.speed_range =
                (speeds.clone().fold(f64::INFINITY, f64::min), speeds.fold(f64::NEG_INFINITY, f64::max));
            ground.least_power = present.iter().map(|f| f.power).fold(f64::INFINITY, f64::min);
        }
        Ok(ground)
    }

    /// The classes.
    pub fn classes(&self) -> &[TerrainClass] {
        &self.classes
    }

    /// Cells the ground covers.
    pub fn cells(&self) -> usize {
        self.cells.len()
    }

    /// The class index of `cell`, or `None` where it is unclassified.
    pub fn class_index(&self, cell: u32) -> Option<u8> {
        self.cells.get(cell as usize).copied().filter(|&i| i != UNCLASSIFIED)
    }

    /// The class of `cell`, if any.
    pub fn class_of(&self, cell: u32) -> Option<&TerrainClass> {
        self.class_index(cell).map(|i| &self.classes[usize::from(i)])
    }

    /// How many cells each class holds (in the order of [`ClassMap::classes`]), and how
    /// many are unclassified.
    pub fn counts(&self) -> (Vec<usize>, usize) {
        let mut counts = vec![0usize; self.classes.len()];
        let mut none = 0;
        for &i in &self.cells {
            match counts.get_mut(usize::from(i)) {
                Some(n) => *n += 1,
                None => none += 1,
            }
        }
        (counts, none)
    }

    pub(crate) fn factors(&self, cell: u32) -> Factors {
        self.class_index(cell).map_or(Factors::NOMINAL, |i| self.factors[usize::from(i)])
    }

    /// The slowest and fastest speed factors any cell has (the rover's own 1 counted
    /// where some cell is unclassified).
    pub(crate) fn speed_range(&self) -> (f64, f64) {
        self.speed_range
    }

    /// The least power factor any cell has (1 where some cell is unclassified).
    pub(crate) fn least_power(&self) -> f64 {
        self.least_power
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn class(name: &str, speed: f64, power: f64) -> TerrainClass {
        TerrainClass { name: name.into(), speed_factor: speed, power_factor: power, max_slope_deg: None }
    }

    #[test]
    fn ranges_count_only_the_classes_present_and_the_rovers_own_where_unclassified() {
        let classes = vec![class("sand", 0.5, 2.0), class("bedrock", 1.5, 0.8), class("unused", 0.1, 0.1)];
        let g = ClassMap::new(classes.clone(), vec![0, 1, 0, 1]).unwrap();
        assert_eq!(g.speed_range(), (0.5, 1.5));
        assert_eq!(g.least_power(), 0.8);
        assert_eq!(g.counts(), (vec![2, 2, 0], 0));
        let g = ClassMap::new(classes, vec![0, UNCLASSIFIED]).unwrap();
        assert_eq!(g.speed_range(), (0.5, 1.0));
        assert_eq!(g.least_power(), 1.0);
        assert_eq!(g.class_of(1), None);
        assert_eq!(g.class_of(0).map(|c| c.name.as_str()), Some("sand"));
    }

    #[test]
    fn out_of_range_factors_slopes_and_indices_are_refused() {
        assert!(ClassMap::new(vec![class("x", 0.0, 1.0)], vec![0]).is_err());
        assert!(ClassMap::new(vec![class("x", 1.0, 11.0)], vec![0]).is_err());
        assert!(ClassMap::new(vec![class("x", f64::NAN, 1.0)], vec![0]).is_err());
        let steep = TerrainClass { max_slope_deg: Some(90.0), ..class("x", 1.0, 1.0) };
        assert!(ClassMap::new(vec![steep], vec![0]).is_err());
        assert!(ClassMap::new(vec![class("x", 1.0, 1.0)], vec![1]).is_err());
    }
}
