//! What an action does to the rover: its duration, its energy, and the battery's path
//! inside it.
//!
//! An action's battery energy is the sum of its integration segments; the battery can
//! still run out *inside* it (a charge that warms up on the generator alone before the
//! array gives anything, a stay that drains in the night before the Sun rises) or lose
//! what a full battery cannot hold (a stay that charges past the capacity and then
//! drains). [`Effect`] keeps, besides the sum, the three extremes of the cumulative
//! energy drawn that decide both, so that the planner and the simulator check the
//! battery at every integration sample of an action, not only at its ends, and two
//! effects back to back compose exactly into one ([`Effect::then`]).

/// What an action does: its duration, the battery energy it uses (negative when it
/// charges) and the extremes of the battery's path inside it, Wh.
///
/// With C(s) the battery energy drawn from the action's start to an instant s within
/// it (a sum over its integration samples, each through the battery's charge or
/// discharge efficiency):
/// - `energy_wh` = C(end);
/// - `peak_wh` = max C(s) ≥ 0: the charge the battery must hold at the start;
/// - `trailing_wh` = max (C(end) − C(s)) ≥ 0: what a battery filled to its capacity
///   part-way loses before the end;
/// - `deepest_wh` = max over s ≤ s' of (C(s') − C(s)): the deepest drain between any
///   two instants; more than the usable capacity and no charge can carry the action.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Effect {
    /// Duration, s.
    pub duration_s: f64,
    /// Battery energy used, Wh (negative: gained).
    pub energy_wh: f64,
    /// Energy the rover's loads drew, Wh (≥ 0, whatever the sources gave meanwhile):
    /// the "energy used" objective's measure, rounded *up* to the energy quantum so
    /// that a bound from the least load power never exceeds it.
    pub load_wh: f64,
    /// The most battery energy drawn from the start to any instant within, Wh.
    pub peak_wh: f64,
    /// The most drawn from any instant within to the end, Wh.
    pub trailing_wh: f64,
    /// The most drawn between any two instants within, Wh.
    pub deepest_wh: f64,
}

/// Slack for rounding in sums of energies, Wh.
const SLACK_WH: f64 = 1e-9;

impl Effect {
    /// The least charge above the floor the battery needs at the action's start so that
    /// it never goes below the floor inside the action and ends with `after_wh`, Wh —
    /// the backward step of the search: max(E + Δe, peak).
    pub fn required_before(&self, after_wh: f64) -> f64 {
        (after_wh + self.energy_wh).max(self.peak_wh).max(0.0)
    }

    /// Whether a battery of usable `capacity_wh` can carry the action and still hold
    /// `after_wh` at its end: charge gained past the capacity is lost, so what the
    /// action draws after its fullest instant must fit below the capacity.
    pub fn fits(&self, after_wh: f64, capacity_wh: f64) -> bool {
        after_wh + self.trailing_wh <= capacity_wh + SLACK_WH && self.deepest_wh <= capacity_wh + SLACK_WH
    }

    /// The charge above the floor at the action's end, Wh, from `before_wh` (at most
    /// `capacity_wh`) at its start: gains past the capacity are lost.
    pub fn after(&self, before_wh: f64, capacity_wh: f64) -> f64 {
        (before_wh - self.energy_wh).min(capacity_wh - self.trailing_wh)
    }

    /// The lowest charge above the floor inside the action, Wh, from `before_wh` at its
    /// start (negative: the battery ran out inside it).
    pub fn lowest(&self, before_wh: f64, capacity_wh: f64) -> f64 {
        (before_wh - self.peak_wh).min(capacity_wh - self.deepest_wh)
    }

    /// This effect followed at once by `next`: the whole as one action (durations,
    /// energies and loads add; the extremes compose exactly).
    pub fn then(&self, next: &Effect) -> Effect {
        Effect {
            duration_s: self.duration_s + next.duration_s,
            energy_wh: self.energy_wh + next.energy_wh,
            load_wh: self.load_wh + next.load_wh,
            peak_wh: self.peak_wh.max(self.energy_wh + next.peak_wh),
            trailing_wh: next.trailing_wh.max(self.trailing_wh + next.energy_wh),
            deepest_wh: self.deepest_wh.max(next.deepest_wh).max(self.trailing_wh + next.peak_wh),
        }
    }

    /// The effect on a grid of `quantum_wh`: its energy rounded to the nearest quantum
    /// by `round`, the extremes rounded *up* to whole quanta (the battery is asked for
    /// a little more, never less) and raised to stay consistent with the energy — so
    /// that batteries and labels stay on the grid.
    pub(crate) fn quantised(mut self, quantum_wh: f64, round: impl Fn(f64) -> f64) -> Effect {
        let up = |x: f64| (x / quantum_wh - 1e-9).ceil().max(0.0) * quantum_wh;
        let energy_wh = round(self.energy_wh);
        (self.peak_wh, self.trailing_wh, self.deepest_wh) =
            (up(self.peak_wh), up(self.trailing_wh), up(self.deepest_wh));
        self.energy_wh = energy_wh;
        self.peak_wh = self.peak_wh.max(energy_wh);
        self.trailing_wh = self.trailing_wh.max(energy_wh);
        self.deepest_wh = self.deepest_wh.max(self.peak_wh).max(self.trailing_wh);
        self
    }
}

/// The cumulative battery energy drawn over an action's integration segments, and its
/// extremes (see [`Effect`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Drawn {
    total: f64,
    peak: f64,
    trailing: f64,
    deepest: f64,
}

impl Drawn {
    /// One more segment that drew `wh` (negative: gained), evenly.
    pub(crate) fn push(&mut self, wh: f64) {
        self.total += wh;
        self.peak = self.peak.max(self.total);
        self.trailing = (self.trailing + wh).max(0.0);
        self.deepest = self.deepest.max(self.trailing);
    }

    /// The effect of the segments pushed, over `duration_s`, with `load_wh` drawn by the
    /// loads.
    pub(crate) fn effect(&self, duration_s: f64, load_wh: f64) -> Effect {
        Effect {
            duration_s,
            energy_wh: self.total,
            load_wh,
            peak_wh: self.peak,
            trailing_wh: self.trailing,
            deepest_wh: self.deepest,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The extremes by brute force over the cumulative sums of `segments`.
    fn brute(segments: &[f64]) -> (f64, f64, f64, f64) {
        let mut c = vec![0.0];
        for s in segments {
            c.push(c.last().unwrap() + s);
        }
        let n = c.len() - 1;
        let peak = c.iter().copied().fold(f64::MIN, f64::max);
        let trailing = c.iter().map(|x| c[n] - x).fold(f64::MIN, f64::max);
        let mut deepest = f64::MIN;
        for i in 0..=n {
            for j in i..=n {
                deepest = deepest.max(c[j] - c[i]);
            }
        }
        (c[n], peak, trailing, deepest)
    }

    fn of(segments: &[f64]) -> Effect {
        let mut d = Drawn::default();
        for &s in segments {
            d.push(s);
        }
        d.effect(segments.len() as f64, 0.0)
    }

    /// Forward simulation with the cap: the end charge and the lowest charge.
    fn simulate(segments: &[f64], before: f64, capacity: f64) -> (f64, f64) {
        let (mut b, mut lowest) = (before, before);
        for s in segments {
            b = (b - s).min(capacity);
            lowest = lowest.min(b);
        }
        (b, lowest)
    }

    fn cases() -> Vec<Vec<f64>> {
        let mut out = vec![vec![5.0, -20.0, 3.0], vec![-30.0, 50.0], vec![10.0, 10.0], vec![-5.0, -5.0, 40.0, -60.0]];
        // A seeded spread of mixed segments.
        let mut x = 0x2545_f491_u64;
        for n in 1..40 {
            let mut v = Vec::new();
            for _ in 0..(n % 7 + 1) {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                v.push((x % 2001) as f64 / 10.0 - 100.0);
            }
            out.push(v);
        }
        out
    }

    #[test]
    fn extremes_equal_a_brute_force_over_the_cumulative_sums() {
        for segments in cases() {
            let e = of(&segments);
            let (total, peak, trailing, deepest) = brute(&segments);
            for (got, want) in
                [(e.energy_wh, total), (e.peak_wh, peak), (e.trailing_wh, trailing), (e.deepest_wh, deepest)]
            {
                assert!((got - want).abs() < 1e-9, "{segments:?}: {got} against {want}");
            }
        }
    }

    #[test]
    fn after_and_lowest_equal_a_forward_simulation_with_the_cap() {
        let capacity = 120.0;
        for segments in cases() {
            let e = of(&segments);
            for before in [0.0, 10.0, 55.5, 100.0, 120.0] {
                let (end, lowest) = simulate(&segments, before, capacity);
                assert!((e.after(before, capacity) - end).abs() < 1e-9, "{segments:?} from {before}");
                assert!((e.lowest(before, capacity) - lowest).abs() < 1e-9, "{segments:?} from {before}");
            }
        }
    }

    #[test]
    fn the_least_battery_that_carries_the_action_is_required_before() {
        let capacity = 150.0;
        for segments in cases() {
            let e = of(&segments);
            for after in [0.0, 12.0, 80.0] {
                let need = e.required_before(after);
                let carries = |b: f64| {
                    let (end, lowest) = simulate(&segments, b, capacity);
                    lowest >= -1e-9 && end >= after - 1e-9
                };
                // Feasible exactly when it fits; then the required charge carries the
                // action and a hair less does not.
                let feasible = need <= capacity && e.fits(after, capacity);
                assert_eq!(feasible, carries(capacity), "{segments:?} to {after}");
                if feasible {
                    assert!(carries(need), "{segments:?} to {after}: {need} does not carry it");
                    if need > 1e-6 {
                        assert!(!carries(need - 1e-6), "{segments:?} to {after}: {need} is more than needed");
                    }
                }
            }
        }
    }

    #[test]
    fn two_effects_back_to_back_equal_one() {
        let all = cases();
        for pair in all.windows(2) {
            let joined: Vec<f64> = pair[0].iter().chain(&pair[1]).copied().collect();
            let (a, b, whole) = (of(&pair[0]), of(&pair[1]), of(&joined));
            let composed = a.then(&b);
            for (got, want) in [
                (composed.energy_wh, whole.energy_wh),
                (composed.peak_wh, whole.peak_wh),
                (composed.trailing_wh, whole.trailing_wh),
                (composed.deepest_wh, whole.deepest_wh),
                (composed.duration_s, whole.duration_s),
            ] {
                assert!((got - want).abs() < 1e-9, "{pair:?}: {got} against {want}");
            }
        }
    }
}
