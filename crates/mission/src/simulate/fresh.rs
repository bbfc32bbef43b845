//! `compare_fresh` on a tick: each compared re-plan against a new, independent planner
//! instance — [`Mission::plan`] from the rover's state to the goals ahead, with its own
//! goal windows, bounds and search, nothing kept from the mission that re-planned.
//!
//! The two answer problems that may differ in one way only: the fresh instance's goal
//! windows are made from where the rover now stands, the mission's were fixed at its
//! start. So a difference in cost is classified: where the cheaper plan meets the other
//! problem's windows too, the other search missed a plan it should have found
//! ([`FreshCheck::Differs`], a defect); where it does not, the windows explain it
//! ([`FreshCheck::Windows`]). A plan's arrival is checked against a window widened by
//! one tick (a goal is marked at the waypoint after its settle): that leans toward
//! calling a difference a defect, never toward hiding one.

use serde::{Deserialize, Serialize};

use crate::action_model::ActionModel;
use crate::domain::Start;
use crate::error::{Error, Result};
use crate::plan::MissionPlan;
use crate::planner::{Mission, PlannerConfig, SearchMode};
use crate::world::World;

/// How a re-plan compares with an independent planner instance from the rover's state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum FreshCheck {
    /// Equal costs (to a part in 10⁹), or neither found a plan.
    Equal,
    /// Costs differ, and the cheaper plan misses a goal window of the other problem:
    /// the windows (fixed at the mission's start, or made from the rover's state)
    /// explain it.
    Windows,
    /// Costs differ where the other problem admits the cheaper plan: a search lost its
    /// optimum.
    Differs,
}

/// The independent instance's plan — its expansions and cost, `None` where no plan
/// exists — and how the re-plan compares with it.
pub type FreshPlan = (Option<(u64, f64)>, FreshCheck);

/// The problem a re-plan answered: the map it planned on, the rover's actions and the
/// planner's settings.
pub type PlannedOn<'p> = (&'p World, &'p ActionModel, &'p PlannerConfig);

impl FreshCheck {
    /// Plans the problem `mission` re-planned — from `here` to the `remaining` goals on
    /// `believed` — with a new planner instance, and compares `replanned` (the
    /// mission's plan) with it: the instance's plan (expansions and cost, `None`: none
    /// exists) and the check. `None` where the fresh search stopped at its budget
    /// undecided, or the mission is not on a tick.
    pub fn of(
        mission: &Mission<'_>,
        replanned: &MissionPlan,
        problem: PlannedOn<'_>,
        here: Start,
        remaining: &[u32],
    ) -> Result<Option<FreshPlan>> {
        independent(mission, replanned, problem, here, remaining)
    }
}

fn independent(
    mission: &Mission<'_>,
    replanned: &MissionPlan,
    (believed, model, config): PlannedOn<'_>,
    here: Start,
    remaining: &[u32],
) -> Result<Option<FreshPlan>> {
    let SearchMode::Exact { tick_s } = config.search else { return Ok(None) };
    // The mission's searches stay alive beside the fresh one.
    let held = mission.search_bytes();
    let config =
        PlannerConfig { max_search_bytes: config.max_search_bytes.map(|m| m.saturating_sub(held)), ..config.clone() };
    let kept = mission.goal_windows();
    let kept = &kept[kept.len().saturating_sub(remaining.len())..];
    let fresh_windows = Mission::tick_windows_from(believed, model, &config, tick_s, here, remaining);
    let fresh = match Mission::plan(believed, model, config, here, remaining) {
        Ok((_, plan)) => Some(plan),
        Err(Error::Unreachable { proven: true, .. }) => None,
        Err(Error::Unreachable { proven: false, .. }) => return Ok(None),
        Err(e) => return Err(e),
    };
    let meets = |plan: &MissionPlan, windows: &[(f64, f64)]| {
        let arrivals: Vec<f64> = plan.waypoints.iter().filter(|w| w.goal.is_some()).map(|w| w.t_s).collect();
        arrivals.len() == windows.len()
            && arrivals.iter().zip(windows).all(|(&t, &(open, close))| t >= open - tick_s && t <= close + tick_s)
    };
    let equal = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0);
    let check = match &fresh {
        Some(f) if equal(f.cost, replanned.cost) => FreshCheck::Equal,
        Some(f) if f.cost < replanned.cost => {
            if meets(f, kept) {
                FreshCheck::Differs
            } else {
                FreshCheck::Windows
            }
        }
        _ => {
            if meets(replanned, &fresh_windows) {
                FreshCheck::Differs
            } else {
                FreshCheck::Windows
            }
        }
    };
    Ok(Some((fresh.map(|f| (f.expansions, f.cost)), check)))
}
