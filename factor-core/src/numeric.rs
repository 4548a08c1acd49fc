//! Numerical differentiation: the Jacobians of [`NumericLinearize::linearize_numeric`],
//! an independent reference for the exact methods, with an error estimate.
//!
//! Each Jacobian column is the derivative of `h ↦ r(x ⊞ h eₖ)` at `h = 0`,
//! through the variable's exact retraction. It is found by Ridders' method:
//! central differences `(r(x ⊞ h eₖ) − r(x ⊞ −h eₖ)) / 2h` at steps shrinking
//! by a factor 1.4 are extrapolated to `h = 0` in a Neville tableau (each
//! column of it removes the next even power of `h` from the truncation
//! error), and every extrapolated value comes with an error estimate: its
//! distance to the two lower-order values it was built from, and at least
//! what rounding alone leaves (of the residuals, and of the step as the
//! stored scalars hold it). The value with the smallest estimate is kept.
//!
//! The steps are chosen per coordinate. The first is a tenth of the
//! variable's scale (the largest magnitude among its stored scalars), shrunk
//! until the retraction moves the stored scalars in proportion to the step
//! (so no rotation wraps around); the steps then shrink until the estimate
//! has stopped improving for a few rows (rounding has taken over), or a step
//! no longer changes the variable. Only rows in the asymptotic regime, where
//! consecutive quotients change little and less and less, are trusted: far
//! above the scale on which the residual is smooth, quotients can agree by
//! chance. A column the tableau cannot trust on its own, because its
//! quotients are noise, is judged again against the size of its block
//! (changes negligible for the block count as converged). A column whose
//! quotients are all within their rounding floor over the first steps is
//! zero to within rounding (a zero column is a legitimate Jacobian: a line's
//! residual does not change as the camera moves along the normal of its
//! interpretation plane), returned as 0 with that rounding as its absolute
//! error; a block made only of such columns counts as converged. (Before,
//! such a column's noise, or an exactly zero quotient taken for a step too
//! small to resolve, refused a line 1 m from the camera at some focal
//! lengths and not others.) A step at which
//! the factor cannot be evaluated (it crossed a degeneracy, such as the image
//! plane for a point near the camera) restarts the tableau below it, so no
//! configuration the exact methods accept is refused for a step's sake.
//!
//! When the estimated error of a block exceeds [`NUMERIC_TOLERANCE`]
//! relative to the block (Frobenius), the method fails with
//! [`FactorError::NumericNotConverged`] rather than return it: near a
//! degeneracy the `f64` residual itself can be too noisy for any step.
//! Measured against a double-double evaluation of the exact derivative
//! (`tests/numeric_accuracy.rs` of crate `slam-factors`): every block it
//! returns is within `1e-7` of the truth (5.8e-8 at worst, near
//! degeneracies) and within 4 times its estimate; on well-conditioned
//! configurations within about `1e-12`.

use nalgebra::{DMatrix, DVector};

use crate::factor::{DynLinearization, Factor, FactorError};
use crate::linalg::scaled_norm;
use crate::validation::within;

/// The largest estimated relative error (Frobenius, per Jacobian block) that
/// [`NumericLinearize::linearize_numeric`] returns; beyond it, it fails.
pub const NUMERIC_TOLERANCE: f64 = 1e-7;

/// The ratio of consecutive steps. Not a power of two: halving a step
/// halves its rounding in the stored scalars too, and an error that repeats
/// from row to row looks like convergence to the tableau.
const SHRINK: f64 = 1.4;

/// The most steps tried per coordinate: from a tenth of the variable's scale
/// down by `1.4¹⁶⁵ ≈ 10²⁴`.
const MAX_STEPS: usize = 165;

/// The most columns of the tableau kept (extrapolation up to `h¹²`).
const ORDERS: usize = 6;

/// The search stops once the best error has not improved for `STALL` rows
/// and the highest-order estimate has drifted from it by `SAFE` times that
/// error: rounding dominates from there on.
const SAFE: f64 = 2.0;
/// See [`SAFE`].
const STALL: usize = 4;

/// A quotient within this many times its rounding floor is rounding alone
/// (the same margin the asymptotic test gives "differ by rounding only").
const ROUNDING: f64 = 4.0;

/// Rows of quotients all within their rounding floor after which a column
/// with no trusted estimate is taken as zero to within rounding.
const ZERO_ROWS: usize = STALL + 2;

/// Residual and Jacobians by numerical differentiation, with the estimated
/// error of every Jacobian column.
#[derive(Debug, Clone, PartialEq)]
pub struct NumericLinearization {
    /// The residual and one Jacobian block per variable.
    pub linearization: DynLinearization,
    /// Per variable, the estimated error of each Jacobian column (Euclidean
    /// norm over the residual rows), in the tangent's order.
    pub column_errors: Vec<DVector<f64>>,
    /// Per variable, whether each column was found zero to within rounding:
    /// every difference quotient, over the first six steps,
    /// within its rounding floor. Its value is then 0 and its error
    /// estimate absolute: the largest of those quotients and floors. (A
    /// zero column is a legitimate Jacobian: the residual of a line does
    /// not change as the camera moves along the normal of its
    /// interpretation plane, for one.)
    pub zero_columns: Vec<Vec<bool>>,
}

impl NumericLinearization {
    /// The estimated error of block `k` (Frobenius norm).
    pub fn block_error(&self, k: usize) -> f64 {
        scaled_norm(&self.column_errors[k])
    }

    /// The estimated error of block `k` relative to the block (Frobenius):
    /// 0 for an exact zero block and for a block whose every column is zero
    /// to within rounding (an absolute criterion: their estimates are the
    /// rounding of the residual itself, [`NumericLinearization::zero_columns`]),
    /// infinite for an uncertain one.
    pub fn relative_block_error(&self, k: usize) -> f64 {
        let error = self.block_error(k);
        let block = scaled_norm(&self.linearization.jacobians[k]);
        if error == 0.0 || (block == 0.0 && self.zero_columns[k].iter().all(|z| *z)) {
            0.0
        } else if error.is_infinite() {
            f64::INFINITY
        } else {
            error / block
        }
    }
}

/// What one step of the central differences gave.
enum Step {
    /// The quotient `(r(x ⊞ h) − r(x ⊞ −h)) / 2h`, and the error rounding
    /// alone leaves in it (of the residuals, at the scale of the inputs, and
    /// of the step as stored).
    Quotient(DVector<f64>, f64),
    /// The factor cannot be evaluated at `x ⊞ ±h`.
    Failed(FactorError),
    /// `x ⊞ ±h` is `x`: the step is below the variable's resolution.
    Unresolved,
}

/// One Jacobian column as Ridders' tableau left it.
struct Column {
    value: DVector<f64>,
    error: f64,
    /// Whether `error` comes from rows in the asymptotic regime, or from
    /// rows that are all rounding (`zero`).
    trusted: bool,
    /// Whether every quotient was within its rounding floor: the column is
    /// zero to within rounding.
    zero: bool,
}

/// One Jacobian column of `rows` entries by Ridders' extrapolation over the
/// steps `first_step / SHRINKⁱ`; `step(h)` evaluates one. `block` is the
/// size of the column's Jacobian block when known (else 0): changes far
/// below it are negligible. Returns the last evaluation error when no step
/// could be evaluated.
///
/// Only tableau entries built from rows in the asymptotic regime are
/// trusted: there consecutive quotients differ by less than a quarter, and
/// by less than the difference before (the `h²` term shrinks by `SHRINK²`
/// per row) unless they differ by rounding only, or by a negligible amount
/// for the block. A step far above the scale on which the residual is
/// smooth gives quotients of no pattern, which can agree by chance. Without
/// a trusted entry the error is bounded by the largest quotient seen, unless
/// every quotient over [`ZERO_ROWS`] steps from the first lies within its
/// rounding floor: then the column is zero to within rounding (a derivative
/// larger than that would show above the floor at the largest steps), with
/// the largest of those quotients and floors as its error. An exactly zero
/// quotient is then no sign that the residual stopped resolving the step.
fn ridders_column(
    rows: usize,
    first_step: f64,
    block: f64,
    mut step: impl FnMut(f64) -> Step,
) -> Result<Column, FactorError> {
    let negligible = 0.01 * NUMERIC_TOLERANCE * block;
    let mut trusted: Option<(DVector<f64>, f64)> = None;
    let mut untrusted: Option<(DVector<f64>, f64)> = None;
    let mut largest_quotient = 0.0_f64;
    let mut last_error = None;
    // The previous row of the tableau (its estimates of orders 0, 1, …), the
    // change of its quotient from the row before, and for how many rows up
    // to it the change was asymptotic.
    let mut previous: Vec<DVector<f64>> = Vec::new();
    let mut previous_change: Option<f64> = None;
    let mut asymptotic_run = 0;
    let mut seen_nonzero = false;
    // While every quotient is rounding: how many, and the largest of them
    // and their floors.
    let (mut rounding_rows, mut rounding_error) = (0, 0.0_f64);
    let mut all_rounding = true;
    let mut stalled = 0;
    let mut h = first_step;
    for _ in 0..MAX_STEPS {
        let (quotient, floor) = match step(h) {
            Step::Quotient(quotient, floor) => (quotient, floor),
            Step::Unresolved => break,
            Step::Failed(e) => {
                // The step crossed a degeneracy: start over below it.
                last_error = Some(e);
                previous.clear();
                previous_change = None;
                asymptotic_run = 0;
                h /= SHRINK;
                continue;
            }
        };
        let zero = quotient.iter().all(|x| *x == 0.0);
        all_rounding &= quotient.norm() <= ROUNDING * floor;
        if all_rounding {
            rounding_rows += 1;
            rounding_error = rounding_error.max(quotient.norm()).max(floor);
            if rounding_rows >= ZERO_ROWS && trusted.is_none() {
                break;
            }
        } else if zero && seen_nonzero {
            // The residual no longer resolves the step: smaller ones only lose more.
            break;
        }
        seen_nonzero |= !zero;
        largest_quotient = largest_quotient.max(quotient.norm());
        let change = previous.first().map(|q| (&quotient - q).norm());
        let asymptotic = change.is_some_and(|c| {
            let small = c <= 0.25 * quotient.norm().max(previous[0].norm());
            let shrinking = previous_change.is_none_or(|b| c <= 0.8 * b);
            (small && (shrinking || c <= 4.0 * floor)) || c <= negligible
        });
        asymptotic_run = if asymptotic { asymptotic_run + 1 } else { 0 };
        let mut row = vec![quotient];
        let mut factor = SHRINK * SHRINK;
        let mut improved = false;
        for j in 1..=previous.len().min(ORDERS - 1) {
            // Neville: remove the h^(2j) term from this row's and the
            // previous row's estimates of order j − 1.
            let value = (&row[j - 1] * factor - &previous[j - 1]) / (factor - 1.0);
            let error = (&value - &row[j - 1])
                .norm()
                .max((&value - &previous[j - 1]).norm())
                .max(floor);
            // An entry of order j spans j + 1 rows: j changes, each judged
            // against the one before.
            let trust = asymptotic_run > j;
            let best = if trust { &mut trusted } else { &mut untrusted };
            if best.as_ref().is_none_or(|(_, e)| error <= *e) {
                improved |= trust;
                *best = Some((value.clone(), error));
            }
            factor *= SHRINK * SHRINK;
            row.push(value);
        }
        // Stop once the best estimate is within the tolerance and has not
        // improved over the last STALL rows, while the highest order drifts
        // from it: rounding dominates from here.
        stalled = if improved { 0 } else { stalled + 1 };
        if let (Some((value, error)), Some(top), Some(previous_top)) =
            (&trusted, row.last(), previous.last())
        {
            let converged = *error <= NUMERIC_TOLERANCE * value.norm().max(block);
            if converged && stalled >= STALL && (top - previous_top).norm() >= SAFE * error {
                break;
            }
        }
        previous_change = change;
        previous = row;
        h /= SHRINK;
    }
    let column = |(value, error), trusted| Column {
        value,
        error,
        trusted,
        zero: false,
    };
    if trusted.is_none() && all_rounding && rounding_rows >= ZERO_ROWS {
        return Ok(Column {
            value: DVector::zeros(rows),
            error: rounding_error,
            trusted: true,
            zero: true,
        });
    }
    match (trusted, untrusted, last_error) {
        (Some(best), _, _) => Ok(column(best, true)),
        (None, Some((value, error)), _) => Ok(column((value, error.max(largest_quotient)), false)),
        (None, None, Some(e)) => Err(e),
        (None, None, None) => Ok(column(
            (
                previous.pop().unwrap_or_else(|| DVector::zeros(rows)),
                f64::INFINITY,
            ),
            false,
        )),
    }
}

/// The first step for one coordinate: a tenth of the variable's `scale`,
/// shrunk until the retraction moves the stored scalars in proportion to
/// the step (within 10 % of a thousand times smaller step, scaled), so that
/// no step wraps a rotation around. `change(h)` is the change of the stored
/// scalars by a step of `h`.
fn first_step(scale: f64, mut change: impl FnMut(f64) -> DVector<f64>) -> f64 {
    let mut h = 0.1 * scale;
    for _ in 0..MAX_STEPS {
        let (far, near) = (change(h), change(h * 1e-3) * 1e3);
        if (&far - &near).norm() <= 0.1 * far.norm() {
            break;
        }
        h /= SHRINK;
    }
    h
}

/// Numerical differentiation for every factor: `factor.linearize_numeric()`
/// with this trait in scope (`use factor_core::NumericLinearize`).
pub trait NumericLinearize: Factor {
    /// Residual and Jacobians by numerical differentiation through the
    /// exact retraction of each variable, with the estimated error of every
    /// Jacobian column: an independent reference for the dual and generated
    /// Jacobians (see the module documentation for the method).
    ///
    /// # Errors
    ///
    /// The validation's error, [`FactorError::NonFinite`], or
    /// [`FactorError::NumericNotConverged`] when a block's estimated relative
    /// error exceeds [`NUMERIC_TOLERANCE`].
    fn linearize_numeric(&self) -> Result<NumericLinearization, FactorError> {
        linearize_numeric(self)
    }

    /// [`NumericLinearize::linearize_numeric`] without the error estimates.
    ///
    /// # Errors
    ///
    /// As [`NumericLinearize::linearize_numeric`].
    fn linearize_numeric_dyn(&self) -> Result<DynLinearization, FactorError> {
        self.linearize_numeric()
            .map(|numeric| numeric.linearization)
    }
}

impl<F: Factor> NumericLinearize for F {}

/// [`NumericLinearize::linearize_numeric`].
fn linearize_numeric<F: Factor>(factor: &F) -> Result<NumericLinearization, FactorError> {
    factor.validate()?;
    let residual = factor.residual_dyn()?;
    let stored = factor.to_scalars();
    let input_scale = stored.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let variables = F::variables();
    let mut jacobians = Vec::with_capacity(variables.len());
    let mut column_errors = Vec::with_capacity(variables.len());
    let mut zero_columns = Vec::with_capacity(variables.len());
    for (index, variable) in variables.iter().enumerate() {
        let scale = variable_scale::<F>(&stored, index);
        let dim = variable.tangent_dim;
        let column = |coordinate: usize, block: f64| {
            let retracted = |h: f64| {
                let mut delta = vec![0.0; dim];
                delta[coordinate] = h;
                factor.with_retracted(index, &delta)
            };
            let change = |h: f64| {
                let scalars = retracted(h).to_scalars();
                DVector::from_iterator(
                    stored.len(),
                    scalars.iter().zip(&stored).map(|(a, b)| a - b),
                )
            };
            let step = |h: f64| {
                let (plus, minus) = (retracted(h), retracted(-h));
                let (to_plus, to_minus) = (moved(&plus, &stored), moved(&minus, &stored));
                if to_plus.is_none() && to_minus.is_none() {
                    return Step::Unresolved;
                }
                // The step as stored is off by rounding, relative
                // `ε ‖x‖ / ‖Δx‖` over the stored scalars it changes.
                let step_rounding = [to_plus, to_minus]
                    .into_iter()
                    .flatten()
                    .fold(0.0_f64, |worst, (x, dx)| worst.max(f64::EPSILON * x / dx));
                match (plus.residual_dyn(), minus.residual_dyn()) {
                    (Ok(plus), Ok(minus)) => {
                        let quotient = (&plus - &minus) / (2.0 * h);
                        // A residual is often the difference of terms as
                        // large as the inputs (pixels of order 10²): its
                        // rounding is relative to the larger of the two.
                        let magnitude =
                            scaled_norm(&plus).max(scaled_norm(&minus)).max(input_scale);
                        let floor =
                            f64::EPSILON * magnitude / h + step_rounding * scaled_norm(&quotient);
                        Step::Quotient(quotient, floor)
                    }
                    (Err(e), _) | (_, Err(e)) => Step::Failed(e),
                }
            };
            ridders_column(F::RESIDUAL_DIM, first_step(scale, change), block, step)
        };
        let mut columns = (0..dim)
            .map(|coordinate| column(coordinate, 0.0))
            .collect::<Result<Vec<Column>, FactorError>>()?;
        // A column the tableau could not trust may be noise far below the
        // block: judge its changes against the block and try again.
        let block = columns
            .iter()
            .filter(|c| c.trusted)
            .map(|c| c.value.norm_squared())
            .sum::<f64>()
            .sqrt();
        for (coordinate, slot) in columns.iter_mut().enumerate() {
            if !slot.trusted && block > 0.0 {
                *slot = column(coordinate, block)?;
            }
        }
        let mut matrix = DMatrix::zeros(F::RESIDUAL_DIM, dim);
        for (coordinate, c) in columns.iter().enumerate() {
            matrix.set_column(coordinate, &c.value);
        }
        jacobians.push(matrix);
        column_errors.push(DVector::from_iterator(dim, columns.iter().map(|c| c.error)));
        zero_columns.push(columns.iter().map(|c| c.zero).collect());
    }
    let names: Vec<&str> = variables.iter().map(|v| v.name).collect();
    let numeric = NumericLinearization {
        linearization: DynLinearization {
            residual,
            jacobians,
        }
        .ensure_finite(F::NAME, &names)?,
        column_errors,
        zero_columns,
    };
    for (k, variable) in variables.iter().enumerate() {
        let estimate = numeric.relative_block_error(k);
        // A NaN estimate fails too.
        if !within(estimate, NUMERIC_TOLERANCE) {
            return Err(FactorError::NumericNotConverged {
                tolerance: NUMERIC_TOLERANCE,
                factor: F::NAME,
                variable: variable.name,
                coordinate: numeric.column_errors[k].imax(),
                estimate,
            });
        }
    }
    Ok(numeric)
}

/// How `retracted` differs from `stored` (a factor's stored scalars): the
/// norms of the stored scalars that changed and of their change, or `None`
/// when none did.
fn moved<F: Factor>(retracted: &F, stored: &[f64]) -> Option<(f64, f64)> {
    let (mut x, mut dx) = (0.0_f64, 0.0_f64);
    for (a, b) in retracted.to_scalars().iter().zip(stored) {
        if a != b {
            x = x.hypot(*b);
            dx = dx.hypot(a - b);
        }
    }
    (dx > 0.0).then_some((x, dx))
}

/// The largest magnitude among variable `index`'s stored scalars, or 1 when
/// they are all zero.
fn variable_scale<F: Factor>(stored: &[f64], index: usize) -> f64 {
    let mut offset = 0;
    let mut scale = 0.0_f64;
    for field in F::fields() {
        if field.variable == Some(index) {
            scale = stored[offset..offset + field.scalars]
                .iter()
                .fold(0.0, |m, x| m.max(x.abs()));
        }
        offset += field.scalars;
    }
    if scale > 0.0 { scale } else { 1.0 }
}
