//! Admitting a label at a state: the global constraint, its resolution class or
//! dominance group decide whether it stays and what it replaces.

use super::*;

impl<D: Domain> Search<D> {
    /// Adds a label unless the global constraint, its resolution class or dominance
    /// rejects it; replaces what it beats.
    #[inline(always)]
    pub(super) fn insert(
        &mut self,
        domain: &D,
        state: D::State,
        label: D::Label,
        g: f64,
        parent: u32,
        via: Option<D::Move>,
    ) {
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
            self.push_node(domain, state, label, g, parent, via, NONE);
            return;
        }
        self.insert_slow(domain, state, label, key, head, g, parent, via);
    }

    /// The rest of [`Search::insert`]: the class table, or a walk over the state's labels.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    pub(super) fn insert_slow(
        &mut self,
        domain: &D,
        state: D::State,
        label: D::Label,
        key: D::Key,
        head: u32,
        g: f64,
        parent: u32,
        via: Option<D::Move>,
    ) {
        if D::MANY_LABELS && D::DOMINANCE {
            self.insert_in_group(domain, state, label, key, head, g, parent, via);
            return;
        }
        if D::MANY_LABELS && !D::DOMINANCE {
            self.insert_in_class(domain, state, label, key, head, g, parent, via);
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
                        self.relabel(domain, id, label, g, parent, via);
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
        self.push_node(domain, state, label, g, parent, via, new_head);
    }

    /// [`Search::insert`] with a class table: the table finds the one label this one
    /// competes with.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub(super) fn insert_in_class(
        &mut self,
        domain: &D,
        state: D::State,
        label: D::Label,
        key: D::Key,
        head: u32,
        g: f64,
        parent: u32,
        via: Option<D::Move>,
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
        let pushed = self.push_node(domain, state, label, g, parent, via, head);
        debug_assert_eq!(pushed, new_id);
    }

    /// [`Search::insert`] for domains with many labels per state and dominance: the new
    /// label competes with the live labels of its (state, dominance group) only. First
    /// whether anything there beats it (the same class at no greater cost, or a
    /// dominating label); only if it survives does it kill what it beats, so a label
    /// is never lost to one that is itself pruned.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn insert_in_group(
        &mut self,
        domain: &D,
        state: D::State,
        label: D::Label,
        key: D::Key,
        state_head: u32,
        g: f64,
        parent: u32,
        via: Option<D::Move>,
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
            self.push_node(domain, state, label, g, parent, via, state_head)
        } else {
            self.relabel(domain, reuse, label, g, parent, via);
            reuse
        };
        self.group_next[new_id as usize] = new_head;
        self.groups.set(domain, state, group, new_id);
    }

    /// Whether a new label (`label` of class `key` at cost `g`) survives the live labels
    /// of its dominance group from `head`: `Some` with the labels it was compared with,
    /// `None` when one of them beats it (counted).
    #[inline]
    pub(super) fn survives_in_group(
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
    pub(super) fn leave_group(&mut self, domain: &D, id: u32) {
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
    pub(super) fn push_node(
        &mut self,
        domain: &D,
        state: D::State,
        label: D::Label,
        g: f64,
        parent: u32,
        via: Option<D::Move>,
        new_head: u32,
    ) -> u32 {
        let h = domain.heuristic(state, &label);
        let new_id = self.nodes.len();
        let first_child = NONE;
        let next_sibling = if parent == NONE { NONE } else { self.nodes[parent].first_child };
        self.nodes.push(Node {
            state,
            label,
            via,
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
    pub(super) fn relabel(&mut self, domain: &D, id: u32, label: D::Label, g: f64, parent: u32, via: Option<D::Move>) {
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
        n.via = via;
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
    pub(super) fn unlink(&mut self, prev: u32, next: u32, new_head: &mut u32) {
        if prev == NONE {
            *new_head = next;
        } else {
            self.nodes[prev].next_in_state = next;
        }
    }

    pub(super) fn relink_head(&mut self, domain: &D, state: D::State, old_head: u32, new_head: u32) {
        if old_head != new_head {
            self.by_state.set(domain, state, new_head);
        }
    }

    /// Marks `id` beaten by `by` (a label at the same state). An expanded label's
    /// subtree stays only if `by` stands in for it ([`Domain::stands_in_for`]): then
    /// `by`'s own steps beat every label of that subtree as the search reaches them.
    pub(super) fn kill(&mut self, domain: &D, id: u32, by: &D::Label) {
        let n = &mut self.nodes[id];
        n.flags = DEAD;
        self.alive -= 1;
        if D::MANY_LABELS && n.first_child != NONE && !domain.stands_in_for(n.state, by, &n.label) {
            self.doomed.push(id);
        }
    }
}
