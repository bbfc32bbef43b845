//! Terrain classes: the job's class map read onto the map's grid (nearest neighbour,
//! [`overlay`]), every id it holds where it covers the map checked against the listed
//! classes, and the classes given to the worlds the rover plans on and drives on; then
//! how much of the plan's and the run's driving each class takes.

use std::collections::BTreeMap;
use std::sync::Arc;

use areo_mission::{Ground, TerrainClass, UNCLASSIFIED};

use super::overlay::{self, Sample};
use super::*;
use crate::format::TerrainClassesSpec;
use crate::report::tempest::{ClassFigures, ClassUse};

/// Reads the class map onto `world`'s grid and gives `world` (and `truth`) its classes;
/// the figures hold the cells of each class (the driving is added by [`drive_use`]).
pub(super) fn apply(
    spec: &TerrainClassesSpec,
    file: &ScenarioFile,
    world: &mut World,
    truth: Option<&mut World>,
    frame: Frame,
) -> Result<ClassFigures> {
    let field = "job.terrain_classes.file";
    let samples = overlay::sample(&spec.file, field, file, world, frame)?;
    let index: BTreeMap<i64, u8> = spec.classes.iter().enumerate().map(|(i, c)| (c.id, i as u8)).collect();
    let allowed = || spec.classes.iter().map(|c| c.id.to_string()).collect::<Vec<_>>().join(", ");
    let bad = |message: String| scenario_error(file, field.to_string(), message);
    let mut cells = Vec::with_capacity(samples.len());
    let mut unknown: BTreeMap<String, usize> = BTreeMap::new();
    let mut holes = 0usize;
    for s in &samples {
        cells.push(match *s {
            Sample::Outside => UNCLASSIFIED,
            Sample::NoData => {
                holes += 1;
                UNCLASSIFIED
            }
            Sample::Value(v) => match (v.fract() == 0.0 && v.abs() < 1e12).then(|| index.get(&(v as i64))).flatten() {
                Some(&i) => i,
                None => {
                    *unknown.entry(format!("{v}")).or_default() += 1;
                    UNCLASSIFIED
                }
            },
        });
    }
    if holes > 0 {
        return Err(bad(format!(
            "{}: {holes} cells of the map fall on cells of the class map with no value (NaN or its no-data): give every cell it covers a class id ({})",
            spec.file,
            allowed()
        )));
    }
    if !unknown.is_empty() {
        let listed: Vec<String> = unknown.iter().take(8).map(|(v, n)| format!("{v} ({n} cells)")).collect();
        return Err(bad(format!(
            "{}: values that are no listed class id under the map: {}{}; the classes list ids {}",
            spec.file,
            listed.join(", "),
            if unknown.len() > 8 { format!(" and {} more", unknown.len() - 8) } else { String::new() },
            allowed()
        )));
    }
    let classes: Vec<TerrainClass> = spec
        .classes
        .iter()
        .map(|c| TerrainClass {
            name: c.name.clone(),
            speed_factor: c.speed_factor,
            power_factor: c.power_factor,
            max_slope_deg: c.max_slope_deg,
        })
        .collect();
    let ground = Arc::new(Ground::new(classes, cells).map_err(|e| bad(e.to_string()))?);
    world.set_ground(ground.clone()).map_err(|e| bad(e.to_string()))?;
    if let Some(t) = truth {
        if (t.cols(), t.rows()) != (world.cols(), world.rows()) {
            return Err(bad(format!(
                "{}: the true terrain ({} × {} cells) is not on the map's grid ({} × {}): terrain classes need one grid for both",
                spec.file,
                t.cols(),
                t.rows(),
                world.cols(),
                world.rows()
            )));
        }
        t.set_ground(ground.clone()).map_err(|e| bad(e.to_string()))?;
    }
    let (counts, unclassified_cells) = ground.counts();
    let classes = spec
        .classes
        .iter()
        .zip(counts)
        .map(|(c, n)| {
            let class = ClassUse {
                id: c.id as u8,
                speed_factor: c.speed_factor,
                power_factor: c.power_factor,
                max_slope_deg: c.max_slope_deg,
                cells: n,
                ..ClassUse::default()
            };
            (c.name.clone(), class)
        })
        .collect();
    Ok(ClassFigures { file: spec.file.clone(), classes, unclassified_cells, ..ClassFigures::default() })
}

/// The class id of every cell of `world` (255 where unclassified), for `classes.tif`.
pub(super) fn layer(world: &World, figures: &ClassFigures) -> Option<Vec<u8>> {
    let ground = world.ground()?;
    let ids: Vec<u8> = ground.classes().iter().map(|c| figures.classes.get(&c.name).map_or(255, |u| u.id)).collect();
    Some((0..world.cells() as u32).map(|c| ground.class_index(c).map_or(255, |i| ids[usize::from(i)])).collect())
}

/// The drive time (s) and the drives' load energy (Wh) on each class of `world`, in the
/// order of its classes, and the time on unclassified cells: each drive `(cell, k,
/// measured)` split between its two cells as its geometry divides its moving time and
/// energy — the duration and load energy `measured` in a run, else the model's (the
/// drive alone, without a wait to the next tick).
pub(super) fn drive_use(
    model: &ActionModel,
    world: &World,
    drives: impl Iterator<Item = (u32, u8, Option<(f64, f64)>)>,
) -> Option<(Vec<(f64, f64)>, f64)> {
    let ground = world.ground()?;
    let mut per = vec![(0.0, 0.0); ground.classes().len()];
    let mut unclassified = 0.0;
    for (cell, k, measured) in drives {
        let Ok(g) = model.drive_geometry(world, cell, k) else { continue };
        let (duration_s, drawn_wh) = measured.unwrap_or((g.duration_s, g.load_w * g.duration_s / 3600.0));
        for (c, time_share, energy_share) in
            [(cell, g.from_time_share, g.from_energy_share), (g.to, 1.0 - g.from_time_share, 1.0 - g.from_energy_share)]
        {
            match ground.class_index(c) {
                Some(i) => {
                    per[usize::from(i)].0 += duration_s * time_share;
                    per[usize::from(i)].1 += drawn_wh * energy_share;
                }
                None => unclassified += duration_s * time_share,
            }
        }
    }
    Some((per, unclassified))
}
