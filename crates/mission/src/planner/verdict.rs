//! Why a mission has no plan: the searches that relax one constraint at a time (or all
//! at once, or open the goal windows) on the problem the mission searched, and the
//! verdict that names the constraint that binds.

use super::Mission;
use super::work::phase_of;
use crate::action_model::{ActionConfig, ActionModel, Binding};
use crate::domain::SharedGeometry;
use crate::error::Error;
use crate::planner::PlannerConfig;

impl Mission<'_> {
    /// Why no plan exists. All constraints that can bind are relaxed at once first
    /// (battery, darkness, shadow, Sun in camera, Communicate sessions — those this
    /// rover and these actions have): no plan then means time binds
    /// ([`Binding::Horizon`]) and nothing more is searched. Otherwise the first of them
    /// that makes a plan relaxed alone is named; none alone means they bind together
    /// ([`Binding::Together`], its message naming the ones relaxed).
    pub(super) fn explain_unreachable(&self) -> Error {
        let error = self.relax_to_explain();
        self.config.meter.set_phase(0);
        error
    }

    fn relax_to_explain(&self) -> Error {
        let base = self.model.config().clone();
        let rules = [&base.drive, &base.charge, &base.hibernate];
        let dark = rules.iter().any(|r| r.daylight);
        let shade = rules.iter().any(|r| r.direct_sun);
        // Without cameras the rule reads nothing: relaxing it cannot change a search.
        let camera = base.drive.sun_in_camera && !self.model.rover().cameras.is_empty();
        let sessions = !self.model.sessions().is_empty();
        let mut all = base.clone();
        for r in [&mut all.drive, &mut all.charge, &mut all.hibernate] {
            (r.daylight, r.direct_sun) = (false, false);
        }
        all.drive.sun_in_camera = false;
        // Whether the goal windows close before the planning horizon: waiting longer
        // than `max_wait_s` may then be what a plan needs.
        let windows = self.kept_windows();
        let capped = windows.iter().any(|w| w.1 < self.world.span_s() - 1e-6);
        if !self.probe_plans(None, all.clone(), true, false) {
            return self.time_binds(all, &windows, capped);
        }
        // (binding, action constraints, unlimited battery, keep the sessions), each
        // relaxing one constraint; shadow with darkness, as direct sun implies daylight.
        let singles = self.single_relaxations(&base, dark, shade, camera, sessions);
        for (binding, actions, big_battery, sessions) in singles {
            let found = self.probe_plans(Some(binding), actions, big_battery, sessions);
            if let Some(e) = self.probes_stopped() {
                return e;
            }
            if found {
                // The goal windows may bind as well; opening them is a search over a
                // longer span (at valley-detour's step-77 state more than all the
                // others together), so it is named as a possibility, not searched.
                let mut message = binding.describe().to_string();
                if capped {
                    message.push_str(&format!(
                        "; the goal windows close before the planning horizon ({}): a longer wait may also make a \
                         plan (not searched)",
                        self.window_limits()
                    ));
                }
                return self.unreachable(binding, &message);
            }
        }
        // No one constraint alone: the goal windows, opened alone, before calling it
        // constraints together.
        if capped {
            let open = self.probe_window_open(base, false, true);
            if let Some(e) = self.probes_stopped() {
                return e;
            }
            if open {
                return self.unreachable(Binding::GoalWindow, &self.window_message());
            }
        }
        let names = [(true, "battery"), (dark, "darkness"), (shade, "shadow"), (camera, "the Sun in the cameras")];
        let mut relaxed: Vec<&str> = names.iter().filter(|n| n.0).map(|n| n.1).collect();
        if sessions {
            relaxed.push("sessions");
        }
        let message = format!(
            "several constraints together ({}: none relaxed alone makes a plan, all relaxed at once do)",
            relaxed.join(", ")
        );
        self.unreachable(Binding::Together, &message)
    }

    /// The verdict when every constraint relaxed at once finds no plan: only time is left
    /// — a goal window that closes before the horizon (`GoalWindow`, if opening it plans),
    /// else the planning horizon (proven where the last window opens past it).
    fn time_binds(&self, all: ActionConfig, windows: &[(f64, f64)], capped: bool) -> Error {
        if let Some(e) = self.probes_stopped() {
            return e;
        }
        let proven = windows.last().is_some_and(|w| w.0 >= self.world.span_s());
        if proven && self.tick.is_none() {
            let message = Binding::Horizon.describe().into();
            return Error::Unreachable { binding: Binding::Horizon, message, proven };
        }
        if capped {
            let open = self.probe_window_open(all, true, false);
            if let Some(e) = self.probes_stopped() {
                return e;
            }
            if open {
                return self.unreachable(Binding::GoalWindow, &self.window_message());
            }
        }
        // Start and goals are connected (checked before any search) and nothing
        // relaxed made a plan: only time is left — the horizon, the goal instants,
        // the waits.
        self.unreachable(Binding::Horizon, Binding::Horizon.describe())
    }

    /// The verdict when a probe was stopped: on a tick, where the search proved that no
    /// plan exists, the proof with the binding constraint undetermined; otherwise the
    /// budget's own error.
    fn probes_stopped(&self) -> Option<Error> {
        if self.tick.is_none() {
            return self.allowance.check().err();
        }
        let why = match (self.allowance.probes_out(), self.allowance.check()) {
            (Some(share), _) => format!("their share of the work, {share} expansions"),
            (None, Err(e)) => format!("the call's budget ({e})"),
            (None, Ok(())) => return None,
        };
        let message = format!(
            "no plan exists; the binding constraint was not determined: the searches that relax one constraint \
             at a time ran out of {why}"
        );
        Some(self.unreachable(Binding::Undetermined, &message))
    }

    /// The single relaxations to probe, in order: (binding, action constraints, unlimited
    /// battery, keep the sessions), each relaxing one constraint the mission has; shadow
    /// with darkness, as direct sun implies daylight.
    fn single_relaxations(
        &self,
        base: &ActionConfig,
        dark: bool,
        shade: bool,
        camera: bool,
        sessions: bool,
    ) -> Vec<(Binding, ActionConfig, bool, bool)> {
        let mut singles: Vec<(Binding, ActionConfig, bool, bool)> = vec![(Binding::Battery, base.clone(), true, true)];
        let mut c = base.clone();
        for r in [&mut c.drive, &mut c.charge, &mut c.hibernate] {
            r.daylight = false;
        }
        if dark {
            singles.push((Binding::Darkness, c.clone(), false, true));
        }
        for r in [&mut c.drive, &mut c.charge, &mut c.hibernate] {
            r.direct_sun = false;
        }
        if shade {
            singles.push((Binding::Shadow, c, false, true));
        }
        if camera {
            let mut cam = base.clone();
            cam.drive.sun_in_camera = false;
            singles.push((Binding::SunInCamera, cam, false, true));
        }
        if sessions {
            singles.push((Binding::Communicate, base.clone(), false, false));
        }
        singles
    }

    /// The message naming the goal windows as binding, with the settings that set them.
    fn window_message(&self) -> String {
        format!(
            "the goal windows: no plan arrives within them ({}); with the windows open to the planning horizon \
             ({:.0} s) a plan is found — raise `max_wait_s`",
            self.window_limits(),
            self.world.span_s()
        )
    }

    /// Where the last goal window closes and the settings that put it there.
    fn window_limits(&self) -> String {
        let max_wait_s = self.config.max_wait_s.unwrap_or_else(|| self.world.body().solar_day_s().round());
        let close = self.kept_windows().last().map_or(0.0, |w| w.1);
        format!(
            "the last goal by {close:.0} s: the slowest travel × `detour_factor` {} plus `max_wait_s` {max_wait_s:.0} s",
            self.config.detour_factor
        )
    }

    /// [`Mission::probe_plans`] with the goal windows open to the planning horizon.
    fn probe_window_open(&self, actions: ActionConfig, big_battery: bool, sessions: bool) -> bool {
        let config = PlannerConfig { max_wait_s: Some(self.world.span_s()), ..self.config.clone() };
        self.probe_with(Some(Binding::GoalWindow), actions, big_battery, sessions, Some(config))
    }

    /// Whether this mission finds a plan with `actions` for constraints, the battery
    /// unlimited if `big_battery`, the Communicate sessions kept if `sessions`: the
    /// probe of [`Mission::explain_unreachable`] relaxing `binding` (`None`: all).
    fn probe_plans(&self, binding: Option<Binding>, actions: ActionConfig, big_battery: bool, sessions: bool) -> bool {
        self.probe_with(binding, actions, big_battery, sessions, None)
    }

    /// [`Mission::probe_plans`]: on the kept problem (its goal instants and start
    /// intervals, [`Mission::kept_problem`]) — a re-plan's probe must relax one
    /// constraint of the problem the re-plan searched, not search goal windows made anew
    /// from the rover's new start — or, with `windows`, on the goal windows those planner
    /// settings make.
    fn probe_with(
        &self,
        binding: Option<Binding>,
        actions: ActionConfig,
        big_battery: bool,
        sessions: bool,
        windows: Option<PlannerConfig>,
    ) -> bool {
        self.config.meter.set_phase(phase_of(binding));
        let mut rover = self.model.rover().clone();
        let mut start = self.start;
        if big_battery {
            rover.battery.capacity_wh *= 1e6;
            start.energy_wh = rover.battery.capacity_wh;
        }
        let mut model = ActionModel::new(rover, actions);
        if sessions {
            model = model.with_sessions(self.model.sessions().to_vec()).sessions_need_earth(self.model.needs_earth());
        }
        if self.tick.is_some() {
            // The same exact search on the relaxed rover, over the kept windows or the
            // windows opened to the planning horizon.
            let mut query = self.tick_query(&model, start);
            if windows.is_some() {
                for g in &mut query.goals {
                    g.close_s = self.world.span_s();
                }
            }
            return self
                .allowance
                .beside(self.search_bytes(), || self.tick_solve(&query))
                .is_ok_and(|o| o.plan.is_some());
        }
        // The same settings as the plan: a coarser probe could lose the very plan the
        // relaxation makes possible, and name the wrong constraint.
        let rebuild = windows.is_some();
        let mut probe = Mission {
            world: self.world,
            model: &model,
            config: windows.unwrap_or_else(|| self.config.clone()),
            start,
            goals: self.goals.clone(),
            segments: Vec::new(),
            // Another action model: its own drive geometries.
            geometry: SharedGeometry::default(),
            last_resort: self.last_resort,
            given_t_max: self.given_t_max,
            widened_for_s: self.widened_for_s,
            allowance: self.allowance.clone(),
            classes: self.classes,
            tick: None,
        };
        if rebuild || self.segments.is_empty() {
            probe.build_segments();
        } else {
            for (from, to, mut seg_start, goals, intervals, arriving) in self.kept_problem() {
                if big_battery {
                    seg_start.energy_wh = if arriving { model.capacity_wh() } else { start.energy_wh };
                }
                let seg = probe.new_segment(from, to, seg_start, goals, intervals, arriving);
                probe.segments.push(seg);
            }
        }
        self.allowance.beside(self.search_bytes(), || probe.solve_from(Some(probe.segments.len() - 1), &[], false));
        !probe.segments[0].candidates.is_empty()
    }

    /// "Unreachable" for `binding` after this mission's searches found no plan: proven
    /// when they were exact at the quanta (the last resort), otherwise said to be a
    /// verdict at these classes only.
    fn unreachable(&self, binding: Binding, description: &str) -> Error {
        if self.tick.is_some() {
            let message = format!("{description}; {}", self.tick_proof());
            return Error::Unreachable { binding, message, proven: true };
        }
        let proven = self.last_resort;
        let mut message = description.to_string();
        if !proven {
            let q = self.model.config().time_quantum_s;
            let why = if q == 0.0 {
                "the actions' times are continuous (`time_quantum_s: 0`), so no search is exact"
            } else if q < 1.0 {
                "quanta under 1 s are not searched exactly"
            } else {
                "the search exact at the quanta was not run"
            };
            // What may still find one: more goal instants are not a superset of fewer
            // (even sets are not nested), so "finer" alone would mislead.
            let halved = (self.widened_for_s / self.classes.resolution.time_s).log2().round() as u32;
            let retried = match halved {
                0 => String::new(),
                n => format!(" (the configured {} s halved {n} time(s): `unreachable_retries`)", self.widened_for_s),
            };
            message.push_str(&format!(
                " (not a proof: searched at time classes of {} s{retried}, which merge instants, and {why}; other \
                 settings may find a plan: finer `time_s`, another `goal_times` (sets of goal instants are not \
                 nested), or quantised actions (`time_quantum_s` ≥ 1), whose last resort is exact)",
                self.classes.resolution.time_s
            ));
        }
        Error::Unreachable { binding, message, proven }
    }
}
