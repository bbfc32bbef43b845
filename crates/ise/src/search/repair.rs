//! Repairing a search graph after the world or the goals changed: removing the
//! subtrees a change invalidated and reopening the closed labels that can regenerate
//! what they held ([`Search::update`], [`Search::set_goals`], [`Search::restrict`]),
//! and compacting the graph once removed labels outnumber live ones.

use super::*;

impl<D: Domain> Search<D> {
    /// Removes the subtrees under `roots` (the nodes and everything whose path passes
    /// through them) and reopens the surviving closed nodes that can regenerate labels
    /// at the states in `whole` (any class: their transitions changed) and in the
    /// classes of what was removed, or reach them more cheaply now.
    pub(super) fn repair(&mut self, domain: &D, roots: Vec<u32>, whole: Vec<D::State>) {
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
    pub(super) fn remove_subtrees(
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
    pub(super) fn closed_near(
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

    pub(super) fn compact_if_worth_it(&mut self, domain: &D) {
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
    pub(super) fn remove_doomed(&mut self, domain: &D) {
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
    pub(super) fn insert_goal(&mut self, domain: &D, goal: Goal<D>) {
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
    pub(super) fn worth_compacting(&self) -> bool {
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
    pub(super) fn relink(&mut self, domain: &D, kept: u32, remap: &[u32]) {
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
}
