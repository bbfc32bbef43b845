//! The node store behind a search: values in fixed-size chunks, addressed by `u32`.

/// The node store: fixed-size chunks, so growing never copies and never holds twice
/// the memory it needs (a doubling `Vec` does, just after it grows).
pub(crate) struct Arena<T> {
    chunks: Vec<Vec<T>>,
    len: u32,
}

const CHUNK_BITS: u32 = 12;
const CHUNK: usize = 1 << CHUNK_BITS;

impl<T> Arena<T> {
    pub(crate) fn new() -> Arena<T> {
        Arena { chunks: Vec::new(), len: 0 }
    }
    pub(crate) fn len(&self) -> u32 {
        self.len
    }
    pub(crate) fn push(&mut self, value: T) -> u32 {
        if (self.len as usize).is_multiple_of(CHUNK) {
            self.chunks.push(Vec::with_capacity(CHUNK));
        }
        if let Some(last) = self.chunks.last_mut() {
            last.push(value);
        }
        self.len += 1;
        self.len - 1
    }
    pub(crate) fn bytes(&self) -> u64 {
        (self.chunks.len() * CHUNK * std::mem::size_of::<T>() + self.chunks.capacity() * std::mem::size_of::<Vec<T>>())
            as u64
    }
    /// Swaps two values (`a` < `b`).
    pub(crate) fn swap(&mut self, a: u32, b: u32) {
        let (ca, ia) = ((a >> CHUNK_BITS) as usize, a as usize & (CHUNK - 1));
        let (cb, ib) = ((b >> CHUNK_BITS) as usize, b as usize & (CHUNK - 1));
        if ca == cb {
            self.chunks[ca].swap(ia, ib);
        } else {
            let (lo, hi) = self.chunks.split_at_mut(cb);
            std::mem::swap(&mut lo[ca][ia], &mut hi[0][ib]);
        }
    }
    /// Drops every value from index `len` on, and the chunks left empty.
    pub(crate) fn truncate(&mut self, len: u32) {
        let chunks = (len as usize).div_ceil(CHUNK);
        self.chunks.truncate(chunks);
        if let Some(last) = self.chunks.last_mut() {
            last.truncate(len as usize - (chunks - 1) * CHUNK);
        }
        self.chunks.shrink_to_fit();
        self.len = len;
    }
}

impl<T> std::ops::Index<u32> for Arena<T> {
    type Output = T;
    #[inline]
    fn index(&self, id: u32) -> &T {
        &self.chunks[(id >> CHUNK_BITS) as usize][id as usize & (CHUNK - 1)]
    }
}

impl<T> std::ops::IndexMut<u32> for Arena<T> {
    #[inline]
    fn index_mut(&mut self, id: u32) -> &mut T {
        &mut self.chunks[(id >> CHUNK_BITS) as usize][id as usize & (CHUNK - 1)]
    }
}
