//! Sparse matrices built from their entries, column by column.
//!
//! faer's `try_new_from_triplets` sorts every entry of the matrix to find its columns and
//! repeats: on a 45k-face disk that sort was a third of the harmonic map's solve and most of the
//! LSCM assembly. Here the entries are bucketed by column with a counting sort (one pass to
//! count, one to place, O(entries)), then each column's handful of rows is sorted and repeats
//! are summed. Same matrix, same order of summation within a column's repeated entry.

use faer::sparse::{SparseColMat, SymbolicSparseColMat};

/// The `n × n` matrix whose entry `(row, col)` is the sum of the values given for it.
/// Entries out of range are a bug (checked by faer's constructor).
pub fn from_entries(n: usize, entries: &[(u32, u32, f64)]) -> SparseColMat<usize, f64> {
    let mut start = vec![0usize; n + 1];
    for &(_, col, _) in entries {
        start[col as usize + 1] += 1;
    }
    for c in 0..n {
        start[c + 1] += start[c];
    }
    let mut next = start.clone();
    let mut bucket = vec![(0u32, 0.0f64); entries.len()];
    for &(row, col, value) in entries {
        let slot = &mut next[col as usize];
        bucket[*slot] = (row, value);
        *slot += 1;
    }
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx: Vec<usize> = Vec::with_capacity(entries.len());
    let mut values: Vec<f64> = Vec::with_capacity(entries.len());
    col_ptr.push(0usize);
    for c in 0..n {
        let column = &mut bucket[start[c]..start[c + 1]];
        column.sort_by_key(|e| e.0);
        let first = row_idx.len();
        for &(row, value) in column.iter() {
            let row = row as usize;
            match row_idx.last() {
                Some(&last) if row_idx.len() > first && last == row => {
                    *values.last_mut().expect("a value per row") += value;
                }
                _ => {
                    row_idx.push(row);
                    values.push(value);
                }
            }
        }
        col_ptr.push(row_idx.len());
    }
    SparseColMat::new(
        SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx),
        values,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeats_are_summed_and_every_entry_lands_in_its_place() {
        let entries = [
            (2, 0, 1.0),
            (0, 0, 4.0),
            (2, 0, 0.5),
            (1, 1, 3.0),
            (0, 2, -1.0),
            (2, 2, 2.0),
            (0, 0, 1.0),
        ];
        let m = from_entries(3, &entries);
        let dense = m.to_dense();
        let expected = [[5.0, 0.0, -1.0], [0.0, 3.0, 0.0], [1.5, 0.0, 2.0]];
        for (r, row) in expected.iter().enumerate() {
            for (c, &x) in row.iter().enumerate() {
                assert_eq!(dense[(r, c)], x, "({r}, {c})");
            }
        }
        assert_eq!(m.compute_nnz(), 5);
    }
}
