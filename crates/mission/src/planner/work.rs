//! The work and memory one planning call may spend ([`Allowance`]), and the count of
//! expansions a watcher reads while the searches run ([`ExpansionMeter`]).

use std::rc::Rc;

use crate::action_model::Binding;
use crate::error::{Error, Result};

/// The work one planning call may still do, in label expansions, shared by the domains
/// of its searches (see [`PlannerConfig::max_expansions`](super::PlannerConfig::max_expansions)): each expansion counts one,
/// and every [`Allowance::COMPARISONS_PER_EXPANSION`] labels a new one was compared with
/// in its dominance group count one more — where the Pareto fronts grow long, that
/// work outgrows the expansions. One mission's searches run one after another, so
/// where a call stops does not depend on threads.
#[derive(Debug, Clone, Default)]
pub(crate) struct Allowance(Rc<AllowanceState>);

#[derive(Debug, Default)]
struct AllowanceState {
    /// Work spent, expansions.
    spent: std::cell::Cell<u64>,
    /// Dominance comparisons not yet counted in `spent`.
    compared: std::cell::Cell<u64>,
    limit: std::cell::Cell<Option<u64>>,
    /// A search was stopped since the call began.
    stopped: std::cell::Cell<bool>,
    /// The search graphs' memory limit, bytes.
    memory: std::cell::Cell<Option<u64>>,
    /// Bytes held by graphs besides the search that runs: the mission's other segments.
    held: std::cell::Cell<u64>,
    /// Bytes held outside the mission that searches: the mission a probe or a fresh
    /// comparison runs beside.
    beside: std::cell::Cell<u64>,
    /// The graphs' bytes when a search was stopped for memory.
    outgrown: std::cell::Cell<Option<u64>>,
    /// While the probes that name a binding constraint run after a proof: the work
    /// spent at which they stop ([`Allowance::share_for_probes`]).
    probe_limit: std::cell::Cell<Option<u64>>,
    /// The share's expansions.
    probe_share: std::cell::Cell<u64>,
    /// A probe was stopped at its share.
    probes_out: std::cell::Cell<bool>,
}

impl Allowance {
    /// Dominance comparisons that cost as long as one expansion: a comparison reads one
    /// label from a list and compares three numbers (about 12 ns where the fronts are
    /// long: devon-island with a moved hill, docs/robustness.md), an expansion evaluates
    /// the Sun, the light and up to ten transitions (1.3–5 µs; `cargo xtask bench
    /// budget`).
    pub(crate) const COMPARISONS_PER_EXPANSION: u64 = 100;

    pub(super) fn new(limit: Option<u64>, memory: Option<u64>) -> Allowance {
        let a = Allowance::default();
        a.0.limit.set(limit);
        a.0.memory.set(memory);
        a
    }

    /// A new planning call: nothing spent, nothing stopped.
    pub(super) fn begin(&self) {
        self.0.spent.set(0);
        self.0.compared.set(0);
        self.0.stopped.set(false);
        self.0.outgrown.set(None);
        self.0.probe_limit.set(None);
        self.0.probes_out.set(false);
    }

    /// From now on in this call, the searches may spend `work` more expansions (within
    /// the call's own limit): the probes that name the binding constraint after a proof
    /// get a bounded share, so that a verdict comes about as fast as the proof.
    pub(super) fn share_for_probes(&self, work: u64) {
        self.0.probe_limit.set(Some(self.0.spent.get().saturating_add(work)));
        self.0.probe_share.set(work);
    }

    /// The share [`Allowance::share_for_probes`] gave: the expansions it allows, if one
    /// was given and a probe ran out of it.
    pub(super) fn probes_out(&self) -> Option<u64> {
        self.0.probes_out.get().then(|| self.0.probe_share.get())
    }

    /// The graphs besides the next search hold `bytes` (with what is held beside the
    /// mission).
    pub(super) fn hold(&self, bytes: u64) {
        self.0.held.set(bytes + self.0.beside.get());
    }

    /// Runs `f` with `bytes` more held beside the mission (a probe or a fresh search
    /// next to the mission holding them).
    pub(super) fn beside<T>(&self, bytes: u64, f: impl FnOnce() -> T) -> T {
        let before = self.0.beside.get();
        self.0.beside.set(before + bytes);
        let out = f();
        self.0.beside.set(before);
        out
    }

    /// Whether a search whose graph and caches hold `bytes` takes the graphs past the
    /// memory limit (the search asking stops).
    pub(crate) fn outgrown(&self, bytes: u64) -> bool {
        let total = bytes + self.0.held.get();
        let out = self.0.memory.get().is_some_and(|m| total > m);
        if out {
            self.0.stopped.set(true);
            self.0.outgrown.set(Some(total));
        }
        out
    }

    /// The work spent since the call began, expansions.
    pub(super) fn spent(&self) -> u64 {
        self.0.spent.get()
    }

    pub(crate) fn spend(&self) {
        self.0.spent.set(self.0.spent.get() + 1);
    }

    /// `labels` dominance comparisons, counted in expansions as they add up; returns the
    /// expansions' worth they completed.
    pub(crate) fn compared(&self, labels: u64) -> u64 {
        let c = self.0.compared.get() + labels;
        let whole = c / Allowance::COMPARISONS_PER_EXPANSION;
        self.0.compared.set(c - whole * Allowance::COMPARISONS_PER_EXPANSION);
        self.0.spent.set(self.0.spent.get() + whole);
        whole
    }

    /// Whether the next expansion would go past the limit (the search asking stops).
    pub(crate) fn exhausted(&self) -> bool {
        let out = self.0.limit.get().is_some_and(|l| self.0.spent.get() >= l);
        if out {
            self.0.stopped.set(true);
        }
        let share = self.0.probe_limit.get().is_some_and(|l| self.0.spent.get() >= l);
        if share {
            self.0.probes_out.set(true);
        }
        out || share
    }

    /// [`Error::MemoryLimit`] or [`Error::WorkLimit`] if a search of this call was
    /// stopped.
    pub(super) fn check(&self) -> Result<()> {
        if !self.0.stopped.get() {
            return Ok(());
        }
        match (self.0.outgrown.get(), self.0.memory.get(), self.0.limit.get()) {
            (Some(bytes), Some(limit), _) => Err(Error::MemoryLimit { bytes, limit }),
            (_, _, Some(limit)) => Err(Error::WorkLimit { expansions: self.0.spent.get(), limit }),
            _ => Ok(()),
        }
    }
}

/// A count of label expansions shared with whoever watches a search run (another
/// thread may read it while the planner works). Clones count into the same total;
/// every meter equals every other, so it never changes what a configuration compares
/// as.
#[derive(Debug, Clone, Default)]
pub struct ExpansionMeter(Option<std::sync::Arc<[std::sync::atomic::AtomicU64; METER_SLOTS]>>);

/// The meter's counters: expansions, work, the current phase, the phases seen (a bit
/// each), the expansions when the current phase began, then the expansions of each
/// phase before it (settled at each change of phase, so that counting an expansion
/// stays two additions).
const METER_SLOTS: usize = 5 + PHASES.len();

/// What the searches are for, as a watcher shows it: planning, or — when no plan was
/// found — the relaxed searches that name the binding constraint
/// ([`ExpansionMeter::phase`]).
const PHASES: [&str; 8] = [
    "planning",
    "no plan: every constraint relaxed",
    "no plan: battery relaxed",
    "no plan: darkness relaxed",
    "no plan: shadow relaxed",
    "no plan: Sun in the cameras relaxed",
    "no plan: sessions relaxed",
    "no plan: goal windows relaxed",
];

/// The phase of the relaxed search for `binding` (`None`: all at once).
pub(super) fn phase_of(binding: Option<Binding>) -> usize {
    match binding {
        None => 1,
        Some(Binding::Battery) => 2,
        Some(Binding::Darkness) => 3,
        Some(Binding::Shadow) => 4,
        Some(Binding::SunInCamera) => 5,
        Some(Binding::GoalWindow) => 7,
        Some(_) => 6,
    }
}

impl ExpansionMeter {
    /// A meter that counts (the default one counts nothing).
    pub fn counting() -> ExpansionMeter {
        ExpansionMeter(Some(std::sync::Arc::default()))
    }

    /// Expansions counted so far.
    pub fn expansions(&self) -> u64 {
        self.0.as_ref().map_or(0, |n| n[0].load(std::sync::atomic::Ordering::Relaxed))
    }

    /// Work counted so far, in expansions: the expansions, and one more for every
    /// hundred labels new ones were compared with (what the work limit,
    /// [`PlannerConfig::max_expansions`](super::PlannerConfig::max_expansions), counts).
    pub fn work(&self) -> u64 {
        self.0.as_ref().map_or(0, |n| n[1].load(std::sync::atomic::Ordering::Relaxed))
    }

    /// What the searches are doing now: "planning", or "no plan: battery relaxed" and
    /// the like while the planner looks for the constraint that binds.
    pub fn phase(&self) -> &'static str {
        self.0.as_ref().map_or(PHASES[0], |n| PHASES[n[2].load(std::sync::atomic::Ordering::Relaxed) as usize])
    }

    /// Every phase the searches have been in since the meter was made, in the order of
    /// [`ExpansionMeter::phase`]'s list (not the order they ran in).
    pub fn phases_seen(&self) -> Vec<&'static str> {
        self.expansions_by_phase().into_iter().map(|(p, _)| p).collect()
    }

    pub(super) fn set_phase(&self, phase: usize) {
        use std::sync::atomic::Ordering::Relaxed;
        if let Some(n) = &self.0 {
            let now = n[0].load(Relaxed);
            let began = n[4].swap(now, Relaxed);
            n[5 + n[2].load(Relaxed) as usize].fetch_add(now.saturating_sub(began), Relaxed);
            n[2].store(phase as u64, Relaxed);
            n[3].fetch_or(1 << phase, Relaxed);
        }
    }

    pub(crate) fn add(&self, n: u64) {
        if let Some(count) = &self.0 {
            count[0].fetch_add(n, std::sync::atomic::Ordering::Relaxed);
            count[1].fetch_add(n, std::sync::atomic::Ordering::Relaxed);
        }
    }

    /// The expansions counted in each phase the searches have been in, in the order
    /// of [`ExpansionMeter::phases_seen`]; they sum to [`ExpansionMeter::expansions`].
    pub fn expansions_by_phase(&self) -> Vec<(&'static str, u64)> {
        use std::sync::atomic::Ordering::Relaxed;
        let Some(n) = &self.0 else { return vec![(PHASES[0], 0)] };
        let (seen, current) = (n[3].load(Relaxed) | 1, n[2].load(Relaxed) as usize);
        // The current phase's expansions are not settled yet.
        let running = n[0].load(Relaxed).saturating_sub(n[4].load(Relaxed));
        (0..PHASES.len())
            .filter(|i| seen >> i & 1 == 1)
            .map(|i| (PHASES[i], n[5 + i].load(Relaxed) + if i == current { running } else { 0 }))
            .collect()
    }

    pub(crate) fn add_work(&self, n: u64) {
        if let Some(count) = &self.0 {
            count[1].fetch_add(n, std::sync::atomic::Ordering::Relaxed);
        }
    }
}

impl PartialEq for ExpansionMeter {
    fn eq(&self, _: &ExpansionMeter) -> bool {
        true
    }
}
