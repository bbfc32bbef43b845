//! The Wait action: the rover stays where it is for any duration, charging where its
//! array sees the Sun and that gains more than sleeping, hibernating where it does not,
//! and talking to the Earth where a scheduled session asks.
//!
//! The bus load's net power is one function of time at each cell, the same for every
//! wait: its values at the Sun table's instants (k × `sun_step_s` after the epoch),
//! interpolated linearly between them, with the radio's load added over the sessions.
//! A wait integrates that function over its span, so a wait split anywhere is the same
//! as the whole: two waits back to back compose ([`Effect::then`]) into exactly one wait
//! of their sum — which is what lets the planner chain short waits into a wait of any
//! length in whole steps, and what the test `two_waits_back_to_back_are_one_wait`
//! checks. The battery's path inside the wait (its lowest and its fullest instants) is
//! kept in the [`Effect`] like any action's, so a wait across sunset that empties the
//! battery before the end is refused even if the Sun would refill it later.

use areo_rover::resources::Load;

use super::{ActionModel, Binding, EPOCH_SLACK_S, Perturbation};
use crate::effect::{Drawn, Effect};
use crate::world::World;

/// The net power (W, positive drains) and the loads' power (W) of a waiting rover at
/// one Sun-table instant, outside and inside a session.
#[derive(Debug, Clone, Copy)]
struct Node {
    outside: (f64, f64),
    inside: (f64, f64),
}

impl ActionModel {
    /// The planner's wait step, s: `Some` when the rover waits rather than charging and
    /// hibernating for the paper's fixed durations (see [`super::ActionConfig::wait_step_s`]).
    pub fn wait_step_s(&self) -> Option<f64> {
        self.config.wait_step_s.map(|w| self.quantise_time(w))
    }

    /// The stationary actions the planner uses: a Wait of one step, or the paper's
    /// Charge and Hibernate.
    pub fn stays(&self) -> &'static [super::Action] {
        use super::Action;
        if self.config.wait_step_s.is_some() { &[Action::Wait] } else { &[Action::Charge, Action::Hibernate] }
    }

    /// A stationary action's share of L, steps: one for the paper's Charge and
    /// Hibernate; for a wait its duration over the paper's Hibernate, so that a wait
    /// as long as a Hibernate counts as one, and a wait split in two counts what the
    /// whole does.
    pub fn stay_units(&self, action: super::Action) -> f64 {
        match action {
            super::Action::Wait => self.stay_duration_s(action) / self.config.hibernate_s,
            _ => 1.0,
        }
    }

    /// How the rover idles at `cell` from `t0` for `duration_s` s before a plan's start,
    /// where it waits ([`super::ActionConfig::wait_step_s`]): a wait, so that it charges
    /// where its array sees the Sun. `None` with the paper's stays, or where no wait is
    /// possible: it then sleeps with the array off-line ([`ActionModel::idle_wh`]).
    pub fn idle_wait(&self, world: &World, cell: u32, t0: f64, duration_s: f64) -> Option<Effect> {
        self.config.wait_step_s?;
        self.wait(world, cell, t0, duration_s.max(0.0)).ok()
    }

    /// The rover waits at `cell` from `t0` for `duration_s` (s after the epoch; any
    /// duration ≥ 0): its effect, or the constraint that forbids it (the horizon, an
    /// impassable cell, the Earth out of view during a session that needs it, or a
    /// Hibernate constraint of the scenario's).
    pub fn wait(&self, world: &World, cell: u32, t0: f64, duration_s: f64) -> Result<Effect, Binding> {
        self.execute_wait(world, cell, t0, duration_s, Perturbation::NONE)
    }

    /// [`ActionModel::wait`] as it happens: the array's output and the loads departing
    /// from the model by `p`. A wait is not commanded, so it has no delay (`p.delay_s`
    /// is not applied).
    pub fn execute_wait(
        &self,
        world: &World,
        cell: u32,
        t0: f64,
        duration_s: f64,
        p: Perturbation,
    ) -> Result<Effect, Binding> {
        let t1 = t0 + duration_s;
        if t0 < -EPOCH_SLACK_S || t1 > world.span_s() || !(duration_s >= 0.0) {
            return Err(Binding::Horizon);
        }
        if !world.passable(cell) {
            return Err(Binding::Blocked);
        }
        self.earth_in_view(world, cell, t0, t1)?;
        let step = world.sun_step_s();
        let mut drawn = Drawn::default();
        let mut load_wh = 0.0;
        // The pieces between consecutive breakpoints: Sun-table instants and session
        // edges inside the wait, and its ends.
        let mut k = (t0.max(0.0) / step).floor() as i64;
        let mut nodes = (self.wait_node(world, cell, k as f64 * step, p)?, None);
        let mut a = t0;
        while a < t1 {
            let node_end = (k + 1) as f64 * step;
            let session_edge =
                self.sessions.iter().flat_map(|&(s, e)| [s, e]).filter(|&x| x > a).fold(f64::INFINITY, f64::min);
            let b = t1.min(node_end).min(session_edge);
            let next = match nodes.1 {
                Some(n) => n,
                None => {
                    let n = self.wait_node(world, cell, node_end, p)?;
                    nodes.1 = Some(n);
                    n
                }
            };
            let inside = self.in_session(0.5 * (a + b));
            let pick = |n: Node| if inside { n.inside } else { n.outside };
            let (lo, hi) = (pick(nodes.0), pick(next));
            let at = |t: f64| {
                let f = ((t - k as f64 * step) / step).clamp(0.0, 1.0);
                (lo.0 + (hi.0 - lo.0) * f, lo.1 + (hi.1 - lo.1) * f)
            };
            let ((net_a, load_a), (net_b, load_b)) = (at(a), at(b));
            self.linear_segment(&mut drawn, net_a, net_b, b - a);
            load_wh += 0.5 * (load_a + load_b) * (b - a) / 3600.0;
            a = b;
            if b >= node_end {
                k += 1;
                nodes = (next, None);
            }
        }
        Ok(self.effect(&drawn, duration_s, load_wh))
    }

    /// The waiting rover's net and load power at instant `t`: whichever of charging
    /// (the charge load against the array facing the Sun, where the Charge constraints
    /// allow it) and sleeping (the low load, the array off-line) drains less; inside a
    /// session the electronics run at least at the high load (the radio).
    fn wait_node(&self, world: &World, cell: u32, t: f64, p: Perturbation) -> Result<Node, Binding> {
        let sun = world.sun(t.min(world.span_s()));
        let draw = self.margins.draw_factor * p.draw_factor;
        let nuclear = self.rover.nuclear_w;
        let power = |load: Load| self.rover.electronics.power_w(load) * draw;
        let radio = power(Load::High);
        let sleep = {
            self.check(world, &self.config.hibernate, cell, &sun, None)?;
            let load = power(Load::Low);
            ((load - nuclear, load), (load.max(radio) - nuclear, load.max(radio)))
        };
        let charge = self.check(world, &self.config.charge, cell, &sun, None).ok().map(|()| {
            let source = nuclear + p.solar_factor * (self.source_w(world, cell, &sun, None) - nuclear);
            let load = power(self.config.charge_load.load());
            ((load - source, load), (load.max(radio) - source, load.max(radio)))
        });
        let better = |s: (f64, f64), c: Option<(f64, f64)>| match c {
            Some(c) if c.0 < s.0 => c,
            _ => s,
        };
        Ok(Node { outside: better(sleep.0, charge.map(|c| c.0)), inside: better(sleep.1, charge.map(|c| c.1)) })
    }

    /// Whether the Earth is in view from `cell` during every session's part inside
    /// [t0, t1], where sessions need it: at the part's ends and every ten minutes
    /// between (the Earth moves 0.5°/h at most in the lunar sky).
    pub(super) fn earth_in_view(&self, world: &World, cell: u32, t0: f64, t1: f64) -> Result<(), Binding> {
        if !self.sessions_need_earth {
            return Ok(());
        }
        for &(a, b) in self.sessions.iter().filter(|&&(a, b)| a < t1 && b > t0) {
            let (lo, hi) = (a.max(t0), b.min(t1));
            let n = ((hi - lo) / 600.0).ceil().max(1.0) as usize;
            if (0..=n).any(|k| !world.earth_visible(cell, lo + (hi - lo) * k as f64 / n as f64)) {
                return Err(Binding::EarthHidden);
            }
        }
        Ok(())
    }

    /// The least battery energy a wait of `duration_s` uses in the dark, Wh: the
    /// lesser of the low and charge loads against the generator alone.
    pub(crate) fn dark_wait_floor_wh(&self, duration_s: f64) -> f64 {
        let e = &self.rover.electronics;
        let load = e.power_w(Load::Low).min(e.power_w(self.config.charge_load.load()));
        self.battery_wh(load - self.rover.nuclear_w, duration_s)
    }
}
