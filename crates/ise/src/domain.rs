//! What a user supplies to the engine: the [`Domain`] trait.

use std::fmt::Debug;
use std::hash::Hash;

/// A search problem, seen backwards from the goals.
///
/// - `State` is the IPARMS part of a search state: discrete and coarse (a grid cell).
/// - `Label` carries the DPARMS and path quantities: arbitrarily fine values (time,
///   required energy) that ride along a path.
/// - `Key` groups labels at one state into resolution-equivalence classes: of the
///   labels at a state with equal keys, only the best (lowest cost; ties by
///   [`Domain::better`]) is kept.
///
/// The engine searches backwards: it starts from goal labels and asks, for each
/// move that could have led *into* a state, which predecessor label it came from
/// and at what cost. Costs are ≥ 0 and additive along a path.
pub trait Domain {
    /// Discrete, coarse coordinates (IPARMS).
    type State: Copy + Eq + Hash + Debug;
    /// Fine-grained path quantities (DPARMS), e.g. time and required energy.
    type Label: Clone + Debug + PartialEq;
    /// Resolution-equivalence class of a label at a state.
    type Key: Copy + Ord + Hash + Debug;
    /// An move; applied forwards it leads from the predecessor to the state.
    type Move: Copy + Debug;

    /// Whether [`Domain::dominates`] can ever return true; when false the engine skips
    /// the pairwise dominance tests.
    const DOMINANCE: bool = false;

    /// Whether a state may hold many labels (e.g. one per time class): the engine then
    /// indexes them instead of walking every label at the state. Without
    /// [`Domain::DOMINANCE`] it keeps a table of resolution classes, so admitting a
    /// label costs O(1) (about 16 bytes per label); with it, a list of the live labels of
    /// each dominance group ([`Domain::dominance_group`]), so a label is tested only
    /// against the few it can dominate or be dominated by (4 bytes per label).
    const MANY_LABELS: bool = false;

    /// With [`Domain::MANY_LABELS`] and [`Domain::DOMINANCE`]: whether the labels of one
    /// resolution class compete by [`Domain::dominates`] alone (the key only groups
    /// them), instead of the cheapest standing for the whole class. A domain whose
    /// labels carry a resource that decides feasibility (a battery) answers true when it
    /// is asked to be exact in it, so that a cheaper label needing more of the resource
    /// never hides one needing less.
    fn pareto_classes(&self) -> bool {
        false
    }

    /// Expands (`state`, `label`): calls `visit` with every feasible backward
    /// transition — the move, and the state and label it leads from with the step's
    /// cost (≥ 0) — in a fixed order, skipping those a local constraint forbids.
    ///
    /// Only moves for which `wanted` is true need be evaluated: a repair's partial
    /// re-expansion asks for the few steps into the states it changed, and a domain
    /// saves the work of the others by asking `wanted` before evaluating an move. A
    /// full expansion passes `|_| true`, which the compiler removes. The steps given for
    /// a `wanted` move must not depend on which other moves are wanted.
    ///
    /// This is the one way the engine learns transitions; a domain whose moves share
    /// work (the same Sun, the same arrival cell) does it once here.
    fn expand(
        &self,
        state: Self::State,
        label: &Self::Label,
        wanted: impl Fn(Self::Move) -> bool,
        visit: impl FnMut(Self::Move, Predecessor<Self>),
    ) where
        Self: Sized;

    /// [`Domain::expand`] with every move wanted, telling besides whether no step
    /// from *another* state can lead to (`state`, `label`) for a reason that depends on
    /// `state` alone (TEMPEST: the rover could not be at this cell at this time — in
    /// the dark, in shadow, on ground too steep), which stays true until `state` itself
    /// changes. A repair then never reopens such a label to remake steps from changed
    /// neighbours: it would make none. The default tells nothing (`false`).
    fn expand_all(
        &self,
        state: Self::State,
        label: &Self::Label,
        visit: impl FnMut(Self::Move, Predecessor<Self>),
    ) -> bool
    where
        Self: Sized,
    {
        self.expand(state, label, |_| true, visit);
        false
    }

    /// The predecessor state `move` comes from into `state`, when it can be told
    /// without evaluating the transition (`None`: unknown). Repairs use it to skip the
    /// steps that cannot land on a changed state.
    fn predecessor_state(&self, _state: Self::State, _via: Self::Move) -> Option<Self::State> {
        None
    }

    /// A test of whether expanding a label at `state` can make a label of a given class
    /// at `pred` (a state among [`Domain::successors`] of `pred`, or `pred` itself).
    /// A repair that must regenerate one class at a state reopens only the neighbours'
    /// labels that pass it. Made once per pair of states and asked for each label
    /// there; the default passes every label, which is always sound.
    fn lands_in(&self, _state: Self::State, _pred: Self::State) -> impl Fn(&Self::Label, Self::Key) -> bool {
        |_, _| true
    }

    /// The states reachable from `state` by one move (appended to `out`; include
    /// `state` itself for stationary moves). Used in re-planning to find the nodes
    /// whose expansion can regenerate labels at a state.
    fn successors(&self, state: Self::State, out: &mut Vec<Self::State>);

    /// The resolution-equivalence class of `label` at `state`.
    fn key(&self, state: Self::State, label: &Self::Label) -> Self::Key;

    /// Whether (`a`, `cost_a`) dominates (`b`, `cost_b`) at `state`: every completion
    /// of `b` toward the start can be matched by `a` at no greater cost. Only called
    /// when [`Domain::DOMINANCE`] is true.
    fn dominates(&self, _state: Self::State, _a: &Self::Label, _cost_a: f64, _b: &Self::Label, _cost_b: f64) -> bool {
        false
    }

    /// The dominance group of a label's resolution class at a state: labels can dominate
    /// one another only within a group (for a time-expanded domain, a time class; the
    /// key may further split it into energy classes). The default, the key itself,
    /// makes every class its own group. Only used with [`Domain::MANY_LABELS`] and
    /// [`Domain::DOMINANCE`].
    fn dominance_group(&self, _state: Self::State, key: Self::Key) -> Self::Key {
        key
    }

    /// Whether `better`, which beat the expanded label `beaten` at `state` (same class at
    /// no greater cost, or dominating it), stands in for it: every step from `beaten`
    /// has a counterpart from `better` that lands in the same class and beats it, so
    /// `beaten`'s subtree is replaced label by label as the search reaches it and may
    /// stay meanwhile. True (the default) where a class is one exact value; a domain
    /// whose classes merge different values (time classes wider than one instant)
    /// answers false when they differ, and the engine then removes the subtree at once
    /// — otherwise labels that descend from a beaten one could hold classes a fresh
    /// search gives to others, and the answer would depend on the search's history.
    fn stands_in_for(&self, _state: Self::State, _better: &Self::Label, _beaten: &Self::Label) -> bool {
        true
    }

    /// The global constraint: false when the path quantities in `label` (with path cost
    /// `cost` from the goal) violate it, so the label is not propagated.
    fn within_global(&self, _state: Self::State, _label: &Self::Label, _cost: f64) -> bool {
        true
    }

    /// Whether any label of class `key` at `state` may pass [`Domain::within_global`]:
    /// false lets a repair skip regenerating labels for a class that is ruled out
    /// entirely (for a time-expanded domain, a time class the rover can no longer
    /// reach). The default, true, is always sound.
    fn class_within_global(&self, _state: Self::State, _key: Self::Key) -> bool {
        true
    }

    /// Whether the work the caller allows is spent: the engine then stops a search
    /// before its next expansion, leaves the graph as it stands (the least entry back on
    /// the open list, so a later [`crate::Search::plan`] goes on from there) and reports
    /// [`crate::Plan::stopped`]. The default never stops.
    fn exhausted(&self) -> bool {
        false
    }

    /// Whether a graph of `graph_bytes` ([`crate::Search::bytes`]) has outgrown the
    /// memory the caller allows: the engine asks every [`crate::MEMORY_CHECK_EVERY`]
    /// expansions and then stops as for [`Domain::exhausted`]. The default never stops.
    fn outgrown(&self, _graph_bytes: u64) -> bool {
        false
    }

    /// The engine compared a new label at a state with `labels` live ones of its
    /// dominance group (with [`Domain::MANY_LABELS`] and [`Domain::DOMINANCE`]): work that
    /// grows with the Pareto fronts rather than with the expansions, so a domain that
    /// bounds its work ([`Domain::exhausted`]) counts it too. The default ignores it.
    fn compared(&self, _labels: u64) {}

    /// The start test: whether a path may begin at (`state`, `label`) (start cell, start
    /// window, start energy).
    fn is_start(&self, state: Self::State, label: &Self::Label) -> bool;

    /// The start's state, if there is a single one: lets the engine find start labels
    /// already in its graph without scanning it (plan extension after the rover moved).
    fn start_state(&self) -> Option<Self::State> {
        None
    }

    /// A dense index of `state` in 0..2³², if the states have one (grid cells): the
    /// engine then keeps its state table in pages allocated as the search touches them,
    /// instead of hashing.
    fn dense_index(&self, _state: Self::State) -> Option<u32> {
        None
    }

    /// An admissible (never over-estimating) estimate of the cost from the start to
    /// (`state`, `label`).
    fn heuristic(&self, state: Self::State, label: &Self::Label) -> f64;

    /// After the start moved from the state `previous` to the current one: a bound on
    /// how much the heuristic of any label may have fallen — for a heuristic that is a
    /// distance obeying the triangle inequality, the heuristic between the two starts.
    /// With it the engine re-keys its open list lazily (D* Lite's key modifier), paying
    /// per node popped rather than for the whole list at every move; `None` (the
    /// default) means unknown, and the whole list is re-keyed.
    fn heuristic_drop(&self, _previous: Self::State) -> Option<f64> {
        None
    }

    /// Whether the current start cannot reach (`state`, `label`) at all, by a bound
    /// that ignores cost (TEMPEST: a label earlier than the start window plus the
    /// fastest travel from the start). `None`: it may. `Some(r)`: it cannot while
    /// [`Domain::release_threshold`] is above `r`; the engine sets such a label aside
    /// instead of expanding it — every label it would make is dormant too, so a start
    /// window no plan can use costs nothing to search instead of everything — and
    /// takes it back when the start moves so that it may wake. Must be consistent:
    /// the predecessors of a dormant label are dormant.
    #[inline(always)]
    fn dormant(&self, _state: Self::State, _label: &Self::Label) -> Option<f64> {
        None
    }

    /// The current start's threshold for [`Domain::dormant`] (TEMPEST: the opening
    /// of the start window, s).
    fn release_threshold(&self) -> f64 {
        f64::NEG_INFINITY
    }

    /// After the start moved from the state `previous` to the current one: a bound on
    /// how much any label's release value may have risen (TEMPEST: the fastest travel
    /// between the two starts).
    fn release_drift(&self, _previous: Self::State) -> f64 {
        0.0
    }

    /// The BESTDPARMS order: whether `a` is strictly better than `b`.
    fn better(&self, _a: &Self::Label, _b: &Self::Label) -> bool {
        false
    }
}

/// One backward transition: the predecessor and the cost of the step.
#[derive(Debug, Clone)]
pub struct Predecessor<D: Domain + ?Sized> {
    /// Predecessor state.
    pub state: D::State,
    /// Predecessor label.
    pub label: D::Label,
    /// Cost of the step, ≥ 0.
    pub cost: f64,
}

/// A goal label from which the backward search starts, with its initial cost (the
/// cost-to-go of whatever follows it, for multi-goal chaining).
#[derive(Debug, Clone)]
pub struct Goal<D: Domain + ?Sized> {
    /// Goal state.
    pub state: D::State,
    /// Goal label.
    pub label: D::Label,
    /// Initial cost, ≥ 0.
    pub cost: f64,
}
