//! Terrain classes: the job's class map read onto the map's grid (nearest neighbour,
//! [`overlay`]), every id it holds where it covers the map checked against the listed
//! classes, and the classes given to the worlds the rover plans on and drives on; then
//! how much of the plan's and the run's driving each class takes.

use std::collections::BTreeMap;
use std::sync::Arc;

use areo_mission::{ClassMap, TerrainClass, UNCLASSIFIED};

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
    let bad = |message: String| scenario_error(file, field.to_string(), message);
    // A class id is a whole number: a value such as 2.000000001 is refused where it
    // lies, not rounded to a class.
    if let Some(cell) = samples.iter().position(|s| matches!(s, Sample::Value(v) if v.fract() != 0.0)) {
        let Sample::Value(v) = samples[cell] else { unreachable!("found as a value") };
        let (col, row) = world.col_row(cell as u32);
        let (x, y) = frame.to_local(world.center(cell as u32));
        return Err(bad(format!(
            "{}: {v} under the map cell at ({x:.1}, {y:.1}) m (column {col}, row {row} of the map) is not a whole \
             number: class ids are integers",
            spec.file
        )));
    }
    let cells = class_cells(spec, &samples).map_err(bad)?;
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
    let ground = Arc::new(ClassMap::new(classes, cells).map_err(|e| bad(e.to_string()))?);
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

/// Each map cell's class index (its position in the job's list; [`UNCLASSIFIED`] where
/// the class map does not reach), or why the class map cannot be used: a hole where it
/// covers the map, or values that are no listed id.
fn class_cells(spec: &TerrainClassesSpec, samples: &[Sample]) -> std::result::Result<Vec<u8>, String> {
    let index: BTreeMap<i64, u8> = spec.classes.iter().enumerate().map(|(i, c)| (c.id, i as u8)).collect();
    let allowed = || spec.classes.iter().map(|c| c.id.to_string()).collect::<Vec<_>>().join(", ");
    let mut cells = Vec::with_capacity(samples.len());
    let mut unknown: BTreeMap<String, usize> = BTreeMap::new();
    let mut holes = 0usize;
    for s in samples {
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
        return Err(format!(
            "{}: {holes} cells of the map fall on cells of the class map with no value (NaN or its no-data): give every cell it covers a class id ({})",
            spec.file,
            allowed()
        ));
    }
    if !unknown.is_empty() {
        let listed: Vec<String> = unknown.iter().take(8).map(|(v, n)| format!("{v} ({n} cells)")).collect();
        return Err(format!(
            "{}: values that are no listed class id under the map: {}{}; the classes list ids {}",
            spec.file,
            listed.join(", "),
            if unknown.len() > 8 { format!(" and {} more", unknown.len() - 8) } else { String::new() },
            allowed()
        ));
    }
    Ok(cells)
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

/// The job's terrain classes given to the worlds, if it has them, timed.
pub(super) fn on(
    job: &TempestJob,
    file: &ScenarioFile,
    world: &mut World,
    truth: Option<&mut World>,
    frame: Frame,
) -> Result<Option<crate::report::tempest::ClassFigures>> {
    let Some(spec) = &job.terrain_classes else { return Ok(None) };
    let clock = Instant::now();
    let mut figures = classes::apply(spec, file, world, truth, frame)?;
    figures.prepare_s = clock.elapsed().as_secs_f64();
    Ok(Some(figures))
}

/// The no-go mask's and the terrain classes' layers, and the classes' figures.
pub(super) fn ground_layers(r: &mut TempestReport, ctx: &Context<'_>, computed: &Computed) {
    let world = ctx.world;
    if let (Some(l), Some(n)) = (r.layers.as_mut(), &computed.prepared.no_go) {
        l.no_go = Some(crate::report::Raster { cols: world.cols(), rows: world.rows(), values: n.codes.clone() });
    }
    r.terrain_classes = computed.prepared.classes.as_ref().map(|c| figures(ctx, computed, c.clone()));
    if let (Some(l), Some(c)) = (r.layers.as_mut(), &r.terrain_classes) {
        let values = layer(world, c);
        l.classes = values.map(|values| crate::report::Raster { cols: world.cols(), rows: world.rows(), values });
    }
}

/// The terrain classes' figures with the drive time and energy the initial plan and
/// the simulated run spend on each.
fn figures(
    ctx: &Context<'_>,
    computed: &Computed,
    mut figures: crate::report::tempest::ClassFigures,
) -> crate::report::tempest::ClassFigures {
    let plan = match &computed.run {
        Run::Plan { plan, .. } => Some(plan),
        Run::Simulated(sim) => sim.plans.first().map(|p| &p.plan),
        _ => None,
    };
    let names: Vec<String> =
        ctx.world.ground().map(|g| g.classes().iter().map(|c| c.name.clone()).collect()).unwrap_or_default();
    if let Some(plan) = plan {
        let drives = plan.waypoints.iter().filter_map(|w| match w.action {
            Some(Action::Drive(k)) => Some((w.cell, k, None)),
            _ => None,
        });
        if let Some((per, unclassified)) = drive_use(ctx.model, ctx.world, drives) {
            for (name, (t, e)) in names.iter().zip(per) {
                if let Some(u) = figures.classes.get_mut(name) {
                    (u.plan_drive_time_s, u.plan_drive_energy_wh) = (t, e);
                }
            }
            figures.unclassified_plan_drive_time_s = unclassified;
        }
    }
    if let Run::Simulated(sim) = &computed.run {
        let drives = sim.steps.iter().filter_map(|s| match s.action {
            Action::Drive(k) => Some((s.cell, k, Some((s.duration_s, s.load_wh)))),
            _ => None,
        });
        let nominal = ctx.model.nominal();
        if let Some((per, _)) = drive_use(&nominal, ctx.truth, drives) {
            for (name, (t, e)) in names.iter().zip(per) {
                if let Some(u) = figures.classes.get_mut(name) {
                    (u.run_drive_time_s, u.run_drive_energy_wh) = (Some(t), Some(e));
                }
            }
        }
    }
    figures
}
