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
        if !connected(world, model, at, g) {
            return Err(ground_binds(world, model, at, g));
        }
        at = g;
    }
    if let crate::planner::SearchMode::Approximate(classes) = &config.search
        && let Some(w) = classes.resolution.energy_wh
    {
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

/// Why drives cannot join `from` to `to`: the one limit on the ground (slope, roll,
/// pitch) whose relaxing alone joins them, the slope when only relaxing several does
/// (the message says so), or blocked ground when nothing does.
fn ground_binds(world: &World, model: &ActionModel, from: u32, to: u32) -> Error {
    let relaxed = |slope: bool, roll: bool, pitch: bool| {
        let (mut rover, mut config) = (model.rover().clone(), model.config().clone());
        config.drive.max_slope &= !slope;
        if roll {
            rover.locomotor.max_roll_deg = None;
        }
        if pitch {
            (rover.locomotor.max_pitch_up_deg, rover.locomotor.max_pitch_down_deg) = (None, None);
        }
        ActionModel::new(rover, config)
    };
    let unreachable =
        |binding: Binding, message: &str| Error::Unreachable { binding, message: message.into(), proven: true };
    if !connected(world, &relaxed(true, true, true), from, to) {
        return unreachable(Binding::Blocked, Binding::Blocked.describe());
    }
    for (binding, slope, roll, pitch) in [
        (Binding::Slope, true, false, false),
        (Binding::Roll, false, true, false),
        (Binding::Pitch, false, false, true),
    ] {
        if connected(world, &relaxed(slope, roll, pitch), from, to) {
            return unreachable(binding, binding.describe());
        }
    }
    unreachable(
        Binding::Slope,
        "the slope, roll and pitch limits together (none relaxed alone joins start and goal; all relaxed do)",
    )
}

/// Whether `to` can be reached from `from` by drives, ignoring time and energy.
fn connected(world: &World, model: &ActionModel, from: u32, to: u32) -> bool {
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
