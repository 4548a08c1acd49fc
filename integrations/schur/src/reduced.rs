//! The reduced system `S δ = b`, factorized by faer's sparse Cholesky
//! (supernodal where the factor is dense enough, which faer decides from
//! the flop count), in the fill-reducing order [`crate::structure`] laid
//! `S` out in: no permutation is applied at each factorization. The
//! symbolic analysis is done once.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{LltParams, LltRegularization};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side, Spec};

use crate::csc::BlockCsc;
use crate::error::SchurError;

/// The transpose of the `n × n` compressed-column pattern `(col_ptr,
/// row_idx)`, its rows sorted.
fn transpose(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut count = vec![0usize; n + 1];
    for &r in row_idx {
        count[r + 1] += 1;
    }
    for k in 0..n {
        count[k + 1] += count[k];
    }
    let mut next = count.clone();
    let mut rows = vec![0; row_idx.len()];
    for column in 0..n {
        for &r in &row_idx[col_ptr[column]..col_ptr[column + 1]] {
            rows[next[r]] = column;
            next[r] += 1;
        }
    }
    (count, rows)
}

/// The Cholesky factorization of `S`, for one structure.
pub(crate) struct ReducedSolver {
    symbolic: SymbolicCholesky<usize>,
    factor: Vec<f64>,
    memory: MemBuffer,
    par: Par,
}

impl ReducedSolver {
    /// The symbolic factorization of `csc`'s structure, its numeric
    /// factorizations and solves to run on `threads` threads.
    pub(crate) fn new(csc: &BlockCsc, threads: usize) -> Result<Self, SchurError> {
        let n = csc.dim();
        // Without a permutation, the analysis reads the upper triangle.
        let (col_ptr, row_idx) = transpose(n, &csc.col_ptr, &csc.row_idx);
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_cholesky(
            pattern,
            Side::Upper,
            SymmetricOrdering::Identity,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..CholeskySymbolicParams::default()
            },
        )
        .map_err(|e| SchurError::TooLarge(format!("the reduced system's factor: {e:?}")))?;
        let par = if threads > 1 {
            Par::rayon(threads)
        } else {
            Par::Seq
        };
        let scratch = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Spec::<LltParams, f64>::default()),
            symbolic.solve_in_place_scratch::<f64>(1, par),
        ]);
        Ok(ReducedSolver {
            factor: vec![0.0; symbolic.len_val()],
            symbolic,
            memory: MemBuffer::new(scratch),
            par,
        })
    }

    /// The number of entries of the Cholesky factor.
    pub(crate) fn factor_entries(&self) -> usize {
        self.factor.len()
    }

    /// Factorizes the matrix whose lower triangle is `values` (in `csc`'s
    /// structure); `false` when it is not numerically positive definite.
    pub(crate) fn factorize(&mut self, csc: &BlockCsc, values: &[f64]) -> bool {
        let n = csc.dim();
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &csc.col_ptr, None, &csc.row_idx);
        let matrix = SparseColMatRef::new(pattern, values);
        self.symbolic
            .factorize_numeric_llt(
                &mut self.factor,
                matrix,
                Side::Lower,
                LltRegularization::default(),
                self.par,
                MemStack::new(&mut self.memory),
                Spec::default(),
            )
            .is_ok()
    }

    /// Solves `S x = b` in place with the last factorization.
    pub(crate) fn solve(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        LltRef::new(&self.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            self.par,
            MemStack::new(&mut self.memory),
        );
    }
}
