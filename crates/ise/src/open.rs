//! The open list: a monotone radix heap on f, with a binary heap beside it for keys
//! below the radix heap's last.
//!
//! Best-first search with a consistent heuristic takes f in non-decreasing order, which
//! a radix heap serves in O(1) amortised per operation, far faster than a binary heap
//! on large searches. Among equal keys it returns the newest entry, which favours the
//! deeper nodes. Two things make this radix heap ours rather than the `radix-heap`
//! crate's (measured on Moving AI grids, where the open list was a fifth of the search):
//!
//! - buckets by base-256 digits rather than bits (see [`DIGIT_BITS`]), and a bit mask
//!   of the non-empty ones (the crate walks all 65 buckets on every pop that empties
//!   the smallest);
//! - the key is f without its 12 lowest mantissa bits (f to a relative 2⁻⁴⁰ ≈ 1e-12):
//!   sums like g + c + h reach equal values with different roundings, and on the full
//!   bits each rounding was a key of its own, with a refill to reach it. Entries whose
//!   f differ by less than that resolution come out newest first rather than in f
//!   order; no plan's cost is affected beyond it.
//!
//! Entries below the radix heap's last key (inconsistent heuristics, reopened nodes in
//! re-planning) go to the binary heap, which orders them exactly, and each pop takes
//! the smaller of the two.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// An open-list entry packed into one integer so the heap compares with a single
/// instruction: f (non-negative, so its IEEE bits order like the value), then larger
/// g first, then the older node (the binary heap's order).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Entry(Reverse<u128>);

impl Entry {
    #[inline]
    pub(crate) fn new(f: f64, g: f64, id: u32) -> Entry {
        let f_bits = f.max(0.0).to_bits() as u128;
        let tie = !(g as f32).to_bits() as u128;
        Entry(Reverse((f_bits << 64) | (tie << 32) | u128::from(id)))
    }
    #[inline]
    fn f_bits(self) -> u64 {
        (self.0.0 >> 64) as u64
    }
    #[inline]
    pub(crate) fn f(self) -> f64 {
        f64::from_bits(self.f_bits())
    }
    #[inline]
    fn g_bits(self) -> u32 {
        !((self.0.0 >> 32) as u32)
    }
    #[inline]
    pub(crate) fn id(self) -> u32 {
        self.0.0 as u32
    }
    /// f without its lowest mantissa bits: the radix heap's key.
    #[inline]
    fn coarse(self) -> u64 {
        self.f_bits() >> COARSE_SHIFT
    }
    /// Whether this entry still describes the node's current cost.
    #[inline]
    pub(crate) fn matches(self, g: f64) -> bool {
        (g as f32).to_bits() == self.g_bits()
    }
}

/// The largest allocation a bucket keeps when it is emptied, entries.
const KEPT_CAPACITY: usize = 1 << 8;

/// Mantissa bits below the radix heap's key.
const COARSE_SHIFT: u32 = 12;

/// Bits per digit of the radix heap: its buckets split keys by base-256 digits, so an
/// entry moves down a level per refill that takes it, eight bits at a time. With binary
/// digits entries moved 3.7 times each on the way out of a grid search and the refills
/// were the open list's largest cost; base 16 took 4.6 % fewer instructions from the
/// whole search, base 256 7.4 % (1793 buckets, a 29-word mask of the non-empty ones).
const DIGIT_BITS: u32 = 8;
const RADIX: usize = 1 << DIGIT_BITS;
const LEVELS: usize = (64 - COARSE_SHIFT).div_ceil(DIGIT_BITS) as usize;

/// Bucket 0 holds the entries whose key equals the last one taken (a stack: newest
/// first); bucket `1 + RADIX·level + digit` those whose highest digit differing from it
/// is `level`, where theirs is `digit` (greater than its). Bucket order is key order.
const BUCKETS: usize = 1 + LEVELS * RADIX;
const MASK_WORDS: usize = BUCKETS.div_ceil(64);

#[inline]
fn bucket_of(coarse: u64, least: u64) -> usize {
    let x = coarse ^ least;
    if x == 0 {
        return 0;
    }
    let level = (63 - x.leading_zeros()) / DIGIT_BITS;
    let digit = (coarse >> (level * DIGIT_BITS)) as usize & (RADIX - 1);
    1 + level as usize * RADIX + digit
}

/// The open list.
pub(crate) struct OpenList {
    /// The last key taken: every entry in a bucket has one at least as great.
    least: u64,
    /// Bit b set when `buckets[b]` is non-empty.
    nonempty: [u64; MASK_WORDS],
    buckets: Box<[Vec<Entry>; BUCKETS]>,
    /// The entries whose key is below `least`, in exact order.
    below: BinaryHeap<Entry>,
    /// Entries held.
    len: usize,
}

impl OpenList {
    pub(crate) fn new() -> OpenList {
        OpenList {
            least: 0,
            nonempty: [0; MASK_WORDS],
            buckets: Box::new(std::array::from_fn(|_| Vec::new())),
            below: BinaryHeap::new(),
            len: 0,
        }
    }

    /// Entries held, stale ones included.
    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// Drops the entries `keep` rejects, and the memory they held. The others keep
    /// their buckets and their order, so what comes out next is unchanged.
    pub(crate) fn retain(&mut self, mut keep: impl FnMut(Entry) -> bool) {
        for b in 0..BUCKETS {
            let bucket = &mut self.buckets[b];
            bucket.retain(|&e| keep(e));
            bucket.shrink_to_fit();
            if bucket.is_empty() {
                self.unmark(b);
            }
        }
        self.below.retain(|&e| keep(e));
        self.below.shrink_to_fit();
        self.len = self.below.len() + self.buckets.iter().map(Vec::len).sum::<usize>();
    }

    #[inline]
    fn mark(&mut self, b: usize) {
        self.nonempty[b / 64] |= 1 << (b % 64);
    }

    #[inline]
    fn unmark(&mut self, b: usize) {
        self.nonempty[b / 64] &= !(1 << (b % 64));
    }

    /// The lowest non-empty bucket.
    #[inline]
    fn lowest(&self) -> Option<usize> {
        self.nonempty.iter().enumerate().find(|(_, w)| **w != 0).map(|(i, w)| i * 64 + w.trailing_zeros() as usize)
    }

    pub(crate) fn from_vec(entries: Vec<Entry>) -> OpenList {
        let mut open = OpenList::new();
        for e in entries {
            open.push(e);
        }
        open
    }

    pub(crate) fn into_vec(self) -> Vec<Entry> {
        let mut v = self.below.into_vec();
        v.extend(self.buckets.into_iter().flatten());
        v
    }

    #[inline]
    pub(crate) fn push(&mut self, e: Entry) {
        self.len += 1;
        let coarse = e.coarse();
        if coarse < self.least {
            self.below.push(e);
        } else {
            let b = bucket_of(coarse, self.least);
            self.buckets[b].push(e);
            self.mark(b);
        }
    }

    #[inline]
    pub(crate) fn pop(&mut self) -> Option<Entry> {
        if self.nonempty[0] & 1 == 0 {
            self.refill();
        }
        let top = self.buckets[0].last().copied();
        self.len -= usize::from(top.is_some() || !self.below.is_empty());
        match (top, self.below.peek()) {
            (Some(r), Some(b)) if b.f() < r.f() => self.below.pop(),
            (Some(_), _) => {
                let r = self.buckets[0].pop();
                if self.buckets[0].is_empty() {
                    self.unmark(0);
                }
                r
            }
            (None, _) => self.below.pop(),
        }
    }

    /// Bucket 0 is empty: the least key of the lowest non-empty bucket becomes the last
    /// taken, and that bucket's entries move down to buckets measured from it (each to a
    /// lower level than it left: they share its digit there with the new key). Entries
    /// of other buckets keep theirs: their highest digit differing from the new key, and
    /// their digit there, are what they were.
    #[cold]
    fn refill(&mut self) {
        let Some(b) = self.lowest() else { return };
        self.unmark(b);
        let mut from = std::mem::take(&mut self.buckets[b]);
        let least = from.iter().map(|e| e.coarse()).min().unwrap_or(self.least);
        self.least = least;
        for &e in &from {
            let to = bucket_of(e.coarse(), least);
            self.buckets[to].push(e);
            self.mark(to);
        }
        // Keep a small allocation for the entries that will come back to this bucket;
        // free a large one — every bucket keeping its largest fill held several times
        // the open list's size (18 MB for 26 000 entries on the lunar plan).
        if from.capacity() <= KEPT_CAPACITY {
            from.clear();
            self.buckets[b] = from;
        }
    }

    pub(crate) fn bytes(&self) -> u64 {
        let cap: usize = self.buckets.iter().map(Vec::capacity).sum::<usize>() + self.below.capacity();
        (cap * std::mem::size_of::<Entry>() + std::mem::size_of::<[Vec<Entry>; BUCKETS]>()) as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// splitmix64: a seeded stream for the test without a dependency.
    struct Stream(u64);
    impl Stream {
        fn next(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }
        fn below(&mut self, n: u64) -> u64 {
            self.next() % n
        }
    }

    /// Pops against a reference list: `monotone` pushes are never below the last f
    /// popped (then entries of equal f must come out newest first); otherwise some are
    /// (reopened nodes), and only the f order is checked. Every 997 rounds a third of
    /// the entries are dropped (`retain`), which must leave the others' order as it was.
    fn check_against_reference(monotone: bool) {
        let mut rng = Stream(7);
        let mut open = OpenList::new();
        let mut reference: Vec<Entry> = Vec::new();
        let mut last = 0.0f64;
        for round in 0..20_000u32 {
            assert_eq!(open.len(), reference.len(), "round {round}");
            if round % 997 == 996 {
                let keep = |e: Entry| e.id() % 3 != round % 3;
                open.retain(keep);
                reference.retain(|&e| keep(e));
                assert_eq!(open.len(), reference.len(), "round {round}");
            }
            if rng.below(100) < 55 || reference.is_empty() {
                let f = match rng.below(10) {
                    0..=2 => last,
                    3 if !monotone => (last - rng.below(1000) as f64 * 1e-3).max(0.0),
                    4 => last + rng.below(1 << 20) as f64,
                    _ => last + rng.below(3000) as f64 * 1e-3 * std::f64::consts::SQRT_2,
                };
                let g = rng.below(5000) as f64 * 0.5;
                let e = Entry::new(f, g, round);
                open.push(e);
                reference.push(e);
            } else {
                let got = open.pop().map_or((f64::NAN, u32::MAX), |e| (e.f(), e.id()));
                let least = reference.iter().map(|e| e.f()).fold(f64::INFINITY, f64::min);
                assert_eq!(got.0, least, "round {round}");
                if monotone {
                    // Of the entries with the least f, the one pushed last (ids grow).
                    let newest = reference.iter().filter(|e| e.f() == least).map(|e| e.id()).max();
                    assert_eq!(Some(got.1), newest, "round {round}");
                }
                reference.retain(|e| e.id() != got.1);
                last = least;
            }
        }
        assert_eq!(reference.len(), std::iter::from_fn(|| open.pop()).count());
    }

    #[test]
    fn open_list_pops_newest_first_among_equal_f_when_keys_never_fall() {
        check_against_reference(true);
    }

    #[test]
    fn open_list_pops_in_f_order_with_keys_below_the_last() {
        check_against_reference(false);
    }
}
