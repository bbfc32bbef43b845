//! Sizes, offsets and counts read from files and flags, in arithmetic that cannot wrap:
//! a [`Size`] that overflows stays overflowed through every later sum and product, and
//! says so only where it is used (as a byte count, an allocation, an index), so a
//! computation reads as the formula it is.

use std::ops::{Add, Mul};

/// A non-negative count (bytes, samples, cells), or the fact that computing it
/// overflowed 64 bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Size(Option<u64>);

impl Size {
    /// A count.
    pub const fn new(n: u64) -> Size {
        Size(Some(n))
    }

    /// A count given as a float read from a text file: a whole number in `0..=max`, or
    /// `None`.
    pub fn whole(value: f64, max: u64) -> Option<Size> {
        (value >= 0.0 && value <= max as f64 && value.fract() == 0.0).then_some(Size::new(value as u64))
    }

    /// The count, or `None` if it overflowed.
    pub fn get(self) -> Option<u64> {
        self.0
    }

    /// The count as a `usize` (an index or an allocation), or `None` if it overflowed
    /// or does not fit.
    pub fn as_usize(self) -> Option<usize> {
        self.0.and_then(|n| usize::try_from(n).ok())
    }

    /// Whether the count is at most `limit` (an overflowed count never is).
    pub fn at_most(self, limit: u64) -> bool {
        self.0.is_some_and(|n| n <= limit)
    }
}

impl From<usize> for Size {
    fn from(n: usize) -> Size {
        Size(u64::try_from(n).ok())
    }
}

impl From<u64> for Size {
    fn from(n: u64) -> Size {
        Size::new(n)
    }
}

impl Add for Size {
    type Output = Size;
    fn add(self, o: Size) -> Size {
        Size(self.0.zip(o.0).and_then(|(a, b)| a.checked_add(b)))
    }
}

impl Mul for Size {
    type Output = Size;
    fn mul(self, o: Size) -> Size {
        Size(self.0.zip(o.0).and_then(|(a, b)| a.checked_mul(b)))
    }
}

impl std::fmt::Display for Size {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0 {
            Some(n) => write!(f, "{n}"),
            None => write!(f, "more than 2^64"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overflow_sticks_through_later_arithmetic() {
        let lines = Size::new(4_000_000_000);
        let line_bytes = Size::new(1 << 40) + Size::new(1 << 40) + Size::new(32_000_000_000);
        // 4e9 × 2.2e12 = 8.8e21 > 2^64: the product a size check once wrapped to a small
        // number.
        let needed = Size::new(1 << 40) + lines * line_bytes;
        assert_eq!(needed.get(), None);
        assert!(!needed.at_most(u64::MAX));
        assert_eq!((needed + Size::new(1)).get(), None);
        assert_eq!(needed.to_string(), "more than 2^64");
        assert_eq!((Size::new(3) * Size::new(4) + Size::new(5)).get(), Some(17));
        assert!(Size::new(17).at_most(17) && !Size::new(18).at_most(17));
        assert_eq!(Size::whole(12.0, 100), Some(Size::new(12)));
        for bad in [-1.0, 12.5, 101.0, f64::NAN, f64::INFINITY] {
            assert_eq!(Size::whole(bad, 100), None, "{bad}");
        }
    }
}
