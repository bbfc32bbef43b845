//! Problems refused before any search: bad settings, no goals, a start or goal off the
//! map or blocked, and goals that slopes or obstacles cut off whatever the time — a
//! proven "unreachable" at the cost of a greedy flood, not a search.

use super::PlannerConfig;
use crate::action_model::{ActionModel, Binding};
use crate::domain::Start;
use crate::error::{Error, Result};
use crate::world::World;

/// Refuses a problem that cannot be planned before any search: bad settings, no goals,
/// a start or goal off the map or blocked, a bad start, goals that slopes or obstacles
/// cut off whatever the time (a proven "unreachable"), energy classes out of range.
pub(super) fn check_problem(
    world: &World,
    model: &ActionModel,
    config: &PlannerConfig,
    start: Start,
    goals: &[u32],
) -> Result<()> {
    config.validate()?;
    if goals.is_empty() {
        return Err(Error::Config { field: "goals", message: "at least one goal is needed".into() });
    }
    for (field, cell) in std::iter::once(("start", start.cell)).chain(goals.iter().map(|&g| ("goals", g))) {
        if cell as usize >= world.cells() || !world.passable(cell) {
            return Err(Error::Config {
                field,
                message: format!("cell {cell} is off the map, on missing data or blocked"),
            });
        }
    }
    if !(start.energy_wh >= 0.0 && start.t_min >= 0.0 && start.t_max >= start.t_min) {
        return Err(Error::Config {
            field: "start",
            message: "start energy must be ≥ 0 and the start window a non-empty interval from t ≥ 0".into(),
        });
    }
    // Time-independent reachability first: a cheap, clear answer when slopes or
    // obstacles cut the goals off.
    let mut at = start.cell;
    for &g in goals {
        if !connected(world, model, at, g, true) {
            let binding = if connected(world, model, at, g, false) { Binding::Slope } else { Binding::Blocked };
            return Err(Error::Unreachable { binding, message: binding.describe().into(), proven: true });
        }
        at = g;
    }
    if let Some(w) = config.resolution.energy_wh {
        let usable = model.capacity_wh();
        if !(1e-3..=usable / 2.0).contains(&w) {
            return Err(Error::Config {
                field: "resolution.energy_wh",
                message: format!(
                    "{w} Wh: allowed 0.001 Wh up to half the usable battery ({:.1} Wh), or none for exact \
                     energy — a wider class would collapse E",
                    usable / 2.0
                ),
            });
        }
    }
    Ok(())
}

/// Whether `to` can be reached from `from` by drives, ignoring time and energy (with or
/// without the slope limit).
fn connected(world: &World, model: &ActionModel, from: u32, to: u32, with_slope: bool) -> bool {
    let relaxed = (!with_slope).then(|| {
        let mut c = model.config().clone();
        c.drive.max_slope = false;
        ActionModel::new(model.rover().clone(), c)
    });
    let model = relaxed.as_ref().unwrap_or(model);
    // Greedy best-first toward the goal: when it is reachable this touches little more
    // than a path's worth of cells (a blind flood would visit the whole map first);
    // only a goal that is cut off costs the flood.
    let (tc, tr) = world.col_row(to);
    let steps_to_goal = |cell: u32| {
        let (c, r) = world.col_row(cell);
        c.abs_diff(tc).max(r.abs_diff(tr))
    };
    let mut seen = vec![false; world.cells()];
    let mut open = std::collections::BinaryHeap::new();
    open.push(std::cmp::Reverse((steps_to_goal(from), from)));
    seen[from as usize] = true;
    while let Some(std::cmp::Reverse((_, c))) = open.pop() {
        if c == to {
            return true;
        }
        for k in 0..8u8 {
            if let Ok(n) = model.drive_geometry(world, c, k).map(|g| g.to)
                && !seen[n as usize]
            {
                seen[n as usize] = true;
                open.push(std::cmp::Reverse((steps_to_goal(n), n)));
            }
        }
    }
    false
}
