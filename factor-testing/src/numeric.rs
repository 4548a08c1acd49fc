//! Dual-number Jacobians against numerical differentiation on the manifolds
//! ([`NumericLinearize::linearize_numeric`]: Ridders' extrapolation of central
//! differences, with an error estimate).

use factor_core::NumericLinearize;
use factor_core::factor::{Factor, relative_frobenius_error};

/// The default tolerance on the relative Frobenius error of each block.
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// How far one linearization of a factor is from a reference: dual numbers
/// from numerical differentiation ([`check_jacobians`]), or a generated kernel from
/// dual numbers ([`crate::check_generated`]).
#[derive(Debug, Clone, PartialEq)]
pub struct JacobianCheck {
    /// Relative error of the residual.
    pub residual_error: f64,
    /// Per variable: its name and the relative Frobenius error of its block.
    pub block_errors: Vec<(&'static str, f64)>,
    /// Per variable, when the reference is numerical ([`check_jacobians`]):
    /// the reference block's own estimated relative error (Frobenius), to
    /// read beside the difference. Empty for an exact reference.
    pub reference_errors: Vec<f64>,
}

impl JacobianCheck {
    /// The largest error over the residual and every block.
    pub fn max_error(&self) -> f64 {
        self.block_errors
            .iter()
            .map(|(_, e)| *e)
            .fold(self.residual_error, f64::max)
    }
}

/// Compares the dual-number linearization with numerical differentiation.
///
/// Errors are relative to the numerical block's Frobenius norm, floored at
/// `1e-9` so a structurally zero block is compared absolutely; beside each,
/// [`JacobianCheck::reference_errors`] holds the numerical block's estimated
/// error.
///
/// # Errors
///
/// When the factor cannot be linearized, including
/// [`factor_core::FactorError::NumericNotConverged`] when the numerical
/// reference cannot be estimated to its tolerance.
pub fn check_jacobians<F: Factor>(factor: &F) -> Result<JacobianCheck, factor_core::FactorError> {
    let dual = factor.linearize_dual_dyn()?;
    let numeric = factor.linearize_numeric()?;
    let reference = &numeric.linearization;
    let residual_error =
        (&dual.residual - &reference.residual).norm() / reference.residual.norm().max(1e-9);
    let block_errors = F::variables()
        .iter()
        .zip(dual.jacobians.iter().zip(&reference.jacobians))
        .map(|(v, (d, n))| (v.name, relative_frobenius_error(d, n, 1e-9)))
        .collect();
    let reference_errors = (0..reference.jacobians.len())
        .map(|k| numeric.relative_block_error(k))
        .collect();
    Ok(JacobianCheck {
        residual_error,
        block_errors,
        reference_errors,
    })
}

/// Panics, naming the variable and showing both blocks, when a dual-number
/// Jacobian block differs from numerical differentiation by more than
/// `tolerance` (relative Frobenius error; the message gives the numerical
/// block's estimated error beside it), or when the factor cannot be
/// linearized.
#[track_caller]
pub fn assert_correct_jacobians<F: Factor>(factor: &F, tolerance: f64) {
    let check = match check_jacobians(factor) {
        Ok(check) => check,
        Err(e) => panic!("{} cannot be linearized: {e}", F::NAME),
    };
    assert!(
        check.residual_error <= tolerance,
        "{}: dual residual differs from the plain residual by {:e}",
        F::NAME,
        check.residual_error
    );
    for (index, (name, error)) in check.block_errors.iter().enumerate() {
        if *error > tolerance {
            let dual = factor.linearize_dual_dyn().expect("linearized above");
            let numeric = factor.linearize_numeric_dyn().expect("linearized above");
            panic!(
                "{}: Jacobian w.r.t. `{name}` is off by {error:e} (relative Frobenius, tolerance \
                 {tolerance:e}; the numerical reference's estimated error is {:e})\n\
                 dual:{}numeric:{}",
                F::NAME,
                check.reference_errors[index],
                dual.jacobians[index],
                numeric.jacobians[index]
            );
        }
    }
}
