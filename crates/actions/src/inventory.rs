//! The action-module inventory (Table 1) and the filters that remove modules a task
//! cannot need, shrinking the design space D = N^m (eq. 1).

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

/// Why the task cannot need `m`, if it cannot.
fn filter_reason(task: &Task, m: Module) -> Option<&'static str> {
    let sampling = task.samples_wanted > 0;
    match m {
        Module::Grasp | Module::Release | Module::TurnToSample | Module::TurnFromSample if !sampling => {
            Some("no samples wanted: nothing to grasp, release or turn to")
        }
        Module::TrayDeploy | Module::TrayRetract if !sampling => {
            Some("no samples wanted: the science tray stays stowed")
        }
        _ if is_arm(m) && !task.manipulation => {
            Some("no manipulation: the arm stays stowed (sample modules bring the tool down themselves)")
        }
        Module::Communicate if !task.communication => Some("no communication required"),
        Module::VideoStart | Module::VideoEnd if !task.video => Some("no video required"),
        Module::SweepSensors => Some("sweeping sensors changes neither the rover's place nor the task's state"),
        Module::Sleep => Some("sleeping only passes time"),
        Module::Recharge if !task.recharge => Some("the battery covers the task: no recharging needed"),
        _ => None,
    }
}

impl Inventory {
    /// All 26 modules of Table 1.
    pub fn full() -> Inventory {
        Inventory { modules: Module::ALL.to_vec(), removed: Vec::new() }
    }

    /// The modules `task` can need, with every removal and its reason, then the
    /// scenario's overrides.
    pub fn for_task(task: &Task, overrides: &Overrides) -> Inventory {
        let mut modules = Vec::new();
        let mut removed = Vec::new();
        for m in Module::ALL {
            let code = m.code();
            if overrides.force_out.contains(&code) {
                removed.push(Removal { code, reason: "forced out by the scenario".into() });
            } else if overrides.force_in.contains(&code) {
                modules.push(m);
            } else if let Some(reason) = filter_reason(task, m) {
                removed.push(Removal { code, reason: reason.into() });
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
