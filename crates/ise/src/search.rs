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
    /// The action taken from here to the next step (`None` at the goal).
    pub action: Option<D::Action>,
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
    /// The action leading from this node to its parent; `None` at goals.
    action: Option<D::Action>,
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

    /// Removes the subtrees under `roots` (the nodes and everything whose path passes
    /// through them) and reopens the surviving closed nodes that can regenerate labels
    /// at the states in `whole` (any class: their transitions changed) and in the
    /// classes of what was removed, or reach them more cheaply now.
    fn repair(&mut self, domain: &D, roots: Vec<u32>, whole: Vec<D::State>) {
        // Nodes still waiting for a partial expansion from an earlier repair stay
        // partial: the touched states accumulate (a superset of what each of them
        // needs), and are forgotten once no partial expansion is pending.
        let nodes = &self.nodes;
        self.partial.retain(|&id| nodes[id].flags & PARTIAL != 0 && nodes[id].flags & REMOVED == 0);
        if self.partial.is_empty() {
            self.touched.clear();
        }
        // What must be regenerated, state by state in the order first touched: every
        // class (`true`) or the listed ones.
        let mut order: Vec<D::State> = Vec::new();
        let mut touch: FxHashMap<D::State, (bool, Vec<D::Key>)> = FxHashMap::default();
        for s in whole {
            touch.entry(s).or_insert_with(|| {
                order.push(s);
                (true, Vec::new())
            });
        }
        self.remove_subtrees(domain, roots, &mut touch, &mut order);
        let closed = self.closed_near(domain, &order, &touch);
        // Those closed nodes keep every step they made that lands on an untouched state
        // (its transition did not change): they are reopened for a partial expansion
        // that makes again only the steps into touched states — if the search still
        // needs them when they come up.
        for id in closed {
            let n = &mut self.nodes[id];
            n.flags = OPEN | PARTIAL;
            self.stats.reopened += 1;
            let (g, label, state) = (n.g, n.label.clone(), n.state);
            let f = g + domain.heuristic(state, &label) + self.key_offset;
            self.open.push(Entry::new(f, g, id));
            self.partial.push(id);
        }
        self.touched.extend(order);
    }

    /// Removes the subtrees under `roots` (the nodes and everything whose path passes
    /// through them), noting in `touch` (in `order` of first touch) the classes the
    /// removed labels had pruned others in.
    fn remove_subtrees(
        &mut self,
        domain: &D,
        roots: Vec<u32>,
        touch: &mut FxHashMap<D::State, (bool, Vec<D::Key>)>,
        order: &mut Vec<D::State>,
    ) {
        let mut stack = roots;
        while let Some(id) = stack.pop() {
            let n = &mut self.nodes[id];
            if n.flags & REMOVED != 0 {
                continue;
            }
            let was_live = n.live();
            if was_live {
                self.alive -= 1;
                if D::MANY_LABELS && D::DOMINANCE {
                    self.leave_group(domain, id);
                }
            }
            let n = &mut self.nodes[id];
            n.flags = REMOVED;
            self.stats.invalidated += 1;
            let state = n.state;
            if D::MANY_LABELS && !D::DOMINANCE {
                let class = (state, domain.key(state, &n.label));
                if self.classes.get(&class).is_some_and(|&(held, _)| held == id) {
                    self.classes.remove(&class);
                }
            }
            let key = domain.key(state, &n.label);
            let mut c = n.first_child;
            while c != NONE {
                stack.push(c);
                c = self.nodes[c].next_sibling;
            }
            // What the removed label had pruned is in its own class at its state. A
            // class the global constraint now rules out entirely has nothing to
            // regenerate (the start moved on past it).
            if domain.class_within_global(state, key) {
                let (all, keys) = touch.entry(state).or_insert_with(|| {
                    order.push(state);
                    (false, Vec::new())
                });
                if !*all && !keys.contains(&key) {
                    keys.push(key);
                }
            }
        }
    }

    /// The surviving closed nodes that can regenerate labels at the touched states, or
    /// reach them more cheaply now: those at the touched states and their neighbours
    /// whose steps can land in a touched class. Removed and replaced-but-never-expanded
    /// nodes met on the way are unlinked from their states' lists.
    fn closed_near(
        &mut self,
        domain: &D,
        order: &[D::State],
        touch: &FxHashMap<D::State, (bool, Vec<D::Key>)>,
    ) -> Vec<u32> {
        let mut near = Vec::new();
        let mut toward: FxHashMap<D::State, Vec<D::State>> = FxHashMap::default();
        for &t in order {
            self.states.clear();
            domain.successors(t, &mut self.states);
            self.states.push(t);
            for &s in &self.states {
                toward
                    .entry(s)
                    .or_insert_with(|| {
                        near.push(s);
                        Vec::new()
                    })
                    .push(t);
            }
        }
        let mut closed = Vec::new();
        for s in near {
            let targets: Vec<_> = toward[&s]
                .iter()
                .map(|t| {
                    let (all, keys) = &touch[t];
                    (*t, *all, keys.as_slice(), domain.lands_in(s, *t))
                })
                .collect();
            let head = self.by_state.get(domain, s);
            let (mut prev, mut id, mut new_head) = (NONE, head, head);
            while id != NONE {
                let n = &self.nodes[id];
                let next = n.next_in_state;
                // Removed nodes, and replaced ones that were never expanded (no path
                // hangs from them), are of no further use at this state: unlink them,
                // so the next repair here walks only what matters. (With a class
                // table, admitting labels never walks these lists, so they collect
                // every label ever made at the state.)
                if n.flags & REMOVED != 0 || (n.flags & DEAD != 0 && n.first_child == NONE) {
                    self.unlink(prev, next, &mut new_head);
                    id = next;
                    continue;
                }
                let isolated = n.flags & ISOLATED != 0;
                if n.flags & !ISOLATED == CLOSED
                    && targets.iter().any(|(t, all, keys, lands)| {
                        (!isolated || *t == s) && (*all || keys.iter().any(|&k| lands(&n.label, k)))
                    })
                {
                    closed.push(id);
                }
                prev = id;
                id = next;
            }
            self.relink_head(domain, s, head, new_head);
        }
        closed
    }

    /// Tells the engine that [`Domain::within_global`] may now reject labels it
    /// accepted before (the start moved on, so fewer labels are reachable): those labels
    /// are removed with their subtrees, and the closed nodes that can regenerate what
    /// they had pruned in their classes are reopened, as in [`Search::update`]. Without
    /// this a kept graph would hold labels a fresh search never makes, and one of them
    /// could hold a class that a reachable label needs. Scans every node once.
    pub fn restrict(&mut self, domain: &D) -> Stats {
        self.stats = Stats::default();
        let roots: Vec<u32> = (0..self.nodes.len())
            .filter(|&id| {
                let n = &self.nodes[id];
                n.live() && !domain.within_global(n.state, &n.label, n.g)
            })
            .collect();
        if !roots.is_empty() {
            self.repair(domain, roots, Vec::new());
            self.compact_if_worth_it(domain);
        }
        self.finish_stats();
        self.stats
    }

    fn compact_if_worth_it(&mut self, domain: &D) {
        if self.worth_compacting() {
            self.stats.reclaimed += self.compact(domain);
        }
    }

    /// Removes the subtrees of the expanded labels the last expansion beat (see
    /// `doomed`): their descendants' paths run through a label that is no longer its
    /// class's best, and a fresh search would never have made them. Leaving them would
    /// make the graph, and so the answer, depend on the order labels arrived in — with
    /// coarse classes, on the search's history. The closed nodes around what is
    /// removed are reopened, so what those descendants had pruned is made again.
    #[cold]
    #[inline(never)]
    fn remove_doomed(&mut self, domain: &D) {
        let roots = std::mem::take(&mut self.doomed);
        let mut children = Vec::new();
        for &id in &roots {
            let mut c = std::mem::replace(&mut self.nodes[id].first_child, NONE);
            while c != NONE {
                children.push(c);
                c = self.nodes[c].next_sibling;
            }
        }
        self.stats.beaten_subtrees += roots.len() as u64;
        self.repair(domain, children, Vec::new());
    }

    /// Adds a goal label (through the same class and dominance tests as any label).
    fn insert_goal(&mut self, domain: &D, goal: Goal<D>) {
        let before = self.nodes.len();
        self.insert(domain, goal.state, goal.label, goal.cost.max(0.0), NONE, None);
        if self.nodes.len() > before {
            self.goal_ids.push(self.nodes.len() - 1);
        }
        if D::MANY_LABELS && !self.doomed.is_empty() {
            self.remove_doomed(domain);
        }
    }

    /// Whether enough of the arena is garbage — labels killed by better ones with
    /// nothing hanging from them, labels removed by a repair — to reclaim it: at least
    /// 40 % of the nodes are not live, and the arena grew by a quarter since it was last
    /// compacted (so the O(nodes) pass is paid for by the nodes made since).
    fn worth_compacting(&self) -> bool {
        let len = u64::from(self.nodes.len());
        len >= 1 << 14 && 5 * self.alive <= 3 * len && 4 * len >= 5 * u64::from(self.compacted_len)
    }

    /// Reclaims the nodes that no longer serve a purpose (the paper's ISE "deletes a
    /// state when it no longer serves a purpose"): removed nodes, and dead ones (beaten
    /// by a better label) from which no live path hangs. The survivors keep their
    /// order, so the open list's tie-breaking is unchanged; every index (parents,
    /// children, state lists, the class and group tables, the open list) is rebuilt.
    /// Returns the nodes reclaimed.
    pub fn compact(&mut self, domain: &D) -> u64 {
        // Pending partial expansions become full ones (the list's ids are about to move).
        for id in std::mem::take(&mut self.partial) {
            self.nodes[id].flags &= !PARTIAL;
        }
        let len = self.nodes.len();
        // Live nodes and every node on their paths to the goals (dead ones included: a
        // live label's path may pass through a beaten one). The state heads of every
        // node are cleared on the way, to be rebuilt from the survivors.
        let mut remap = vec![NONE; len as usize];
        for id in 0..len {
            let state = self.nodes[id].state;
            self.by_state.set(domain, state, NONE);
            if self.nodes[id].live() {
                let mut a = id;
                while a != NONE && remap[a as usize] == NONE {
                    remap[a as usize] = 0;
                    a = self.nodes[a].parent;
                }
            }
        }
        let mut kept = 0u32;
        for slot in remap.iter_mut() {
            if *slot != NONE {
                *slot = kept;
                kept += 1;
            }
        }
        let open: Vec<Entry> = std::mem::replace(&mut self.open, OpenList::new())
            .into_vec()
            .into_iter()
            .filter_map(|e| {
                let n = &self.nodes[e.id()];
                let new = remap[e.id() as usize];
                (n.flags & !PARTIAL == OPEN && e.matches(n.g) && new != NONE).then(|| Entry::new(e.f(), n.g, new))
            })
            .collect();
        // Slide the survivors down, in order.
        for old in 0..len {
            let new = remap[old as usize];
            if new != NONE && new != old {
                self.nodes.swap(new, old);
            }
        }
        self.nodes.truncate(kept);
        self.relink(domain, kept, &remap);
        self.open = OpenList::from_vec(open);
        self.open_purge_at = (3 * self.open.len() / 2).max(OPEN_PURGE_MIN);
        let parked = std::mem::take(&mut self.parked);
        self.parked = parked
            .into_iter()
            .filter_map(|p| {
                let new = remap[p.id as usize];
                (new != NONE).then_some(Parked { release: p.release, id: new })
            })
            .collect();
        self.goal_ids.retain_mut(|id| {
            *id = remap[*id as usize];
            *id != NONE
        });
        self.compacted_len = kept;
        u64::from(len - kept)
    }

    /// After compaction moved the `kept` survivors down (`remap`: old id to new), makes
    /// again every link between them: parents and children, the states' label lists,
    /// and the class table or dominance groups of the live ones — newest first, as
    /// they were made.
    fn relink(&mut self, domain: &D, kept: u32, remap: &[u32]) {
        self.classes.clear();
        self.groups.clear();
        self.group_next.clear();
        if D::MANY_LABELS && D::DOMINANCE {
            self.group_next.resize(kept as usize, NONE);
        }
        // Children lists are emptied first: a relabelled node (decrease-key) may be older
        // than its new parent.
        for id in 0..kept {
            let n = &mut self.nodes[id];
            n.parent = if n.parent == NONE { NONE } else { remap[n.parent as usize] };
            n.first_child = NONE;
        }
        for id in 0..kept {
            let (state, key, parent, live, g) = {
                let n = &self.nodes[id];
                (n.state, domain.key(n.state, &n.label), n.parent, n.live(), n.g)
            };
            self.nodes[id].next_sibling = if parent == NONE { NONE } else { self.nodes[parent].first_child };
            if parent != NONE {
                self.nodes[parent].first_child = id;
            }
            self.nodes[id].next_in_state = self.by_state.get(domain, state);
            self.by_state.set(domain, state, id);
            if live && D::MANY_LABELS {
                if D::DOMINANCE {
                    let group = domain.dominance_group(state, key);
                    self.group_next[id as usize] = self.groups.get(domain, state, group);
                    self.groups.set(domain, state, group, id);
                } else {
                    self.classes.insert((state, key), (id, g));
                }
            }
        }
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

    /// Adds a label unless the global constraint, its resolution class or dominance
    /// rejects it; replaces what it beats.
    #[inline(always)]
    fn insert(&mut self, domain: &D, state: D::State, label: D::Label, g: f64, parent: u32, action: Option<D::Action>) {
        if !domain.within_global(state, &label, g) || matches!(self.mode, Mode::BestDparms { max_cost } if g > max_cost)
        {
            self.stats.pruned_constraint += 1;
            return;
        }
        let key = domain.key(state, &label);
        let head = self.by_state.get(domain, state);
        if !D::MANY_LABELS && !D::DOMINANCE && head != NONE {
            // Most labels offered during a search lose to (or tie with) the label
            // already heading their state — on a grid, 4 of every 5: decide those here,
            // inlined in the expansion loop, exactly as the walk below would at its
            // first node.
            let n = &self.nodes[head];
            if n.flags & (DEAD | REMOVED) == 0
                && domain.key(state, &n.label) == key
                && (n.g < g || (n.g == g && !domain.better(&label, &n.label)))
            {
                self.stats.pruned_resolution += 1;
                return;
            }
        }
        if !D::MANY_LABELS && head == NONE {
            // A state seen for the first time: nothing to compete with.
            self.push_node(domain, state, label, g, parent, action, NONE);
            return;
        }
        self.insert_slow(domain, state, label, key, head, g, parent, action);
    }

    /// The rest of [`Search::insert`]: the class table, or a walk over the state's labels.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn insert_slow(
        &mut self,
        domain: &D,
        state: D::State,
        label: D::Label,
        key: D::Key,
        head: u32,
        g: f64,
        parent: u32,
        action: Option<D::Action>,
    ) {
        if D::MANY_LABELS && D::DOMINANCE {
            self.insert_in_group(domain, state, label, key, head, g, parent, action);
            return;
        }
        if D::MANY_LABELS && !D::DOMINANCE {
            self.insert_in_class(domain, state, label, key, head, g, parent, action);
            return;
        }
        // Walk the labels at this state, unlinking removed ones on the way.
        let mut prev = NONE;
        let mut id = head;
        let mut new_head = head;
        while id != NONE {
            let next = self.nodes[id].next_in_state;
            let flags = self.nodes[id].flags;
            if flags & REMOVED != 0 {
                self.unlink(prev, next, &mut new_head);
                id = next;
                continue;
            }
            if flags & DEAD == 0 {
                let n = &self.nodes[id];
                if domain.key(state, &n.label) == key {
                    let keep_old = n.g < g || (n.g == g && !domain.better(&label, &n.label));
                    if keep_old {
                        self.stats.pruned_resolution += 1;
                        self.relink_head(domain, state, head, new_head);
                        return;
                    }
                    self.stats.pruned_resolution += 1;
                    if !D::DOMINANCE && n.flags == OPEN && n.first_child == NONE {
                        // Not yet expanded and nothing hangs from it: the better label
                        // takes its node (A*'s decrease-key) instead of a new one. On a
                        // grid half the labels made are such replacements.
                        self.relabel(domain, id, label, g, parent, action);
                        self.relink_head(domain, state, head, new_head);
                        return;
                    }
                    self.kill(domain, id, &label);
                } else if D::DOMINANCE {
                    if domain.dominates(state, &n.label, n.g, &label, g) {
                        self.stats.pruned_dominance += 1;
                        self.relink_head(domain, state, head, new_head);
                        return;
                    }
                    if domain.dominates(state, &label, g, &n.label, n.g) {
                        self.kill(domain, id, &label);
                        self.stats.pruned_dominance += 1;
                    }
                }
            }
            prev = id;
            id = next;
        }
        self.push_node(domain, state, label, g, parent, action, new_head);
    }

    /// [`Search::insert`] with a class table: the table finds the one label this one
    /// competes with.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn insert_in_class(
        &mut self,
        domain: &D,
        state: D::State,
        label: D::Label,
        key: D::Key,
        head: u32,
        g: f64,
        parent: u32,
        action: Option<D::Action>,
    ) {
        // The class table finds the one label this one competes with.
        let new_id = self.nodes.len();
        match self.classes.entry((state, key)) {
            std::collections::hash_map::Entry::Occupied(mut e) => {
                let (id, old_g) = *e.get();
                self.stats.pruned_resolution += 1;
                let keep_old = old_g < g || (old_g == g && !domain.better(&label, &self.nodes[id].label));
                if keep_old {
                    return;
                }
                // Killed in place: the entry borrows the table.
                self.nodes[id].flags = DEAD;
                self.alive -= 1;
                if self.nodes[id].first_child != NONE && !domain.stands_in_for(state, &label, &self.nodes[id].label) {
                    self.doomed.push(id);
                }
                *e.get_mut() = (new_id, g);
            }
            std::collections::hash_map::Entry::Vacant(e) => {
                e.insert((new_id, g));
            }
        }
        let pushed = self.push_node(domain, state, label, g, parent, action, head);
        debug_assert_eq!(pushed, new_id);
    }

    /// [`Search::insert`] for domains with many labels per state and dominance: the new
    /// label competes with the live labels of its (state, dominance group) only. First
    /// whether anything there beats it (the same class at no greater cost, or a
    /// dominating label); only if it survives does it kill what it beats, so a label
    /// is never lost to one that is itself pruned.
    #[allow(clippy::too_many_arguments)]
    fn insert_in_group(
        &mut self,
        domain: &D,
        state: D::State,
        label: D::Label,
        key: D::Key,
        state_head: u32,
        g: f64,
        parent: u32,
        action: Option<D::Action>,
    ) {
        let group = domain.dominance_group(state, key);
        let head = self.groups.get(domain, state, group);
        let Some(compared) = self.survives_in_group(domain, state, &label, key, g, head) else { return };
        // The second walk below tests the same labels again.
        self.stats.compared += 2 * compared;
        domain.compared(2 * compared);
        // It survives: drop what it beats. The first dropped label that was never
        // expanded gives the new one its node (A*'s decrease-key): most labels are
        // beaten before they are expanded, and each left a dead node behind.
        let (mut prev, mut id, mut new_head, mut reuse) = (NONE, head, head, NONE);
        while id != NONE {
            let next = self.group_next[id as usize];
            let n = &self.nodes[id];
            let drop = if !domain.pareto_classes() && domain.key(state, &n.label) == key {
                self.stats.pruned_resolution += 1;
                true
            } else if domain.dominates(state, &label, g, &n.label, n.g) {
                self.stats.pruned_dominance += 1;
                true
            } else {
                false
            };
            if drop {
                // Not a goal (goal_ids name goals' nodes), and a cost the old node's
                // open-list entry cannot match (see `Entry::matches`), so that entry
                // goes stale.
                if reuse == NONE
                    && n.flags == OPEN
                    && n.first_child == NONE
                    && n.parent != NONE
                    && parent != NONE
                    && (n.g as f32).to_bits() != (g as f32).to_bits()
                {
                    reuse = id;
                } else {
                    self.kill(domain, id, &label);
                }
                if prev == NONE {
                    new_head = next;
                } else {
                    self.group_next[prev as usize] = next;
                }
            } else {
                prev = id;
            }
            id = next;
        }
        let new_id = if reuse == NONE {
            self.push_node(domain, state, label, g, parent, action, state_head)
        } else {
            self.relabel(domain, reuse, label, g, parent, action);
            reuse
        };
        self.group_next[new_id as usize] = new_head;
        self.groups.set(domain, state, group, new_id);
    }

    /// Whether a new label (`label` of class `key` at cost `g`) survives the live labels
    /// of its dominance group from `head`: `Some` with the labels it was compared with,
    /// `None` when one of them beats it (counted).
    #[inline]
    fn survives_in_group(
        &mut self,
        domain: &D,
        state: D::State,
        label: &D::Label,
        key: D::Key,
        g: f64,
        head: u32,
    ) -> Option<u64> {
        let mut id = head;
        let mut compared = 0u64;
        while id != NONE {
            compared += 1;
            let n = &self.nodes[id];
            let beaten = if !domain.pareto_classes() && domain.key(state, &n.label) == key {
                (n.g < g || (n.g == g && !domain.better(label, &n.label))).then_some(&mut self.stats.pruned_resolution)
            } else {
                domain.dominates(state, &n.label, n.g, label, g).then_some(&mut self.stats.pruned_dominance)
            };
            if let Some(count) = beaten {
                *count += 1;
                self.stats.compared += compared;
                domain.compared(compared);
                return None;
            }
            id = self.group_next[id as usize];
        }
        Some(compared)
    }

    /// Takes a removed node out of its dominance group's list (which holds live labels
    /// only).
    fn leave_group(&mut self, domain: &D, id: u32) {
        let state = self.nodes[id].state;
        let key = domain.key(state, &self.nodes[id].label);
        let group = domain.dominance_group(state, key);
        let head = self.groups.get(domain, state, group);
        if head == NONE {
            return;
        }
        let next = self.group_next[id as usize];
        if head == id {
            self.groups.set(domain, state, group, next);
            return;
        }
        let mut c = head;
        while c != NONE {
            let after = self.group_next[c as usize];
            if after == id {
                self.group_next[c as usize] = next;
                return;
            }
            c = after;
        }
    }

    /// Adds a node at the head of its state's list and to the open list.
    #[allow(clippy::too_many_arguments)]
    fn push_node(
        &mut self,
        domain: &D,
        state: D::State,
        label: D::Label,
        g: f64,
        parent: u32,
        action: Option<D::Action>,
        new_head: u32,
    ) -> u32 {
        let h = domain.heuristic(state, &label);
        let new_id = self.nodes.len();
        let first_child = NONE;
        let next_sibling = if parent == NONE { NONE } else { self.nodes[parent].first_child };
        self.nodes.push(Node {
            state,
            label,
            action,
            g,
            parent,
            first_child,
            next_sibling,
            next_in_state: new_head,
            flags: OPEN,
        });
        if parent != NONE {
            self.nodes[parent].first_child = new_id;
        }
        if D::MANY_LABELS && D::DOMINANCE {
            self.group_next.push(NONE);
        }
        self.by_state.set(domain, state, new_id);
        self.open.push(Entry::new(g + h + self.key_offset, g, new_id));
        self.alive += 1;
        self.stats.generated += 1;
        new_id
    }

    /// Gives the open, childless node `id` a better label of its class: new cost, path
    /// and parent (it leaves its old parent's children), and a new open-list entry (the
    /// old one no longer matches, or is taken after the new one and finds it closed).
    fn relabel(&mut self, domain: &D, id: u32, label: D::Label, g: f64, parent: u32, action: Option<D::Action>) {
        let old_parent = self.nodes[id].parent;
        if old_parent != NONE {
            let next = self.nodes[id].next_sibling;
            if self.nodes[old_parent].first_child == id {
                self.nodes[old_parent].first_child = next;
            } else {
                let mut c = self.nodes[old_parent].first_child;
                while c != NONE {
                    if self.nodes[c].next_sibling == id {
                        self.nodes[c].next_sibling = next;
                        break;
                    }
                    c = self.nodes[c].next_sibling;
                }
            }
        }
        let next_sibling = if parent == NONE { NONE } else { self.nodes[parent].first_child };
        let state = self.nodes[id].state;
        let h = domain.heuristic(state, &label);
        let n = &mut self.nodes[id];
        n.label = label;
        n.g = g;
        n.action = action;
        n.parent = parent;
        n.next_sibling = next_sibling;
        if parent != NONE {
            self.nodes[parent].first_child = id;
        }
        self.open.push(Entry::new(g + h + self.key_offset, g, id));
        self.stats.generated += 1;
    }

    /// Drops the node between `prev` (`NONE` at the head) and `next` from a state's
    /// list; the head change, if any, goes to `new_head` (see `relink_head`).
    fn unlink(&mut self, prev: u32, next: u32, new_head: &mut u32) {
        if prev == NONE {
            *new_head = next;
        } else {
            self.nodes[prev].next_in_state = next;
        }
    }

    fn relink_head(&mut self, domain: &D, state: D::State, old_head: u32, new_head: u32) {
        if old_head != new_head {
            self.by_state.set(domain, state, new_head);
        }
    }

    /// Marks `id` beaten by `by` (a label at the same state). An expanded label's
    /// subtree stays only if `by` stands in for it ([`Domain::stands_in_for`]): then
    /// `by`'s own steps beat every label of that subtree as the search reaches them.
    fn kill(&mut self, domain: &D, id: u32, by: &D::Label) {
        let n = &mut self.nodes[id];
        n.flags = DEAD;
        self.alive -= 1;
        if D::MANY_LABELS && n.first_child != NONE && !domain.stands_in_for(n.state, by, &n.label) {
            self.doomed.push(id);
        }
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
            path.push(PathStep { state: n.state, label: n.label.clone(), action: n.action, cost_so_far: total - n.g });
            id = n.parent;
        }
        Plan { path: Some(path), cost: total, stats: self.stats, stopped: false }
    }
}
