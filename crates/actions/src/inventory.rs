//! The action-module inventory (Table 1) and the filters that remove modules a task
//! cannot need, shrinking the design space D = N^m (eq. 1). Task tests (what the task
//! asks for) and physics tests (what the rover's geometry does on the task's map) each
//! give their reason; for the paper's task 1 they leave its nine modules.

use areo_rover::motion::Module;
use serde::{Deserialize, Serialize};

use crate::task::Task;

/// A module removed from the inventory, and why.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Removal {
    /// The module's Table 1 code.
    pub code: u16,
    /// The reason, for reports.
    pub reason: String,
}

/// The modules a plan may use.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Inventory {
    /// Modules, in Table 1 order.
    pub modules: Vec<Module>,
    /// What the filters removed.
    pub removed: Vec<Removal>,
}

/// What the scenario forces in or out, by code.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Overrides {
    /// Keep these even if a filter would remove them.
    pub force_in: Vec<u16>,
    /// Remove these whatever the filters say.
    pub force_out: Vec<u16>,
}

fn is_arm(m: Module) -> bool {
    matches!(
        m,
        Module::ArmForward | Module::ArmBack | Module::ArmLeft | Module::ArmRight | Module::ArmDown | Module::ArmUp
    )
}

/// Where a task is planned: what the physics filters look at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surroundings {
    /// The map's width (east–west) and height (north–south), m.
    pub map_m: (f64, f64),
    /// The rover's track (wheel mid-plane to mid-plane) and wheel width, m.
    pub track_m: f64,
    /// Wheel width, m.
    pub wheel_width_m: f64,
}

impl Surroundings {
    /// `params`'s rover on a map `map_m` (width, height) metres.
    pub fn new(map_m: (f64, f64), params: &areo_rover::RoverParams) -> Surroundings {
        Surroundings { map_m, track_m: params.track_m, wheel_width_m: params.wheel_width_m }
    }

    /// The width a U-turn on the tightest arc (105/107, 0.5 m radius) sweeps, m: the
    /// outer wheel's circle.
    fn u_turn_m(&self) -> f64 {
        2.0 * (TIGHT_ARC_M + 0.5 * self.track_m + 0.5 * self.wheel_width_m)
    }
}

/// The tight arcs' radius (105, 107), m.
const TIGHT_ARC_M: f64 = 0.5;

/// Why the task cannot need `m`, if it cannot.
fn filter_reason(task: &Task, room: &Surroundings, m: Module) -> Option<String> {
    let sampling = task.samples_wanted > 0;
    let (dx, dy) = (task.target.0 - task.start.0, task.target.1 - task.start.1);
    let heading = task.start.2.to_radians();
    // The target's bearing off the start heading: ahead when within ±90°.
    let ahead = dx * heading.sin() + dy * heading.cos() > 0.0;
    Some(match m {
        Module::Grasp | Module::Release | Module::TurnToSample | Module::TurnFromSample if !sampling => {
            "no samples wanted: nothing to grasp, release or turn to".into()
        }
        Module::TrayDeploy | Module::TrayRetract if !task.tray => {
            "no in-situ measurement: samples are grasped and carried, the science tray stays stowed".into()
        }
        Module::TurnLeft | Module::TurnRight if room.map_m.0.min(room.map_m.1) >= room.u_turn_m() => format!(
            "the tight arcs turn the rover through any heading while moving: a U-turn on them sweeps {:.2} m, and the map is {:.2} m across",
            room.u_turn_m(),
            room.map_m.0.min(room.map_m.1)
        ),
        Module::Backward if ahead && room.map_m.0.min(room.map_m.1) >= room.u_turn_m() => {
            "the target lies ahead of the start, and the forward arcs can turn the rover anywhere on the map: backing only lengthens the way".into()
        }
        _ if is_arm(m) && !task.manipulation => {
            "no manipulation: the arm stays stowed (a grasp reaches down to the sample itself)".into()
        }
        Module::Communicate if !task.communication => "no communication required".into(),
        Module::VideoStart | Module::VideoEnd if !task.video => "no video required".into(),
        Module::SweepSensors => "sweeping sensors changes neither the rover's place nor the task's state".into(),
        Module::Sleep => "sleeping only passes time".into(),
        Module::Recharge if !task.recharge => "the battery covers the task: no recharging needed".into(),
        _ => return None,
    })
}

impl Inventory {
    /// All 26 modules of Table 1.
    pub fn full() -> Inventory {
        Inventory { modules: Module::ALL.to_vec(), removed: Vec::new() }
    }

    /// The modules `task` can need where it is planned (`room`), with every removal
    /// and its reason, then the scenario's overrides.
    pub fn for_task(task: &Task, room: &Surroundings, overrides: &Overrides) -> Inventory {
        let mut modules = Vec::new();
        let mut removed = Vec::new();
        for m in Module::ALL {
            let code = m.code();
            if overrides.force_out.contains(&code) {
                removed.push(Removal { code, reason: "forced out by the scenario".into() });
            } else if overrides.force_in.contains(&code) {
                modules.push(m);
            } else if let Some(reason) = filter_reason(task, room, m) {
                removed.push(Removal { code, reason });
            } else {
                modules.push(m);
            }
        }
        Inventory { modules, removed }
    }

    /// Only the listed codes (a scenario's explicit inventory); unknown codes are
    /// returned as the error.
    pub fn from_codes(codes: &[u16]) -> Result<Inventory, u16> {
        let mut modules = Vec::new();
        for &c in codes {
            let m = Module::from_code(c).ok_or(c)?;
            if !modules.contains(&m) {
                modules.push(m);
            }
        }
        modules.sort();
        let removed = Module::ALL
            .iter()
            .filter(|m| !modules.contains(m))
            .map(|m| Removal { code: m.code(), reason: "not in the scenario's inventory".into() })
            .collect();
        Ok(Inventory { modules, removed })
    }

    /// Codes of the modules, in order.
    pub fn codes(&self) -> Vec<u16> {
        self.modules.iter().map(|m| m.code()).collect()
    }
}

/// log10 of the design space D = N^m for N modules and plans of m modules (eq. 1).
pub fn design_space_log10(modules: usize, plan_length: usize) -> f64 {
    plan_length as f64 * (modules.max(1) as f64).log10()
}
