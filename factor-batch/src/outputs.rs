//! The outputs of a batch, as columns: [`JacobianColumns`] (the residual and
//! each free variable's Jacobian block) and [`NormalColumns`] (the cost and
//! each free variable's blocks of the normal equations).

use factor_core::Factor;

use crate::columns::Columns;
use crate::error::BatchError;

/// The pairs `(i, j)`, `i ≤ j < n`, in the order of the Hessian blocks:
/// `(0, 0), (0, 1), …, (0, n−1), (1, 1), …`.
pub fn pairs(n: usize) -> Vec<(usize, usize)> {
    (0..n).flat_map(|i| (i..n).map(move |j| (i, j))).collect()
}

/// Each variable's tangent dimension, in declaration order.
fn tangents<F: Factor>() -> Vec<usize> {
    F::variables().iter().map(|v| v.tangent_dim).collect()
}

/// The rows (factors) with a non-finite entry in any of `outputs`, in
/// order: where a configuration was degenerate.
fn non_finite_rows<'a, S: 'a + Copy + Into<f64>>(
    outputs: impl IntoIterator<Item = &'a Columns<S>>,
) -> Vec<usize> {
    let mut bad: Vec<bool> = Vec::new();
    for columns in outputs {
        bad.resize(bad.len().max(columns.len()), false);
        for column in columns.columns() {
            for (flag, x) in bad.iter_mut().zip(column) {
                *flag |= !(*x).into().is_finite();
            }
        }
    }
    (0..bad.len()).filter(|&i| bad[i]).collect()
}

/// Checks that `columns` has `width` columns of `len` rows.
fn check(
    factor: &'static str,
    what: impl Fn() -> String,
    columns: &Columns<impl Sized>,
    width: usize,
    len: usize,
) -> Result<(), BatchError> {
    if columns.len() != len {
        return Err(BatchError::Length {
            factor,
            what: what(),
            found: columns.len(),
            expected: len,
        });
    }
    // With no rows there is nothing to write, and no width to read.
    if len > 0 && columns.width() != width {
        return Err(BatchError::Width {
            factor,
            what: what(),
            found: columns.width(),
            expected: width,
        });
    }
    Ok(())
}

/// Checks that `inputs` holds a batch of `F`: one column per stored scalar.
pub(crate) fn check_inputs<F: Factor, S>(inputs: &Columns<S>) -> Result<(), BatchError> {
    check(
        F::NAME,
        || "inputs".into(),
        inputs,
        F::SCALARS,
        inputs.len(),
    )
}

/// The residual and the Jacobian blocks of a batch of one factor type.
///
/// Column `k` of `residual` is residual entry `k`; column `r · D + c` of a
/// block is its entry at row `r`, column `c` (row-major, residual rows ×
/// the variable's `D` tangent columns), as the kernels lay blocks out.
#[derive(Debug, Clone, PartialEq)]
pub struct JacobianColumns<S> {
    /// The residual: one column per entry.
    pub residual: Columns<S>,
    /// One entry per variable in declaration order: its block, or `None`
    /// for a variable held fixed (not computed).
    pub blocks: Vec<Option<Columns<S>>>,
}

impl<S: Copy + Default> JacobianColumns<S> {
    /// Zeroed outputs for `len` factors of type `F`, with the blocks of the
    /// variables `k` with `free[k]` (every variable when `free` is
    /// shorter: a missing entry counts as free).
    pub fn new<F: Factor>(len: usize, free: &[bool]) -> Self {
        let r = F::RESIDUAL_DIM;
        JacobianColumns {
            residual: Columns::zeros(r, len),
            blocks: tangents::<F>()
                .iter()
                .enumerate()
                .map(|(k, d)| {
                    free.get(k)
                        .copied()
                        .unwrap_or(true)
                        .then(|| Columns::zeros(r * d, len))
                })
                .collect(),
        }
    }
}

impl<S> JacobianColumns<S> {
    /// Which variables' blocks are present.
    pub fn free(&self) -> Vec<bool> {
        self.blocks.iter().map(Option::is_some).collect()
    }

    /// The factors (rows) with a non-finite residual or Jacobian entry, in
    /// order: the degenerate configurations of the batch.
    pub fn non_finite_rows(&self) -> Vec<usize>
    where
        S: Copy + Into<f64>,
    {
        non_finite_rows(std::iter::once(&self.residual).chain(self.blocks.iter().flatten()))
    }

    /// Checks the shapes against factor `F` and `len` rows.
    pub(crate) fn check<F: Factor>(&self, len: usize) -> Result<(), BatchError> {
        let r = F::RESIDUAL_DIM;
        check(F::NAME, || "residual".into(), &self.residual, r, len)?;
        let variables = F::variables();
        if self.blocks.len() != variables.len() {
            return Err(BatchError::Blocks {
                factor: F::NAME,
                what: "the Jacobian",
                found: self.blocks.len(),
                expected: variables.len(),
            });
        }
        for (block, v) in self.blocks.iter().zip(&variables) {
            if let Some(block) = block {
                let what = || format!("the Jacobian w.r.t. `{}`", v.name);
                check(F::NAME, what, block, r * v.tangent_dim, len)?;
            }
        }
        Ok(())
    }
}

/// The Gauss–Newton normal equations of a batch of one factor type, per
/// factor: the cost `½ w rᵀr`, each variable's gradient block `Jᵢᵀ w r` and
/// the upper triangle of `JᵀwJ`, block by block.
///
/// Column `a` of a gradient block is its entry `a`. A diagonal Hessian
/// block `Jᵢᵀ w Jᵢ` holds its upper triangle row by row (entries `(a, b)`,
/// `a ≤ b`: `D(D+1)/2` columns); an off-diagonal one `Jᵢᵀ w Jⱼ`, `i < j`,
/// its `Dᵢ × Dⱼ` entries row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct NormalColumns<S> {
    /// The cost of each factor (one column).
    pub cost: Columns<S>,
    /// One entry per variable in declaration order: its gradient block, or
    /// `None` for a variable held fixed.
    pub gradient: Vec<Option<Columns<S>>>,
    /// One entry per pair of variables `i ≤ j` in [`pairs`] order: the
    /// Hessian block, or `None` when either variable is fixed.
    pub hessian: Vec<Option<Columns<S>>>,
}

/// The number of columns of the Hessian block of tangent dimensions `di`
/// and `dj`, diagonal when `diagonal`.
fn hessian_width(di: usize, dj: usize, diagonal: bool) -> usize {
    if diagonal { di * (di + 1) / 2 } else { di * dj }
}

impl<S: Copy + Default> NormalColumns<S> {
    /// Zeroed outputs for `len` factors of type `F`, with the blocks of the
    /// variables `k` with `free[k]` (a missing entry counts as free).
    pub fn new<F: Factor>(len: usize, free: &[bool]) -> Self {
        let d = tangents::<F>();
        let is_free = |k: usize| free.get(k).copied().unwrap_or(true);
        NormalColumns {
            cost: Columns::zeros(1, len),
            gradient: d
                .iter()
                .enumerate()
                .map(|(k, &dk)| is_free(k).then(|| Columns::zeros(dk, len)))
                .collect(),
            hessian: pairs(d.len())
                .into_iter()
                .map(|(i, j)| {
                    (is_free(i) && is_free(j))
                        .then(|| Columns::zeros(hessian_width(d[i], d[j], i == j), len))
                })
                .collect(),
        }
    }
}

impl<S> NormalColumns<S> {
    /// Which variables' blocks are present (by their gradient blocks).
    pub fn free(&self) -> Vec<bool> {
        self.gradient.iter().map(Option::is_some).collect()
    }

    /// The factors (rows) with a non-finite output, in order: the
    /// degenerate configurations of the batch.
    pub fn non_finite_rows(&self) -> Vec<usize>
    where
        S: Copy + Into<f64>,
    {
        non_finite_rows(
            std::iter::once(&self.cost)
                .chain(self.gradient.iter().flatten())
                .chain(self.hessian.iter().flatten()),
        )
    }

    /// Checks the shapes against factor `F` and `len` rows, and that the
    /// Hessian blocks present are those of the pairs of free variables.
    pub(crate) fn check<F: Factor>(&self, len: usize) -> Result<(), BatchError> {
        check(F::NAME, || "cost".into(), &self.cost, 1, len)?;
        let variables = F::variables();
        let n = variables.len();
        let expected_pairs = pairs(n);
        for (what, found, expected) in [
            ("the gradient", self.gradient.len(), n),
            ("the Hessian", self.hessian.len(), expected_pairs.len()),
        ] {
            if found != expected {
                return Err(BatchError::Blocks {
                    factor: F::NAME,
                    what,
                    found,
                    expected,
                });
            }
        }
        for (block, v) in self.gradient.iter().zip(&variables) {
            if let Some(block) = block {
                let what = || format!("the gradient w.r.t. `{}`", v.name);
                check(F::NAME, what, block, v.tangent_dim, len)?;
            }
        }
        let free = self.free();
        for ((i, j), block) in expected_pairs.into_iter().zip(&self.hessian) {
            let (a, b) = (&variables[i], &variables[j]);
            let wanted = free[i] && free[j];
            match block {
                Some(block) if wanted => {
                    let what = || format!("the Hessian block of `{}` and `{}`", a.name, b.name);
                    let width = hessian_width(a.tangent_dim, b.tangent_dim, i == j);
                    check(F::NAME, what, block, width, len)?;
                }
                None if !wanted => {}
                _ => {
                    return Err(BatchError::Pairing {
                        factor: F::NAME,
                        first: a.name,
                        second: b.name,
                        state: if block.is_some() { "present" } else { "absent" },
                        free: if wanted { "both free" } else { "not both free" },
                    });
                }
            }
        }
        Ok(())
    }
}
