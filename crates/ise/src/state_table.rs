//! State → the first search node at that state.

use rustc_hash::FxHashMap;

use crate::domain::Domain;
use crate::search::NONE;

/// Cells per page of the dense state table.
const PAGE: usize = 1 << 10;

/// State → first node at that state. Dense domains get pages allocated on first touch
/// (memory ∝ the part of the space searched); others a hash table.
pub(crate) enum StateTable<D: Domain> {
    Undecided,
    Paged(Vec<Option<Box<[u32; PAGE]>>>),
    Hashed(FxHashMap<D::State, u32>),
}

impl<D: Domain> StateTable<D> {
    pub(crate) fn new() -> StateTable<D> {
        StateTable::Undecided
    }

    #[inline(always)]
    pub(crate) fn get(&self, domain: &D, state: D::State) -> u32 {
        // The paged table first: it is the hot case, and one test of the variant.
        if let StateTable::Paged(pages) = self {
            let i = domain.dense_index(state).map_or(usize::MAX, |i| i as usize);
            return pages.get(i / PAGE).and_then(|p| p.as_deref()).map_or(NONE, |p| p[i % PAGE]);
        }
        match self {
            StateTable::Hashed(map) => map.get(&state).copied().unwrap_or(NONE),
            _ => NONE,
        }
    }

    #[inline(always)]
    pub(crate) fn set(&mut self, domain: &D, state: D::State, head: u32) {
        if let StateTable::Paged(pages) = self
            && let Some(i) = domain.dense_index(state)
            && let Some(Some(page)) = pages.get_mut(i as usize / PAGE)
        {
            page[i as usize % PAGE] = head;
            return;
        }
        self.set_slow(domain, state, head);
    }

    #[inline(never)]
    pub(crate) fn set_slow(&mut self, domain: &D, state: D::State, head: u32) {
        if let StateTable::Undecided = self {
            *self = if domain.dense_index(state).is_some() {
                StateTable::Paged(Vec::new())
            } else {
                StateTable::Hashed(FxHashMap::default())
            };
        }
        match self {
            StateTable::Undecided => {}
            StateTable::Paged(pages) => {
                let Some(i) = domain.dense_index(state) else { return };
                let (page, slot) = (i as usize / PAGE, i as usize % PAGE);
                if pages.len() <= page {
                    pages.resize_with(page + 1, || None);
                }
                pages[page].get_or_insert_with(|| Box::new([NONE; PAGE]))[slot] = head;
            }
            StateTable::Hashed(map) => {
                if head == NONE {
                    map.remove(&state);
                } else {
                    map.insert(state, head);
                }
            }
        }
    }

    pub(crate) fn bytes(&self) -> u64 {
        match self {
            StateTable::Undecided => 0,
            StateTable::Paged(pages) => {
                let used = pages.iter().filter(|p| p.is_some()).count();
                (pages.capacity() * std::mem::size_of::<Option<Box<[u32; PAGE]>>>() + used * PAGE * 4) as u64
            }
            StateTable::Hashed(map) => (map.capacity() * (std::mem::size_of::<(D::State, u32)>() + 1)) as u64,
        }
    }
}
