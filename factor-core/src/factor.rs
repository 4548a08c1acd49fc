//! The factor model: a residual over manifold variables and its tangent-space
//! Jacobians.
//!
//! A factor is a struct generic over the scalar holding its constants and its
//! variables; `#[derive(Factor)]` (crate `factor-macros`) implements this trait
//! for the `f64` instance from one generic residual function. The typed API
//! (`linearize_dual` returning one fixed-size `nalgebra` block per variable) is
//! emitted beside it as inherent methods; this trait is the uniform, dynamically
//! sized view used by the command line, the numerical check and reports.

use nalgebra::{DMatrix, DVector};

use crate::manifold::Perturbation;
use crate::scalar::Scalar;
use crate::storage::{Layout, Storage, StorageError};
use crate::validation::number_text;

/// Why a factor has no meaningful value at a configuration (or, for
/// [`FactorError::StaleKernel`], why its kernel cannot be trusted).
///
/// `#[non_exhaustive]`: a `match` on it ends with a `_ =>` arm, so that a
/// new kind of error does not break it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FactorError {
    /// The geometry is degenerate (point behind the camera, parallel bearing
    /// vectors, ...): the residual is undefined or its Jacobian infinite.
    #[error("{factor}: degenerate geometry: {reason}")]
    Degenerate {
        /// The factor's name.
        factor: &'static str,
        /// What is degenerate, with the offending value.
        reason: String,
    },
    /// The configuration is valid, but its `f64` inputs do not determine
    /// the outputs to the factor's stated accuracy (a residual whose terms
    /// cancel below their own rounding): outside the accuracy envelope.
    /// Unlike [`FactorError::Degenerate`], no reading of the inputs is
    /// wrong; only the arithmetic cannot be trusted there.
    #[error("{factor}: outside the accuracy envelope: {reason}")]
    Inaccurate {
        /// The factor's name.
        factor: &'static str,
        /// What lost its digits, with the magnitudes involved.
        reason: String,
    },
    /// An evaluation produced a NaN or an infinity that validation did not
    /// foresee; reported instead of returned.
    #[error("{factor}: non-finite {what}")]
    NonFinite {
        /// The factor's name.
        factor: &'static str,
        /// Which output (`residual` or the Jacobian of a variable).
        what: String,
    },
    /// A debug build found the factor's generated kernel stale: it
    /// disagrees with dual numbers through the current definition (a
    /// residual, a function it calls or a retraction changed since the
    /// kernel was generated; see [`crate::kernel`]). Regenerate it.
    #[error("{factor}: the generated kernel `{kernel}` is stale: {detail}")]
    StaleKernel {
        /// The factor's name.
        factor: &'static str,
        /// The kernel's path.
        kernel: &'static str,
        /// The output that differs, both values, and how to regenerate.
        detail: String,
    },
    /// Numerical differentiation
    /// ([`NumericLinearize::linearize_numeric`](crate::NumericLinearize::linearize_numeric))
    /// could not estimate a Jacobian block to its tolerance.
    #[error(
        "{factor}: numerical differentiation w.r.t. `{variable}` did not converge: {} \
         (worst at tangent coordinate {coordinate}), above the tolerance {}",
        if .estimate.is_finite() {
            format!("estimated relative error {}", number_text(*.estimate))
        } else {
            "no error estimate could be formed".to_string()
        },
        number_text(*.tolerance)
    )]
    NumericNotConverged {
        /// The factor's name.
        factor: &'static str,
        /// The variable whose block did not converge.
        variable: &'static str,
        /// The tangent coordinate (column) with the largest estimated error.
        coordinate: usize,
        /// The block's estimated relative error (Frobenius); infinite (or
        /// NaN) when no estimate could be formed.
        estimate: f64,
        /// The largest estimate the method accepts.
        tolerance: f64,
    },
}

impl FactorError {
    /// [`FactorError::NonFinite`] for factor `F`'s output at `at`, as
    /// [`first_non_finite`] reports it: `None` for the residual, `Some(k)`
    /// for the Jacobian block of variable `k`.
    pub fn non_finite_output<F: Factor>(at: Option<usize>) -> Self {
        FactorError::NonFinite {
            factor: F::NAME,
            what: match at {
                None => "residual".into(),
                Some(k) => format!("Jacobian w.r.t. `{}`", F::variables()[k].name),
            },
        }
    }
}

/// The first output that is not finite: `None` when all are, `Some(None)`
/// for the residual, `Some(Some(k))` for block `k` (blocks passed as `None`
/// are not looked at).
#[inline]
pub fn first_non_finite(residual: &[f64], blocks: &[Option<&mut [f64]>]) -> Option<Option<usize>> {
    let finite = blocks.iter().fold(all_finite(residual), |ok, b| {
        ok & b.as_deref().is_none_or(all_finite)
    });
    if finite {
        return None;
    }
    if !all_finite(residual) {
        return Some(None);
    }
    blocks
        .iter()
        .position(|block| block.as_deref().is_some_and(|b| !all_finite(b)))
        .map(Some)
}

/// Whether every value is finite: `Σ (x − x)` is `0` when every `x` is finite
/// and NaN otherwise (`∞ − ∞` and `NaN − NaN` are NaN). No branch per value,
/// and scalar loads: this runs right after a kernel wrote the values, and a
/// vector load of values just written one by one waits until they reach the
/// cache (a failed store-to-load forwarding), which cost more than the
/// kernel's own arithmetic. This is on every linearization's path.
#[inline]
#[expect(clippy::eq_op, reason = "`x - x` is the finiteness test")]
pub fn all_finite(values: &[f64]) -> bool {
    values.iter().fold(0.0, |sum, x| sum + (x - x)) == 0.0
}

/// A variable of a factor as reports describe it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VariableInfo {
    /// The field name.
    pub name: &'static str,
    /// The variable's type as written in the factor (`Se3<S>`); a variable
    /// of the factor's scalar type itself is `f64` (its type at the `f64`
    /// instance, as problem files name it).
    pub type_name: &'static str,
    /// Tangent dimension (Jacobian columns).
    pub tangent_dim: usize,
    /// Side of the perturbation.
    pub perturbation: Perturbation,
    /// The perturbation and the column order in words.
    pub tangent: &'static str,
}

impl VariableInfo {
    /// The name of the variable's chart: its type's name in snake case and
    /// its side, `<type>_<side>` (`Se3<S>` on the left is `se3_left`,
    /// `factor_core::lie::Se3RhoTheta<S>` on the right
    /// `se3_rho_theta_right`): what generated solver manifolds are named
    /// after.
    pub fn chart_name(&self) -> String {
        let base = self
            .type_name
            .split('<')
            .next()
            .unwrap_or(self.type_name)
            .trim();
        let last = base.rsplit("::").next().unwrap_or(base);
        let mut name = String::new();
        let mut previous: Option<char> = None;
        for c in last.chars() {
            if c.is_ascii_uppercase() {
                if previous.is_some_and(|p| p.is_ascii_lowercase() || p.is_ascii_digit()) {
                    name.push('_');
                }
                name.push(c.to_ascii_lowercase());
            } else if c.is_ascii_alphanumeric() {
                name.push(c);
            } else {
                name.push('_');
            }
            previous = Some(c);
        }
        format!("{name}_{}", self.perturbation.as_str())
    }
}

/// A field of a factor (constant or variable): how it is stored, as kernels
/// lay out their inputs, and how a user writes it.
#[derive(Debug, Clone)]
pub struct FieldInfo {
    /// The field name.
    pub name: &'static str,
    /// The first paragraph of the field's documentation, on one line.
    pub doc: &'static str,
    /// How many scalars the field stores ([`crate::Storage::SCALARS`]).
    pub scalars: usize,
    /// The variable's index among the variables, or `None` for a constant.
    pub variable: Option<usize>,
    /// The stored scalars' names ([`crate::Storage::layout`]).
    pub layout: Layout,
    /// The shape a user writes the field in ([`crate::Storage::input_layout`]).
    pub input_layout: Layout,
    /// The field's [`crate::Storage::from_input`]: what a user wrote, in
    /// `input_layout` order, to the stored scalars, or what is wrong with it.
    pub from_input: fn(&[f64]) -> Result<Vec<f64>, StorageError>,
}

/// Residual and Jacobian blocks of any factor, dynamically sized.
#[derive(Debug, Clone, PartialEq)]
pub struct DynLinearization {
    /// The residual.
    pub residual: DVector<f64>,
    /// One block per variable, in declaration order: residual rows × tangent columns.
    pub jacobians: Vec<DMatrix<f64>>,
}

impl DynLinearization {
    /// Fails with [`FactorError::NonFinite`] naming the first non-finite output.
    pub fn ensure_finite(self, factor: &'static str, names: &[&str]) -> Result<Self, FactorError> {
        if self.residual.iter().any(|x| !x.is_finite()) {
            return Err(FactorError::NonFinite {
                factor,
                what: "residual".into(),
            });
        }
        for (block, name) in self.jacobians.iter().zip(names) {
            if block.iter().any(|x| !x.is_finite()) {
                return Err(FactorError::NonFinite {
                    factor,
                    what: format!("Jacobian w.r.t. `{name}`"),
                });
            }
        }
        Ok(self)
    }
}

/// A factor at a configuration of its variables (the `f64` instance).
///
/// A factor is stored as its fields' scalars, in declaration order
/// ([`Storage`]), which is also the order of a generated kernel's inputs.
pub trait Factor: Storage<f64> + Sized {
    /// Snake-case name used on the command line.
    const NAME: &'static str;
    /// The factor type's path (`my_crate::module::MyFactor`).
    const TYPE_PATH: &'static str;
    /// The first paragraph of the factor type's documentation, on one line.
    const DESCRIPTION: &'static str;
    /// Residual dimension (Jacobian rows).
    const RESIDUAL_DIM: usize;

    /// Length of the stacked tangent `[δ_v₁, …, δ_vₙ]`.
    const TANGENT_DIM: usize;

    /// The variables in declaration order.
    fn variables() -> Vec<VariableInfo>;

    /// Every field in declaration order: the order of its [`Storage`] and of
    /// a generated kernel's input arrays.
    fn fields() -> Vec<FieldInfo>;

    /// The residual of the factor stored as `stored` (its fields' scalars in
    /// declaration order, [`Storage`]) with every variable retracted to first
    /// order by its slice of the stacked tangent `delta`, over any scalar
    /// `T`. Its derivative w.r.t. `delta` at `delta = 0` is the Jacobian; a
    /// symbolic scalar traces it (crate `factor-symbolic`) with no value of
    /// the factor at hand.
    ///
    /// # Panics
    ///
    /// If `stored` or `delta` has the wrong length.
    fn perturbed_residual_over<T: Scalar>(stored: &[T], delta: &[T]) -> Vec<T>;

    /// The residual of the factor stored as `stored` over any scalar `T`,
    /// with no perturbation: what a host's chart composes with its own
    /// retraction ([`crate::host::host_residual`]).
    ///
    /// # Panics
    ///
    /// If `stored` has the wrong length.
    fn residual_over<T: Scalar>(stored: &[T]) -> Vec<T> {
        let mut out = vec![T::zero(); Self::RESIDUAL_DIM];
        Self::residual_over_into(stored, &mut out);
        out
    }

    /// [`Factor::residual_over`] written into `out` ([`Factor::RESIDUAL_DIM`]
    /// entries), with no allocation: the dual-number pass in a host's chart
    /// ([`crate::host::linearize_host_dual`]).
    ///
    /// # Panics
    ///
    /// If `stored` or `out` has the wrong length.
    fn residual_over_into<T: Scalar>(stored: &[T], out: &mut [T]);

    /// Checks that the configuration has a meaningful residual and Jacobian.
    fn validate(&self) -> Result<(), FactorError>;

    /// The residual, after [`Factor::validate`].
    fn residual_dyn(&self) -> Result<DVector<f64>, FactorError>;

    /// Residual and Jacobians by dual numbers, after [`Factor::validate`].
    fn linearize_dual_dyn(&self) -> Result<DynLinearization, FactorError>;

    /// The generated kernel the typed `linearize()` goes through, as written
    /// in `#[factor(kernel = path)]`; `None` when the factor has none.
    const KERNEL: Option<&'static str> = None;

    /// Residual and Jacobians through the generated kernel, after
    /// [`Factor::validate`]; `None` when the factor has no kernel (then
    /// [`Factor::linearize_dual_dyn`] is the exact method).
    fn linearize_generated_dyn(&self) -> Option<Result<DynLinearization, FactorError>> {
        None
    }

    /// Residual and the requested Jacobian blocks written into the caller's
    /// storage: the path a solver takes. Through the generated kernel where
    /// the factor has one (no allocation), else through dual numbers.
    ///
    /// `residual` holds [`Factor::RESIDUAL_DIM`] entries; `jacobians` has one
    /// entry per variable, `Some(block)` for a block to compute (row-major,
    /// residual rows × the variable's tangent columns) and `None` for a
    /// variable the caller holds fixed, whose block is not computed (nor the
    /// work only it needs, in a kernel). On an error the outputs hold
    /// unspecified values (a kernel runs before the validation, which would
    /// otherwise wait for its outputs to be stored).
    ///
    /// # Errors
    ///
    /// The validation's error, or [`FactorError::NonFinite`] naming the first
    /// non-finite output.
    ///
    /// # Panics
    ///
    /// If `residual`, `jacobians` or a block has the wrong length.
    fn linearize_into(
        &self,
        residual: &mut [f64],
        jacobians: &mut [Option<&mut [f64]>],
    ) -> Result<(), FactorError>;

    /// [`Factor::linearize_into`] by dual numbers, whether or not the factor
    /// has a generated kernel: the same outputs to rounding, with no
    /// allocation, for solvers that compare the two (every block is
    /// computed; those passed as `None` are not written).
    ///
    /// # Errors
    ///
    /// As [`Factor::linearize_into`].
    ///
    /// # Panics
    ///
    /// As [`Factor::linearize_into`].
    fn linearize_dual_into(
        &self,
        residual: &mut [f64],
        jacobians: &mut [Option<&mut [f64]>],
    ) -> Result<(), FactorError>;

    /// [`Factor::linearize_into`] for the factor stored as `stored` (its
    /// fields' scalars in declaration order, [`Storage`]): the factor is
    /// rebuilt from them for its validation, and the generated kernel reads
    /// its inputs straight from `stored`. The path of a solver that holds the
    /// scalars already (crate `factor-apex`); no allocation.
    ///
    /// # Errors
    ///
    /// As [`Factor::linearize_into`].
    ///
    /// # Panics
    ///
    /// If `stored` has the wrong length, or as [`Factor::linearize_into`].
    fn linearize_stored_into(
        stored: &[f64],
        residual: &mut [f64],
        jacobians: &mut [Option<&mut [f64]>],
    ) -> Result<(), FactorError>;

    /// [`Factor::linearize_stored_into`] at stored scalars the caller knows
    /// the factor accepts: the same outputs without the validation, their
    /// finiteness still checked. A solver that evaluates every trial step's
    /// residuals, validating each factor there, and linearizes only where it
    /// accepted a step meets no configuration here that the validation has
    /// not passed (`factor-schur`'s per-factor path; for apex-solver,
    /// [`crate::host::linearize_host_validated`]). By default
    /// [`Factor::linearize_stored_into`], validation included; the derive
    /// skips it for a factor with a generated kernel.
    ///
    /// # Errors
    ///
    /// [`FactorError::NonFinite`] naming the first non-finite output; by
    /// default also the validation's error.
    ///
    /// # Panics
    ///
    /// As [`Factor::linearize_stored_into`].
    fn linearize_stored_validated_into(
        stored: &[f64],
        residual: &mut [f64],
        jacobians: &mut [Option<&mut [f64]>],
    ) -> Result<(), FactorError> {
        Self::linearize_stored_into(stored, residual, jacobians)
    }

    /// A copy with variable `index` retracted (exactly) by `delta`, on that
    /// variable's perturbation side.
    fn with_retracted(&self, index: usize, delta: &[f64]) -> Self;

    /// Variable `variable`'s chart over any scalar `T`: `map` of its type's
    /// [`crate::Manifold`] on its perturbation side, at the value stored as
    /// `point` (see [`crate::manifold::ChartMap`]: `argument` a tangent or
    /// another value's stored scalars, `out` the result's stored scalars or
    /// tangent). What a code
    /// generator traces into a solver's manifold (crate `factor-codegen`,
    /// Ceres' `Manifold`), from the variable's type alone.
    ///
    /// # Errors
    ///
    /// [`crate::manifold::NoLocal`] for [`crate::manifold::ChartMap::Local`]
    /// of a type without [`crate::Manifold::local`].
    ///
    /// # Panics
    ///
    /// If `variable` is out of range or a slice has the wrong length.
    fn chart_over<T: Scalar>(
        variable: usize,
        map: crate::manifold::ChartMap,
        point: &[T],
        argument: &[T],
        out: &mut [T],
    ) -> Result<(), crate::manifold::NoLocal>;
}

/// `‖a − b‖_F / max(‖b‖_F, floor)`: the relative Frobenius error used by every
/// Jacobian comparison in this project. `floor` keeps a zero reference block
/// from turning a tiny absolute error into an infinite relative one.
pub fn relative_frobenius_error(a: &DMatrix<f64>, b: &DMatrix<f64>, floor: f64) -> f64 {
    (a - b).norm() / b.norm().max(floor)
}
