//! (state, dominance group) → the newest live label of the group.
//!
//! A time-expanded domain has about one dominance group per label it keeps (a cell in
//! one time class holds one or two Pareto labels), so this table is as large as the
//! node arena. A hash table keyed by (state, group) spent 41 bytes per slot at two
//! thirds load — 600 MB on the 10 m lunar plan. Here dense domains keep, per state, a
//! short vector of (group, head) sorted by group: 16 bytes per group in TEMPEST, and
//! the groups of one cell sit together, so a lookup reads one or two cache lines.

use rustc_hash::FxHashMap;

use crate::domain::Domain;
use crate::search::NONE;

/// States per page of the dense table.
const PAGE: usize = 1 << 10;

/// The groups of one state, sorted by group.
type Heads<K> = Vec<(K, u32)>;

/// The groups of `PAGE` consecutive states, allocated when one of them is first set.
type Page<K> = Option<Box<[Heads<K>]>>;

pub(crate) enum GroupTable<D: Domain> {
    Undecided,
    /// `held`: the heads' capacities summed, and the pages allocated (kept as they
    /// change, so that reporting memory does not walk every page).
    Paged {
        pages: Vec<Page<D::Key>>,
        held: usize,
        allocated: usize,
    },
    Hashed(FxHashMap<(D::State, D::Key), u32>),
}

impl<D: Domain> GroupTable<D> {
    pub(crate) fn new() -> GroupTable<D> {
        GroupTable::Undecided
    }

    /// The head of `group` at `state`, or `NONE`.
    #[inline]
    pub(crate) fn get(&self, domain: &D, state: D::State, group: D::Key) -> u32 {
        match self {
            GroupTable::Paged { pages, .. } => {
                let Some(i) = domain.dense_index(state) else { return NONE };
                let i = i as usize;
                let Some(Some(page)) = pages.get(i / PAGE) else { return NONE };
                let heads = &page[i % PAGE];
                heads.binary_search_by(|(g, _)| g.cmp(&group)).map_or(NONE, |k| heads[k].1)
            }
            GroupTable::Hashed(map) => map.get(&(state, group)).copied().unwrap_or(NONE),
            GroupTable::Undecided => NONE,
        }
    }

    /// Makes `id` the head of `group` at `state`; `NONE` removes the group.
    pub(crate) fn set(&mut self, domain: &D, state: D::State, group: D::Key, id: u32) {
        if let GroupTable::Undecided = self {
            *self = if domain.dense_index(state).is_some() {
                GroupTable::Paged { pages: Vec::new(), held: 0, allocated: 0 }
            } else {
                GroupTable::Hashed(FxHashMap::default())
            };
        }
        match self {
            GroupTable::Paged { pages, held, allocated } => {
                let Some(i) = domain.dense_index(state) else { return };
                let (page, slot) = (i as usize / PAGE, i as usize % PAGE);
                if pages.len() <= page {
                    pages.resize_with(page + 1, || None);
                }
                let heads = &mut pages[page].get_or_insert_with(|| {
                    *allocated += 1;
                    (0..PAGE).map(|_| Vec::new()).collect()
                })[slot];
                let before = heads.capacity();
                match heads.binary_search_by(|(g, _)| g.cmp(&group)) {
                    Ok(k) if id == NONE => {
                        heads.remove(k);
                    }
                    Ok(k) => heads[k].1 = id,
                    Err(_) if id == NONE => {}
                    Err(k) => {
                        // Grow by half, not double: most cells stop at a few dozen groups.
                        if heads.len() == heads.capacity() {
                            heads.reserve_exact((heads.len() / 2).max(4));
                        }
                        heads.insert(k, (group, id));
                    }
                }
                *held = *held + heads.capacity() - before;
            }
            GroupTable::Hashed(map) => {
                if id == NONE {
                    map.remove(&(state, group));
                } else {
                    map.insert((state, group), id);
                }
            }
            GroupTable::Undecided => {}
        }
    }

    pub(crate) fn clear(&mut self) {
        *self = GroupTable::Undecided;
    }

    /// Bytes held (approximate).
    pub(crate) fn bytes(&self) -> u64 {
        match self {
            GroupTable::Undecided => 0,
            GroupTable::Paged { pages, held, allocated } => {
                let entry = std::mem::size_of::<(D::Key, u32)>();
                (held * entry + allocated * PAGE * std::mem::size_of::<Heads<D::Key>>() + pages.capacity() * 8) as u64
            }
            GroupTable::Hashed(map) => (map.capacity() * (std::mem::size_of::<((D::State, D::Key), u32)>() + 1)) as u64,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::domain::Predecessor;

    /// States without transitions: only their index matters here.
    struct Cells {
        dense: bool,
    }

    impl Domain for Cells {
        type State = u32;
        type Label = ();
        type Key = i64;
        type Move = u8;
        fn expand(&self, _: u32, _: &(), _: impl Fn(u8) -> bool, _: impl FnMut(u8, Predecessor<Self>)) {}
        fn successors(&self, _: u32, _: &mut Vec<u32>) {}
        fn key(&self, _: u32, _: &()) -> i64 {
            0
        }
        fn is_start(&self, _: u32, _: &()) -> bool {
            false
        }
        fn heuristic(&self, _: u32, _: &()) -> f64 {
            0.0
        }
        fn dense_index(&self, state: u32) -> Option<u32> {
            self.dense.then_some(state)
        }
    }

    /// Random sets, replacements and removals against a hash map, in both layouts
    /// (states spread over several pages; groups inserted out of order).
    #[test]
    fn the_group_table_answers_as_a_hash_map_does() {
        for dense in [true, false] {
            let domain = Cells { dense };
            let mut table = GroupTable::<Cells>::new();
            let mut reference: FxHashMap<(u32, i64), u32> = FxHashMap::default();
            let mut x = 12345u64;
            for round in 0..40_000u32 {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                let state = ((x >> 33) % 3000) as u32 * 7;
                let group = ((x >> 20) % 40) as i64 * 16 - 100;
                let id = if (x >> 10).is_multiple_of(4) { NONE } else { round };
                table.set(&domain, state, group, id);
                if id == NONE {
                    reference.remove(&(state, group));
                } else {
                    reference.insert((state, group), id);
                }
                let probe = ((x >> 40) % 3000) as u32 * 7;
                assert_eq!(
                    table.get(&domain, probe, group),
                    reference.get(&(probe, group)).copied().unwrap_or(NONE),
                    "round {round}, dense {dense}"
                );
            }
            for (&(state, group), &id) in &reference {
                assert_eq!(table.get(&domain, state, group), id);
            }
            assert!(table.bytes() > 0);
            if let GroupTable::Paged { pages, held, allocated } = &table {
                // The kept counts equal a walk over the pages.
                let walked: usize = pages.iter().flatten().map(|p| p.iter().map(Vec::capacity).sum::<usize>()).sum();
                assert_eq!(*held, walked);
                assert_eq!(*allocated, pages.iter().flatten().count());
            }
            table.clear();
            assert_eq!(table.get(&domain, 7, 0), NONE);
        }
    }
}
