//! [`BlockCsc`]: the reduced system `S`'s lower triangle as a
//! compressed-column matrix laid out by blocks.
//!
//! Block column `v` holds its diagonal block's lower triangle and then, in
//! increasing order, the blocks `(u, v)`, `u > v`, of the blocks that share
//! a factor or an eliminated variable with `v`. Every scalar column of a
//! block column has the same rows below the diagonal block, so an entry's
//! index is computed, not searched: see [`BlockCsc::diagonal`] and
//! [`BlockCsc::below`].

/// The lower triangle of the reduced system, by blocks (module
/// documentation).
#[derive(Debug, Clone, Default)]
pub(crate) struct BlockCsc {
    /// Each block's tangent dimension.
    pub(crate) dims: Vec<usize>,
    /// Each block's first scalar row (and column).
    pub(crate) offsets: Vec<usize>,
    /// Where each diagonal block starts among the blocks kept whole
    /// ([`BlockCsc::fold_diagonal`]); one more than the blocks.
    pub(crate) dense: Vec<usize>,
    /// The index of each block column's first entry.
    column_start: Vec<usize>,
    /// The rows below each block column's diagonal block.
    rows_below: Vec<usize>,
    /// Each block column's blocks below the diagonal: `(u, prefix)`, `prefix`
    /// the rows of the blocks above `u` in that column (below the diagonal),
    /// by increasing `u`; column `v`'s are `below_blocks[below_start[v]..below_start[v + 1]]`.
    below_blocks: Vec<(u32, u32)>,
    below_start: Vec<usize>,
    /// The scalar compressed-column structure, for faer.
    pub(crate) col_ptr: Vec<usize>,
    pub(crate) row_idx: Vec<usize>,
}

impl BlockCsc {
    /// The scalar dimension.
    pub(crate) fn dim(&self) -> usize {
        self.offsets.last().copied().unwrap_or(0) + self.dims.last().copied().unwrap_or(0)
    }

    /// The number of stored entries.
    pub(crate) fn len(&self) -> usize {
        self.row_idx.len()
    }

    /// The index of the first stored entry of scalar column `b` of block
    /// column `v` (its diagonal entry).
    #[inline]
    fn column(&self, v: usize, b: usize) -> usize {
        // Column b' stores d − b' entries of the diagonal block and every
        // row below it.
        let d = self.dims[v];
        self.column_start[v] + b * (d + self.rows_below[v]) - b * b.saturating_sub(1) / 2
    }

    /// Entry `(a, b)`, `a ≥ b`, of diagonal block `v`.
    #[inline]
    pub(crate) fn diagonal(&self, v: usize, a: usize, b: usize) -> usize {
        debug_assert!(a >= b && a < self.dims[v]);
        self.column(v, b) + (a - b)
    }

    /// Entry `(a, b)` of block `(u, v)`, `u > v`, whose rows start at
    /// `prefix` below column `v`'s diagonal block.
    #[inline]
    pub(crate) fn below(&self, v: usize, prefix: u32, a: usize, b: usize) -> usize {
        self.column(v, b) + (self.dims[v] - b) + prefix as usize + a
    }

    /// The prefix of block `(u, v)`, `u > v`, if it is stored.
    pub(crate) fn prefix(&self, u: usize, v: usize) -> Option<u32> {
        let blocks = &self.below_blocks[self.below_start[v]..self.below_start[v + 1]];
        blocks
            .binary_search_by_key(&(u as u32), |&(row, _)| row)
            .ok()
            .map(|k| blocks[k].1)
    }

    /// Adds the diagonal blocks kept whole in `dense` (block `v`'s `d × d`
    /// entries row-major from `dense[v]`, each entry `(r, c)` and `(c, r)`
    /// of the symmetric block accumulated in either place) into their lower
    /// triangles in `values`.
    pub(crate) fn fold_diagonal(&self, dense: &[f64], values: &mut [f64]) {
        for (v, &d) in self.dims.iter().enumerate() {
            let block = &dense[self.dense[v]..self.dense[v + 1]];
            for c in 0..d {
                let base = self.col_ptr[self.offsets[v] + c];
                values[base] += block[c * d + c];
                for r in c + 1..d {
                    values[base + r - c] += block[r * d + c] + block[c * d + r];
                }
            }
        }
    }

    /// `Σ_v xᵀ S x` over the symmetric matrix whose lower triangle is
    /// `values`.
    pub(crate) fn quadratic_form(&self, values: &[f64], x: &[f64]) -> f64 {
        let mut total = 0.0;
        for column in 0..self.col_ptr.len().saturating_sub(1) {
            let xc = x[column];
            let entries = self.col_ptr[column]..self.col_ptr[column + 1];
            for (&row, value) in self.row_idx[entries.clone()].iter().zip(&values[entries]) {
                let term = value * x[row] * xc;
                total += if row == column { term } else { 2.0 * term };
            }
        }
        total
    }

    /// The structure of blocks `dims` whose block columns hold the blocks
    /// `below[v]` (increasing) under their diagonal.
    pub(crate) fn new(dims: Vec<usize>, below: &[Vec<u32>]) -> Self {
        let mut offsets = Vec::with_capacity(dims.len());
        let mut dense = Vec::with_capacity(dims.len() + 1);
        let (mut n, mut squares) = (0, 0);
        for d in &dims {
            offsets.push(n);
            dense.push(squares);
            n += d;
            squares += d * d;
        }
        dense.push(squares);
        let mut csc = BlockCsc {
            dims,
            offsets,
            dense,
            column_start: Vec::with_capacity(below.len()),
            rows_below: Vec::with_capacity(below.len()),
            below_blocks: Vec::new(),
            below_start: vec![0],
            col_ptr: vec![0],
            row_idx: Vec::new(),
        };
        for (v, rows) in below.iter().enumerate() {
            let mut prefix = 0;
            for &u in rows {
                csc.below_blocks.push((u, prefix as u32));
                prefix += csc.dims[u as usize];
            }
            csc.below_start.push(csc.below_blocks.len());
            csc.rows_below.push(prefix);
            csc.column_start.push(csc.row_idx.len());
            let (offset, d) = (csc.offsets[v], csc.dims[v]);
            for b in 0..d {
                csc.row_idx.extend(offset + b..offset + d);
                for &u in rows {
                    let start = csc.offsets[u as usize];
                    csc.row_idx.extend(start..start + csc.dims[u as usize]);
                }
                csc.col_ptr.push(csc.row_idx.len());
            }
        }
        csc
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three blocks (dims 2, 1, 3): column 0 has blocks 1 and 2 below it,
    /// column 1 block 2, column 2 none. Every entry's computed index is its
    /// place in the scalar structure.
    #[test]
    fn entries_are_found_where_the_scalar_structure_has_them() {
        let csc = BlockCsc::new(vec![2, 1, 3], &[vec![1, 2], vec![2], vec![]]);
        assert_eq!(csc.dim(), 6);
        let entry = |row: usize, column: usize| {
            (csc.col_ptr[column]..csc.col_ptr[column + 1])
                .find(|&k| csc.row_idx[k] == row)
                .expect("stored")
        };
        for v in 0..3 {
            let (o, d) = (csc.offsets[v], csc.dims[v]);
            for b in 0..d {
                for a in b..d {
                    assert_eq!(csc.diagonal(v, a, b), entry(o + a, o + b));
                }
                for &(u, prefix) in &csc.below_blocks[csc.below_start[v]..csc.below_start[v + 1]] {
                    assert_eq!(csc.prefix(u as usize, v), Some(prefix));
                    let ou = csc.offsets[u as usize];
                    for a in 0..csc.dims[u as usize] {
                        assert_eq!(csc.below(v, prefix, a, b), entry(ou + a, o + b));
                    }
                }
            }
        }
        assert_eq!(csc.prefix(0, 1), None);
        // xᵀSx of the symmetric matrix with every stored entry 1 in its
        // lower triangle and x = 1: diagonal entries once, the others twice.
        let ones = vec![1.0; csc.len()];
        let diagonal = 6.0;
        assert_eq!(
            csc.quadratic_form(&ones, &[1.0; 6]),
            2.0 * csc.len() as f64 - diagonal
        );
    }
}
