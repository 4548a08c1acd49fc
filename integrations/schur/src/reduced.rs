//! The reduced system `S δ = b`, factorized by faer's sparse Cholesky
//! (supernodal), in the fill-reducing order [`crate::structure`] laid `S`
//! out in: no permutation is applied at each factorization, and the
//! symbolic analysis is done once. A small system (at most [`DENSE_MAX`]
//! unknowns) is factorized dense instead, by faer's dense Cholesky: the
//! sparse factorization's fixed costs dominate there.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{LltParams, LltRegularization};
use faer::linalg::solvers::{Llt, SolveCore};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, MatMut, Par, Side, Spec};

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

/// The largest reduced system factorized dense. Measured (2026-11-29, all
/// of a solve's factorizations and solves, sparse against dense):
/// `pose3example`, 24 unknowns, 1.56–1.72 ms against 0.12–0.14 ms;
/// Balbianello, 39, 0.28–0.31 ms against 0.28 ms; KITTI VO, 150, 3.0–3.2 ms
/// against 6.0–7.2 ms; `synth-bal` with 30 cameras, 264, 19–22 ms against
/// 67–102 ms.
pub(crate) const DENSE_MAX: usize = 40;

/// The Cholesky factorization of `S`, for one structure.
pub(crate) enum ReducedSolver {
    /// faer's supernodal factorization (boxed: it is the larger by far).
    Sparse(Box<SparseLlt>),
    /// faer's dense factorization of `S` copied whole, and the last one.
    Dense {
        matrix: Mat<f64>,
        llt: Option<Llt<f64>>,
    },
}

/// faer's supernodal factorization, its symbolic analysis done once.
pub(crate) struct SparseLlt {
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
        if n <= DENSE_MAX {
            return Ok(ReducedSolver::Dense {
                matrix: Mat::zeros(n, n),
                llt: None,
            });
        }
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
        Ok(ReducedSolver::Sparse(Box::new(SparseLlt {
            factor: vec![0.0; symbolic.len_val()],
            symbolic,
            memory: MemBuffer::new(scratch),
            par,
        })))
    }

    /// Which factorization, in words.
    pub(crate) fn name(&self) -> &'static str {
        match self {
            ReducedSolver::Sparse(_) => "faer supernodal sparse Cholesky",
            ReducedSolver::Dense { .. } => "faer dense Cholesky",
        }
    }

    /// The number of entries of the Cholesky factor (the lower triangle,
    /// for a dense one).
    pub(crate) fn factor_entries(&self) -> usize {
        match self {
            ReducedSolver::Sparse(sparse) => sparse.factor.len(),
            ReducedSolver::Dense { matrix, .. } => matrix.nrows() * (matrix.nrows() + 1) / 2,
        }
    }

    /// Factorizes the matrix whose lower triangle is `values` (in `csc`'s
    /// structure); `false` when it is not numerically positive definite.
    pub(crate) fn factorize(&mut self, csc: &BlockCsc, values: &[f64]) -> bool {
        let n = csc.dim();
        match self {
            ReducedSolver::Sparse(sparse) => {
                let SparseLlt {
                    symbolic,
                    factor,
                    memory,
                    par,
                } = &mut **sparse;
                let pattern =
                    SymbolicSparseColMatRef::new_checked(n, n, &csc.col_ptr, None, &csc.row_idx);
                let matrix = SparseColMatRef::new(pattern, values);
                symbolic
                    .factorize_numeric_llt(
                        factor,
                        matrix,
                        Side::Lower,
                        LltRegularization::default(),
                        *par,
                        MemStack::new(memory),
                        Spec::default(),
                    )
                    .is_ok()
            }
            ReducedSolver::Dense { matrix, llt } => {
                // The lower triangle, entry by entry (the rest is not read).
                for column in 0..n {
                    for k in csc.col_ptr[column]..csc.col_ptr[column + 1] {
                        matrix[(csc.row_idx[k], column)] = values[k];
                    }
                }
                *llt = matrix.llt(Side::Lower).ok();
                llt.is_some()
            }
        }
    }

    /// Solves `S x = b` in place with the last factorization (which
    /// succeeded).
    pub(crate) fn solve(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        let rhs = MatMut::from_column_major_slice_mut(rhs, n, 1);
        match self {
            ReducedSolver::Sparse(sparse) => {
                let SparseLlt {
                    symbolic,
                    factor,
                    memory,
                    par,
                } = &mut **sparse;
                LltRef::new(symbolic, factor).solve_in_place_with_conj(
                    Conj::No,
                    rhs,
                    *par,
                    MemStack::new(memory),
                );
            }
            ReducedSolver::Dense { llt, .. } => {
                if let Some(llt) = llt {
                    llt.solve_in_place_with_conj(Conj::No, rhs);
                }
            }
        }
    }
}
