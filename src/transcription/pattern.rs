//! Sparsity patterns built once: triplets with duplicates merged, and each block's map from
//! its dense local entries to positions in the value arrays.

use std::collections::HashMap;

/// A growing set of (row, col) triplets; asking for an entry twice returns the same slot.
#[derive(Debug, Default)]
pub struct PatternBuilder {
    slots: HashMap<(usize, usize), usize>,
    rows: Vec<usize>,
    cols: Vec<usize>,
}

impl PatternBuilder {
    /// Slot of entry (row, col), created on first use.
    pub fn slot(&mut self, row: usize, col: usize) -> usize {
        let next = self.rows.len();
        *self.slots.entry((row, col)).or_insert_with(|| {
            self.rows.push(row);
            self.cols.push(col);
            next
        })
    }

    /// Slot of the lower-triangle entry of the symmetric pair (a, b).
    pub fn lower_slot(&mut self, a: usize, b: usize) -> usize {
        self.slot(a.max(b), a.min(b))
    }

    /// The finished pattern.
    pub fn finish(self) -> Pattern {
        Pattern {
            rows: self.rows,
            cols: self.cols,
        }
    }
}

/// Zero-based (row, col) triplets in value order.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Pattern {
    /// Row of each nonzero.
    pub rows: Vec<usize>,
    /// Column of each nonzero.
    pub cols: Vec<usize>,
}

impl Pattern {
    /// Number of nonzeros.
    pub fn nnz(&self) -> usize {
        self.rows.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeated_entries_share_a_slot_and_lower_slots_are_symmetric() {
        let mut b = PatternBuilder::default();
        assert_eq!(b.slot(2, 3), 0);
        assert_eq!(b.slot(1, 1), 1);
        assert_eq!(b.slot(2, 3), 0);
        assert_eq!(b.lower_slot(3, 5), b.lower_slot(5, 3));
        let p = b.finish();
        assert_eq!(p.nnz(), 3);
        assert_eq!((p.rows[2], p.cols[2]), (5, 3));
    }
}
