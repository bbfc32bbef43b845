//! The engine: backward best-first search with dominance and resolution pruning, and
//! incremental repair.
//!
//! The search graph is a forest rooted at the goal labels: every node points to its
//! parent (the next step toward a goal) and threads its children through intrusive
//! sibling lists, so a change can invalidate exactly the subtree that depends on it.
//!
//! Re-planning keeps one invariant: every closed node has generated all its
//! predecessors, and every generated node has a cost that is the true cost of its path
//! to a goal. `update` removes the nodes whose paths cross a changed state (with their
//! subtrees, whose costs derived from them) and reopens the surviving closed nodes that
//! could regenerate what was removed or now reach something cheaper — for a partial
//! expansion that makes only the steps into the states the change touched; `plan` then resumes
//! best-first search (with reopening) from the frontier. In a backward search the start
//! sits at the leaves, so a change near the rover removes a small subtree and reopens a
//! handful of nodes — the D* Lite insight, here over labelled states (DD* Lite).

use rustc_hash::{FxHashMap, FxHashSet};

use crate::arena::Arena;
use crate::domain::{Domain, Goal};
use crate::group_table::GroupTable;
use crate::open::{Entry, OpenList};
use crate::state_table::StateTable;

mod insert;
mod repair;

/// No node (the end of a list, a root's parent).
pub(crate) const NONE: u32 = u32::MAX;
/// The open list's length below which stale entries are never purged.
const OPEN_PURGE_MIN: usize = 1 << 16;
/// Expansions between two asks of [`Domain::outgrown`]: [`Search::bytes`] walks the
/// state table's pages, and a graph grows by well under a megabyte in this many.
pub const MEMORY_CHECK_EVERY: u64 = 4096;
const OPEN: u8 = 1;
const CLOSED: u8 = 2;
/// Replaced by a better label of its class or dominated: no longer a search node, but
/// its path is still valid for the children that hang from it.
const DEAD: u8 = 4;
/// Invalidated by a change: its path crosses a changed state.
const REMOVED: u8 = 8;
/// With OPEN: reopened by a repair; its expansion makes only the steps into the states
/// that repair touched.
const PARTIAL: u8 = 16;
/// With CLOSED: its expansion found that no step from another state can lead to it
/// ([`Domain::expand_all`]); repairs reopen it only for steps within its own state.
const ISOLATED: u8 = 32;

/// What the search optimises.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    /// BESTPCOST: the least-cost feasible path.
    BestPathCost,
    /// BESTDPARMS: among feasible paths costing at most `max_cost`, the one whose start
    /// label is best by [`Domain::better`] (ties: lower cost).
    BestDparms {
        /// Paths costing more are discarded.
        max_cost: f64,
    },
}

/// Counters for one call (`plan` or `update`) and the graph's size after it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Nodes expanded.
    pub expansions: u64,
    /// Labels created.
    pub generated: u64,
    /// Labels discarded because another label dominated them.
    pub pruned_dominance: u64,
    /// Live labels a new one was compared with in its dominance group (see
    /// [`crate::Domain::compared`]).
    pub compared: u64,
    /// Labels discarded in favour of a better one of their resolution class.
    pub pruned_resolution: u64,
    /// Labels discarded by the global constraint or the cost bound.
    pub pruned_constraint: u64,
    /// Nodes removed because their path crossed a changed state.
    pub invalidated: u64,
    /// Closed nodes reopened for repair.
    pub reopened: u64,
    /// Nodes reclaimed (see [`Search::compact`]).
    pub reclaimed: u64,
    /// Expanded labels beaten by a better label of their class (or dominated) whose
    /// subtrees were removed; zero in a fresh search with a consistent heuristic.
    pub beaten_subtrees: u64,
    /// Open labels set aside because the current start cannot reach them
    /// ([`Domain::dormant`]).
    pub parked: u64,
    /// Live labels in the graph.
    pub labels_alive: u64,
    /// Approximate bytes held by the graph, the class table and the open list.
    pub bytes: u64,
}

/// One step of a plan, from the start toward the goal.
#[derive(Debug, Clone)]
pub struct PathStep<D: Domain> {
    /// IPARMS of this step.
    pub state: D::State,
    /// DPARMS and path quantities of this step.
    pub label: D::Label,
    /// The move taken from here to the next step (`None` at the goal).
    pub via: Option<D::Move>,
    /// Cost accumulated from the start to here.
    pub cost_so_far: f64,
}

/// The answer of [`Search::plan`].
#[derive(Debug, Clone)]
pub struct Plan<D: Domain> {
    /// The optimal path from the start to a goal, or `None` if no feasible path exists.
    pub path: Option<Vec<PathStep<D>>>,
    /// Total cost of the path (including the goal's initial cost).
    pub cost: f64,
    /// What the call did.
    pub stats: Stats,
    /// The search stopped because [`Domain::exhausted`] said so: `path` is then not
    /// known to be optimal, and `None` does not mean that no path exists.
    pub stopped: bool,
}

/// A label in the graph: 48 bytes in TEMPEST, 32 on a grid. Its resolution class is
/// not stored but recomputed ([`Domain::key`] is a division or two): nodes are most of
/// a large search's memory. (Aligning nodes to 32 bytes, so that a grid's never
/// straddle two cache lines, once made grids faster; with the class gone it measured
/// no faster, and padded TEMPEST's nodes to 64 bytes.)
struct Node<D: Domain> {
    state: D::State,
    label: D::Label,
    /// The move leading from this node to its parent; `None` at goals.
    via: Option<D::Move>,
    g: f64,
    parent: u32,
    first_child: u32,
    next_sibling: u32,
    next_in_state: u32,
    flags: u8,
}

impl<D: Domain> Node<D> {
    fn live(&self) -> bool {
        self.flags & (DEAD | REMOVED) == 0
    }
}

/// An incremental search over a [`Domain`].
pub struct Search<D: Domain> {
    mode: Mode,
    nodes: Arena<Node<D>>,
    by_state: StateTable<D>,
    open: OpenList,
    alive: u64,
    stats: Stats,
    states: Vec<D::State>,
    /// With [`Domain::MANY_LABELS`]: the label holding each (state, key) class and its
    /// cost — enough to prune a worse label without reading its rival's node (a cache
    /// miss in a large arena). Removed nodes leave the table (see [`Search::update`]).
    classes: FxHashMap<(D::State, D::Key), (u32, f64)>,
    /// The arena's length after the last compaction (see [`Search::compact`]).
    compacted_len: u32,
    /// The goal nodes, for [`Search::set_goals`].
    goal_ids: Vec<u32>,
    /// Nodes the last repair reopened for a partial expansion, and the states it
    /// touched.
    partial: Vec<u32>,
    touched: FxHashSet<D::State>,
    /// With [`Domain::MANY_LABELS`]: expanded labels beaten in their class or dominated
    /// during the current call, whose subtrees are removed once the expansion that beat
    /// them ends (see [`Search::insert`]).
    doomed: Vec<u32>,
    /// With [`Domain::MANY_LABELS`] and [`Domain::DOMINANCE`]: the head of each
    /// (state, dominance group)'s list of live labels, threaded through `group_next`
    /// (indexed by node). A label leaves its list when it is beaten or removed.
    groups: GroupTable<D>,
    group_next: Vec<u32>,
    /// D* Lite's key modifier: the sum of the heuristic drops since the open list was
    /// last keyed in full, added to every new key so that older keys stay lower bounds
    /// and can be brought up to date when they are popped.
    key_offset: f64,
    /// Whether the open list may hold keys older than the last start move.
    stale_keys: bool,
    /// The open list's length at which stale entries are next purged.
    open_purge_at: usize,
    /// The start state the keys were computed for.
    keyed_start: Option<D::State>,
    /// Open labels set aside as dormant ([`Domain::dormant`]), by their release value
    /// less `drift` when they were parked: the greatest first.
    parked: std::collections::BinaryHeap<Parked>,
    /// The sum of the release drifts since the search began ([`Domain::release_drift`]):
    /// a parked label's release value is now at most its stored one plus this.
    drift: f64,
}

/// A dormant open label and its stored release value.
#[derive(Debug, Clone, Copy)]
struct Parked {
    release: f64,
    id: u32,
}

impl PartialEq for Parked {
    fn eq(&self, other: &Parked) -> bool {
        self.cmp(other).is_eq()
    }
}
impl Eq for Parked {}
impl PartialOrd for Parked {
    fn partial_cmp(&self, other: &Parked) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Parked {
    fn cmp(&self, other: &Parked) -> std::cmp::Ordering {
        self.release.total_cmp(&other.release).then(self.id.cmp(&other.id))
    }
}

impl<D: Domain> std::fmt::Debug for Search<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Search").field("mode", &self.mode).field("nodes", &self.nodes.len()).finish_non_exhaustive()
    }
}

impl<D: Domain> Search<D> {
    /// A search from `goals` (each with its initial cost) in `mode`. Nothing is
    /// expanded until [`Search::plan`].
    pub fn new(domain: &D, goals: impl IntoIterator<Item = Goal<D>>, mode: Mode) -> Search<D> {
        let mut s = Search {
            mode,
            nodes: Arena::new(),
            by_state: StateTable::new(),
            open: OpenList::new(),
            alive: 0,
            stats: Stats::default(),
            states: Vec::new(),
            // Time-expanded domains collect hundreds of thousands of classes: start big
            // enough to skip the first dozen rehashes.
            classes: if D::MANY_LABELS && !D::DOMINANCE {
                FxHashMap::with_capacity_and_hasher(1 << 16, Default::default())
            } else {
                FxHashMap::default()
            },
            groups: GroupTable::new(),
            group_next: Vec::new(),
            compacted_len: 0,
            goal_ids: Vec::new(),
            partial: Vec::new(),
            touched: FxHashSet::default(),
            doomed: Vec::new(),
            key_offset: 0.0,
            stale_keys: false,
            open_purge_at: OPEN_PURGE_MIN,
            keyed_start: domain.start_state(),
            parked: std::collections::BinaryHeap::new(),
            drift: 0.0,
        };
        for goal in goals {
            s.insert_goal(domain, goal);
        }
        s
    }

    /// Bytes held now by the graph, its tables and the open list (approximate).
    pub fn bytes(&self) -> u64 {
        self.nodes.bytes()
            + self.by_state.bytes()
            + self.open.bytes()
            + (self.classes.capacity() * (std::mem::size_of::<((D::State, D::Key), (u32, f64))>() + 1)) as u64
            + self.groups.bytes()
            + (self.group_next.capacity() * 4) as u64
            + (self.parked.capacity() * std::mem::size_of::<Parked>()) as u64
    }

    /// The search mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Finds the optimal plan for the domain's current start, reusing the graph.
    pub fn plan(&mut self, domain: &D) -> Plan<D> {
        let reclaimed = if self.worth_compacting() { self.compact(domain) } else { 0 };
        let mut plan = match self.mode {
            Mode::BestPathCost => self.plan_best_cost(domain),
            Mode::BestDparms { max_cost } => self.plan_best_dparms(domain, max_cost),
        };
        plan.stats.reclaimed += reclaimed;
        plan
    }

    /// Tells the engine that transitions into or out of `changed` states have new costs
    /// or feasibility (increases and decreases alike). The repair happens in the next
    /// [`Search::plan`].
    pub fn update(&mut self, domain: &D, changed: &[D::State]) -> Stats {
        self.stats = Stats::default();
        let touched: Vec<D::State> = changed.to_vec();
        // Remove every node whose own transition crosses a changed state, with the
        // subtree below it.
        let mut roots = Vec::new();
        for &s in changed {
            let mut id = self.by_state.get(domain, s);
            while id != NONE {
                let n = &self.nodes[id];
                if n.flags & REMOVED == 0 {
                    if n.parent == NONE {
                        // A goal has no transition; its children's transitions touch s.
                        let mut c = n.first_child;
                        while c != NONE {
                            roots.push(c);
                            c = self.nodes[c].next_sibling;
                        }
                    } else {
                        roots.push(id);
                    }
                }
                id = n.next_in_state;
            }
        }
        self.repair(domain, roots, touched);
        self.compact_if_worth_it(domain);
        self.finish_stats();
        self.stats
    }

    /// Replaces the goals (multi-goal chaining: a later segment's candidates changed).
    /// A goal that is still among `goals` — same state, label and cost — keeps its
    /// subtree; the others are removed with theirs, the closed nodes around what they
    /// held are reopened, and the new goals are added: the next [`Search::plan`]
    /// repairs the graph instead of searching it again from scratch.
    pub fn set_goals(&mut self, domain: &D, goals: impl IntoIterator<Item = Goal<D>>) -> Stats {
        self.stats = Stats::default();
        let mut fresh: Vec<Goal<D>> = goals.into_iter().collect();
        let mut kept_goals = Vec::with_capacity(self.goal_ids.len());
        let mut roots = Vec::new();
        for &id in &self.goal_ids {
            let n = &self.nodes[id];
            if n.flags & REMOVED != 0 {
                continue;
            }
            let g = n.g;
            let same = fresh.iter().position(|goal| {
                goal.state == n.state && goal.label == n.label && goal.cost.max(0.0).to_bits() == g.to_bits()
            });
            match same {
                Some(i) => {
                    fresh.swap_remove(i);
                    kept_goals.push(id);
                }
                None => roots.push(id),
            }
        }
        self.goal_ids = kept_goals;
        self.repair(domain, roots, Vec::new());
        self.compact_if_worth_it(domain);
        for goal in fresh {
            self.insert_goal(domain, goal);
        }
        self.finish_stats();
        self.stats
    }

    /// Tells the engine that the start (and so the heuristic) changed: plan extension
    /// after the rover moved, or a new start window. Re-keys the open list.
    pub fn start_moved(&mut self, domain: &D) {
        let previous = self.keyed_start;
        let drop = previous.and_then(|p| domain.heuristic_drop(p));
        // Without a single start to measure from, any parked label may wake.
        self.drift += previous.map_or(f64::INFINITY, |p| domain.release_drift(p).max(0.0));
        self.keyed_start = domain.start_state();
        self.heuristic_fell(domain, drop);
        self.wake(domain);
    }

    /// Returns to the open list the parked labels that the current start may reach:
    /// those whose release value can now be at least the start's threshold. Each is
    /// judged again when popped.
    fn wake(&mut self, domain: &D) {
        let threshold = domain.release_threshold();
        while let Some(&Parked { release, id }) = self.parked.peek() {
            if release + self.drift < threshold {
                break;
            }
            self.parked.pop();
            let n = &self.nodes[id];
            if n.flags & !PARTIAL == OPEN {
                let f = n.g + domain.heuristic(n.state, &n.label) + self.key_offset;
                self.open.push(Entry::new(f, n.g, id));
            }
        }
        if self.drift.is_infinite() {
            self.drift = 0.0;
        }
    }

    /// Tells the engine that the heuristic of any label fell by at most `by` (`None`:
    /// by an unknown amount) — a domain whose heuristic is a cached bound repaired
    /// after the world changed. Older keys stay lower bounds and are brought up to
    /// date as they are popped (D* Lite's key modifier); with `None` the open list is
    /// keyed again in full.
    pub fn heuristic_fell(&mut self, domain: &D, by: Option<f64>) {
        if let Some(drop) = by.filter(|d| d.is_finite()) {
            self.key_offset += drop.max(0.0);
            // Keys may also have risen: each is brought up to date when popped, so a
            // label the new heuristic puts past the answer is not expanded.
            self.stale_keys = true;
            return;
        }
        self.key_offset = 0.0;
        self.stale_keys = false;
        self.keyed_start = domain.start_state();
        let mut seen = FxHashSet::default();
        let entries: Vec<Entry> = std::mem::replace(&mut self.open, OpenList::new())
            .into_vec()
            .into_iter()
            .filter(|e| {
                let n = &self.nodes[e.id()];
                n.flags & !PARTIAL == OPEN && e.matches(n.g) && seen.insert(e.id())
            })
            .map(|e| {
                let n = &self.nodes[e.id()];
                Entry::new(n.g + domain.heuristic(n.state, &n.label), n.g, e.id())
            })
            .collect();
        self.open = OpenList::from_vec(entries);
        self.open_purge_at = (3 * self.open.len() / 2).max(OPEN_PURGE_MIN);
    }

    /// Whether the graph has outgrown the memory `domain` allows, asked every
    /// [`MEMORY_CHECK_EVERY`] expansions of this call ([`Domain::outgrown`]).
    fn outgrown(&self, domain: &D) -> bool {
        self.stats.expansions.is_multiple_of(MEMORY_CHECK_EVERY) && domain.outgrown(self.bytes())
    }

    fn plan_best_cost(&mut self, domain: &D) -> Plan<D> {
        self.stats = Stats::default();
        // A start label may already be in the graph (the rover moved along the plan).
        let mut best = self.best_known_start(domain, f64::INFINITY, |a, b| a.g < b.g);
        let mut stopped = false;
        while let Some(top) = self.pop_valid(domain) {
            if best.is_some_and(|b| self.nodes[b].g + self.key_offset <= top.f()) {
                self.open.push(top);
                break;
            }
            let id = top.id();
            let (state, label) = {
                let n = &self.nodes[id];
                (n.state, n.label.clone())
            };
            if domain.is_start(state, &label) {
                // f = g + h ≥ g and this is the least f: nothing cheaper remains.
                self.open.push(top);
                if best.is_none_or(|b| self.nodes[id].g < self.nodes[b].g) {
                    best = Some(id);
                }
                break;
            }
            // Checked last: a search whose answer is on the open list needs no more work.
            if domain.exhausted() || self.outgrown(domain) {
                self.open.push(top);
                stopped = true;
                break;
            }
            self.expand(domain, id);
            if best.is_some_and(|b| !self.nodes[b].live()) {
                // The expansion beat a label on the known start's path.
                best = self.best_known_start(domain, f64::INFINITY, |a, b| a.g < b.g);
            }
        }
        self.finish_stats();
        Plan { stopped, ..self.extract(best) }
    }

    fn plan_best_dparms(&mut self, domain: &D, max_cost: f64) -> Plan<D> {
        self.stats = Stats::default();
        let mut stopped = false;
        while let Some(top) = self.pop_valid(domain) {
            if top.f() - self.key_offset > max_cost {
                self.open.push(top);
                break;
            }
            if domain.exhausted() || self.outgrown(domain) {
                self.open.push(top);
                stopped = true;
                break;
            }
            self.expand(domain, top.id());
        }
        let best = self.best_known_start(domain, max_cost, |a, b| {
            domain.better(&a.label, &b.label) || (!domain.better(&b.label, &a.label) && a.g < b.g)
        });
        self.finish_stats();
        Plan { stopped, ..self.extract(best) }
    }

    /// The best live start label already in the graph with cost ≤ `max_cost`.
    fn best_known_start(&self, domain: &D, max_cost: f64, prefer: impl Fn(&Node<D>, &Node<D>) -> bool) -> Option<u32> {
        let mut best: Option<u32> = None;
        let mut consider = |id: u32| {
            let n = &self.nodes[id];
            if n.live()
                && n.g <= max_cost
                && domain.is_start(n.state, &n.label)
                && best.is_none_or(|b| prefer(n, &self.nodes[b]))
            {
                best = Some(id);
            }
        };
        match domain.start_state() {
            Some(s) => {
                let mut id = self.by_state.get(domain, s);
                while id != NONE {
                    consider(id);
                    id = self.nodes[id].next_in_state;
                }
            }
            None => (0..self.nodes.len()).for_each(consider),
        }
        best
    }

    /// Takes the least open entry that is still current, discarding stale ones (put it
    /// back with `OpenList::push` if it is not expanded).
    #[inline(always)]
    fn pop_valid(&mut self, domain: &D) -> Option<Entry> {
        while let Some(e) = self.open.pop() {
            let n = &self.nodes[e.id()];
            if n.flags & !PARTIAL == OPEN && e.matches(n.g) {
                if let Some(release) = domain.dormant(n.state, &n.label) {
                    // The current start cannot reach it: set aside until it may.
                    self.parked.push(Parked { release: release - self.drift, id: e.id() });
                    self.stats.parked += 1;
                    continue;
                }
                if self.stale_keys {
                    // Keyed before a start move: a lower bound of its key now. Bring it
                    // up to date; if it grew, it waits its turn.
                    let f = n.g + domain.heuristic(n.state, &n.label) + self.key_offset;
                    let current = Entry::new(f, n.g, e.id());
                    if current.f() > e.f() {
                        self.open.push(current);
                        continue;
                    }
                }
                return Some(e);
            }
        }
        None
    }

    /// Expands `id`, then removes the subtrees of the expanded labels it beat.
    #[inline(always)]
    fn expand(&mut self, domain: &D, id: u32) {
        self.expand_node(domain, id);
        if D::MANY_LABELS && !self.doomed.is_empty() {
            self.remove_doomed(domain);
        }
        if D::MANY_LABELS && self.open.len() > self.open_purge_at {
            self.purge_open();
        }
    }

    /// Drops the open list's stale entries — those of labels since beaten, or given a
    /// lower cost (each left its entry behind). With many labels per state many
    /// entries go stale before they are popped. Run when the list has grown by half since the last
    /// purge, so the cost is constant per entry.
    #[cold]
    #[inline(never)]
    fn purge_open(&mut self) {
        let nodes = &self.nodes;
        self.open.retain(|e| {
            let n = &nodes[e.id()];
            n.flags & !PARTIAL == OPEN && e.matches(n.g)
        });
        self.open_purge_at = (3 * self.open.len() / 2).max(OPEN_PURGE_MIN);
    }

    fn expand_node(&mut self, domain: &D, id: u32) {
        let partial = self.nodes[id].flags & PARTIAL != 0;
        self.nodes[id].flags = CLOSED;
        self.stats.expansions += 1;
        let (state, label, g) = {
            let n = &self.nodes[id];
            (n.state, n.label.clone(), n.g)
        };
        if partial {
            self.expand_partially(domain, id, state, label, g);
            return;
        }
        let isolated = domain.expand_all(state, &label, |a, step| {
            debug_assert!(step.cost >= 0.0, "step costs must be non-negative");
            self.insert(domain, step.state, step.label, g + step.cost, id, Some(a));
        });
        // The node may have been beaten while expanding (a step back into its own
        // class): only a node still closed keeps the mark.
        if isolated && self.nodes[id].flags == CLOSED {
            self.nodes[id].flags |= ISOLATED;
        }
    }

    /// A reopened node's expansion: only the steps into the states the last repair
    /// touched (the others it made before are still in the graph, at their costs).
    /// Kept out of line: a fresh search never takes it.
    #[cold]
    #[inline(never)]
    fn expand_partially(&mut self, domain: &D, id: u32, state: D::State, label: D::Label, g: f64) {
        let touched = std::mem::take(&mut self.touched);
        domain.expand(
            state,
            &label,
            |a| domain.predecessor_state(state, a).is_none_or(|p| touched.contains(&p)),
            |a, step| {
                if touched.contains(&step.state) {
                    debug_assert!(step.cost >= 0.0, "step costs must be non-negative");
                    self.insert(domain, step.state, step.label, g + step.cost, id, Some(a));
                }
            },
        );
        self.touched = touched;
    }

    fn finish_stats(&mut self) {
        self.stats.labels_alive = self.alive;
        self.stats.bytes = self.bytes();
    }

    fn extract(&self, best: Option<u32>) -> Plan<D> {
        let Some(start) = best else {
            return Plan { path: None, cost: f64::INFINITY, stats: self.stats, stopped: false };
        };
        let total = self.nodes[start].g;
        let mut path = Vec::new();
        let mut id = start;
        while id != NONE {
            let n = &self.nodes[id];
            path.push(PathStep { state: n.state, label: n.label.clone(), via: n.via, cost_so_far: total - n.g });
            id = n.parent;
        }
        Plan { path: Some(path), cost: total, stats: self.stats, stopped: false }
    }
}
