//! The blocks of a symmetric block-sparse matrix (a normal matrix `JᵀJ`),
//! in one slab of `f64`: each variable's diagonal block, and the block of
//! each pair of variables some factor (or an elimination) joins, stored
//! once, as the rows of the lower-indexed variable (`H_ab`, `a < b`; `H_ba`
//! is its transpose). Every block is column-major; a variable's neighbours
//! are kept sorted, each with the offset of the pair's block, so that a
//! block is found by a binary search and no block is ever moved.

use nalgebra::DVector;

/// The blocks (see the module documentation).
#[derive(Debug, Clone)]
pub(super) struct Blocks {
    /// Each variable's dimension.
    pub(super) dims: Vec<usize>,
    /// Each variable's diagonal block: its offset in `values` (the
    /// diagonal blocks first, then the pairs').
    diagonal: Vec<usize>,
    /// Each variable's neighbours, sorted: the neighbour and the offset of
    /// the pair's block.
    pub(super) off: Vec<Vec<(usize, usize)>>,
    pub(super) values: Vec<f64>,
}

impl Blocks {
    /// Zero diagonal blocks of the dimensions `dims`, no pair.
    pub(super) fn new(dims: Vec<usize>) -> Self {
        let mut diagonal = Vec::with_capacity(dims.len());
        let mut end = 0;
        for d in &dims {
            diagonal.push(end);
            end += d * d;
        }
        Blocks {
            off: vec![Vec::new(); dims.len()],
            dims,
            diagonal,
            values: vec![0.0; end],
        }
    }

    /// Zero blocks of the dimensions `dims`, the pairs `off` (each
    /// variable's neighbours, sorted, with their blocks' offsets) among
    /// `len` values: the layout of blocks laid out before.
    pub(super) fn laid_out(dims: Vec<usize>, off: Vec<Vec<(usize, usize)>>, len: usize) -> Self {
        let mut blocks = Blocks::new(dims);
        blocks.off = off;
        blocks.values.resize(len, 0.0);
        blocks
    }

    /// The offset of variable `v`'s diagonal block.
    pub(super) fn diagonal(&self, v: usize) -> usize {
        self.diagonal[v]
    }

    /// The offset of the block of the pair `a ≠ b`, and whether it was
    /// created (zero) now.
    pub(super) fn pair(&mut self, a: usize, b: usize) -> (usize, bool) {
        let (at, created, _) = self.pair_from(a, b, 0);
        (at, created)
    }

    /// [`Blocks::pair`] with `b` at or after position `from` of `a`'s
    /// neighbours, found by galloping from there (the pairs of one variable
    /// with increasing neighbours are found in one pass); also returns
    /// `b`'s position among them, to start the next search from.
    pub(super) fn pair_from(&mut self, a: usize, b: usize, from: usize) -> (usize, bool, usize) {
        let list = &self.off[a];
        // The first position at or after `from` whose neighbour is not below
        // `b`: bracketed by doubling steps, then found by bisection.
        let (mut low, mut step) = (from, 1);
        while low + step <= list.len() && list[low + step - 1].0 < b {
            low += step;
            step *= 2;
        }
        let high = (low + step).min(list.len());
        let k = low + list[low..high].partition_point(|&(w, _)| w < b);
        if k < list.len() && list[k].0 == b {
            return (list[k].1, false, k);
        }
        let at = self.values.len();
        self.values.resize(at + self.dims[a] * self.dims[b], 0.0);
        self.off[a].insert(k, (b, at));
        let j = self.off[b]
            .binary_search_by_key(&a, |&(w, _)| w)
            .expect_err("pairs are created both ways at once");
        self.off[b].insert(j, (a, at));
        (at, true, k)
    }

    /// Lays the pairs' blocks out anew, those of each variable of `order`
    /// (every variable once) side by side in turn, each pair with the first
    /// of its two variables there: an elimination in about that order
    /// reads each variable's blocks from one place, not from wherever its
    /// factors put them. Returns the room of the old layout.
    pub(super) fn repack(&mut self, order: &[usize]) -> Vec<f64> {
        let mut position = vec![0; order.len()];
        for (k, &v) in order.iter().enumerate() {
            position[v] = k;
        }
        let pairs = self.diagonal.last().map_or(0, |&at| {
            let d = self.dims[self.dims.len() - 1];
            at + d * d
        });
        let mut values = Vec::with_capacity(self.values.len());
        values.extend_from_slice(&self.values[..pairs]);
        for &v in order {
            for k in 0..self.off[v].len() {
                let (w, at) = self.off[v][k];
                if position[w] < position[v] {
                    continue;
                }
                let moved = values.len();
                values.extend_from_slice(&self.values[at..at + self.dims[v] * self.dims[w]]);
                self.off[v][k].1 = moved;
                let j = self.off[w]
                    .binary_search_by_key(&v, |&(u, _)| u)
                    .expect("pairs are kept both ways");
                self.off[w][j].1 = moved;
            }
        }
        std::mem::replace(&mut self.values, values)
    }

    /// `H_vw` (the rows of `v`) of the pair's block at `at` in `values`
    /// (these blocks' values, or a copy of them), written to `out`
    /// (`dims[v] × dims[w]`, column-major): the block as stored when
    /// `v < w`, else its transpose.
    pub(super) fn rows_of(&self, values: &[f64], v: usize, w: usize, at: usize, out: &mut [f64]) {
        let (dv, dw) = (self.dims[v], self.dims[w]);
        let block = &values[at..at + dv * dw];
        if v < w {
            out.copy_from_slice(block);
        } else {
            // Stored `dw × dv`: its (j, i) is H_vw's (i, j).
            for i in 0..dv {
                for j in 0..dw {
                    out[i + j * dv] = block[j + i * dw];
                }
            }
        }
    }

    /// `H ← diag(s) · H · diag(s)` on every block (each pair once).
    pub(super) fn scale(&mut self, scales: &[DVector<f64>]) {
        for v in 0..self.dims.len() {
            let (at, s) = (self.diagonal[v], scales[v].as_slice());
            scale_block(&mut self.values[at..], s, s);
            for &(w, at) in &self.off[v] {
                if v < w {
                    scale_block(&mut self.values[at..], s, scales[w].as_slice());
                }
            }
        }
    }
}

/// `h ← diag(rows) · h · diag(columns)` for the column-major block at the
/// start of `h`, in place.
fn scale_block(h: &mut [f64], rows: &[f64], columns: &[f64]) {
    let m = rows.len();
    for (j, c) in columns.iter().enumerate() {
        for (x, r) in h[j * m..(j + 1) * m].iter_mut().zip(rows) {
            *x = *x * r * c;
        }
    }
}

/// `c += alpha · a b`: `a` is `m × k`, `b` is `k × n` and `c` (at the
/// start of the slice) `m × n`, all column-major: each column of `c` gains
/// a combination of the columns of `a`. The small heights the blocks have
/// (a variable's dimension) are each compiled with the height known.
pub(super) fn add_product(c: &mut [f64], alpha: f64, a: &[f64], b: &[f64], m: usize) {
    match m {
        1 => product::<1>(c, alpha, a, b),
        2 => product::<2>(c, alpha, a, b),
        3 => product::<3>(c, alpha, a, b),
        4 => product::<4>(c, alpha, a, b),
        6 => product::<6>(c, alpha, a, b),
        _ => product_any(c, alpha, a, b, m),
    }
}

/// [`add_product`] of height `M`.
fn product<const M: usize>(c: &mut [f64], alpha: f64, a: &[f64], b: &[f64]) {
    let k = a.len() / M;
    if k == 0 {
        return;
    }
    for (cj, bj) in c.chunks_exact_mut(M).zip(b.chunks_exact(k)) {
        let mut sum = [0.0; M];
        for (at, bt) in a.chunks_exact(M).zip(bj) {
            for i in 0..M {
                sum[i] += at[i] * bt;
            }
        }
        for i in 0..M {
            cj[i] += alpha * sum[i];
        }
    }
}

/// [`add_product`] of any height `m`.
fn product_any(c: &mut [f64], alpha: f64, a: &[f64], b: &[f64], m: usize) {
    let k = a.len() / m.max(1);
    if k == 0 {
        return;
    }
    for (cj, bj) in c.chunks_exact_mut(m).zip(b.chunks_exact(k)) {
        for (i, ci) in cj.iter_mut().enumerate() {
            let dot: f64 = bj.iter().enumerate().map(|(t, bt)| a[i + t * m] * bt).sum();
            *ci += alpha * dot;
        }
    }
}

/// `out ← aᵀ` for the `m`-row, column-major `a` (`out` column-major too).
pub(super) fn transpose(a: &[f64], m: usize, out: &mut [f64]) {
    let n = a.len() / m.max(1);
    for j in 0..n {
        for i in 0..m {
            out[j + i * n] = a[i + j * m];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// `add_product` is `c + α a b` at every height, `transpose` is `aᵀ`;
    /// a pair's block reads as either variable's rows.
    #[test]
    fn products_and_blocks_read_as_the_matrices_they_are() {
        for m in 1..=7 {
            let a = DMatrix::from_fn(m, 3, |i, j| (i as f64 + 1.0) * 0.7 - j as f64);
            let b = DMatrix::from_fn(3, 4, |i, j| (i * j) as f64 - 0.5);
            let c = DMatrix::from_fn(m, 4, |i, j| (i + 2 * j) as f64);
            let mut sum = c.clone();
            add_product(sum.as_mut_slice(), -2.0, a.as_slice(), b.as_slice(), m);
            let expected = &c - 2.0 * &a * &b;
            assert!((sum - expected).amax() < 1e-12, "height {m}");
            let mut t = vec![0.0; 3 * m];
            transpose(a.as_slice(), m, &mut t);
            assert_eq!(t, a.transpose().as_slice());
        }

        let mut blocks = Blocks::new(vec![2, 3]);
        let (at, created) = blocks.pair(1, 0);
        assert!(created);
        assert_eq!(blocks.pair(0, 1), (at, false));
        // Found by galloping from any earlier position.
        let mut many = Blocks::new(vec![1; 40]);
        let made: Vec<usize> = (1..40).step_by(3).map(|b| many.pair(0, b).0).collect();
        let mut from = 0;
        for (b, at) in (1..40).step_by(3).zip(&made) {
            let (found, created, k) = many.pair_from(0, b, from);
            assert_eq!((found, created), (*at, false));
            from = k;
        }
        assert!(many.pair_from(0, 2, 1).1, "a pair not there is created");

        // Laid out anew, every pair's block reads the same.
        let before: Vec<Vec<f64>> = (1..40)
            .step_by(3)
            .map(|b| {
                let at = many.pair(0, b).0;
                many.values[at] = b as f64;
                many.values[at..at + 1].to_vec()
            })
            .collect();
        let order: Vec<usize> = (0..40).rev().collect();
        let _ = many.repack(&order);
        for (b, value) in (1..40).step_by(3).zip(before) {
            let (at, created) = many.pair(b, 0);
            assert!(!created);
            assert_eq!(many.values[at..at + 1], value[..]);
        }
        let h01 = DMatrix::from_fn(2, 3, |i, j| (3 * i + j) as f64);
        blocks.values[at..at + 6].copy_from_slice(h01.as_slice());
        let mut rows = vec![0.0; 6];
        blocks.rows_of(&blocks.values, 1, 0, at, &mut rows);
        assert_eq!(rows, h01.transpose().as_slice());
        blocks.rows_of(&blocks.values, 0, 1, at, &mut rows);
        assert_eq!(rows, h01.as_slice());
    }

    /// Scaling a block in place gives the bits of `diag(r) · h · diag(c)`.
    #[test]
    fn a_block_scaled_in_place_is_the_product_with_the_diagonals() {
        let h = DMatrix::from_fn(3, 2, |i, j| (i as f64 + 0.3).powi(3) - 1.7 * j as f64);
        let rows = [0.1, 3.7, 1e-5];
        let columns = [2.3e4, 0.77];
        let product = DMatrix::from_diagonal(&DVector::from_column_slice(&rows))
            * &h
            * DMatrix::from_diagonal(&DVector::from_column_slice(&columns));
        let mut scaled = h.clone();
        scale_block(scaled.as_mut_slice(), &rows, &columns);
        assert_eq!(scaled, product);
    }
}
