//! Dual-number Jacobians against central differences on the manifolds.

use factor_core::factor::{Factor, relative_frobenius_error};

/// The default tolerance on the relative Frobenius error of each block.
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// How far one linearization of a factor is from a reference: dual numbers
/// from central differences ([`check_jacobians`]), or a generated kernel from
/// dual numbers ([`crate::check_generated`]).
#[derive(Debug, Clone, PartialEq)]
pub struct JacobianCheck {
    /// Relative error of the residual.
    pub residual_error: f64,
    /// Per variable: its name and the relative Frobenius error of its block.
    pub block_errors: Vec<(&'static str, f64)>,
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

/// Compares the dual-number linearization with central differences.
///
/// Errors are relative to the numerical block's Frobenius norm, floored at
/// `1e-9` so a structurally zero block is compared absolutely.
pub fn check_jacobians<F: Factor>(factor: &F) -> Result<JacobianCheck, factor_core::FactorError> {
    let dual = factor.linearize_dual_dyn()?;
    let numeric = factor.linearize_numeric_dyn()?;
    let residual_error =
        (&dual.residual - &numeric.residual).norm() / numeric.residual.norm().max(1e-9);
    let block_errors = F::variables()
        .iter()
        .zip(dual.jacobians.iter().zip(&numeric.jacobians))
        .map(|(v, (d, n))| (v.name, relative_frobenius_error(d, n, 1e-9)))
        .collect();
    Ok(JacobianCheck {
        residual_error,
        block_errors,
    })
}

/// Panics, naming the variable and showing both blocks, when a dual-number
/// Jacobian block differs from central differences by more than `tolerance`
/// (relative Frobenius error), or when the factor cannot be linearized.
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
    for (name, error) in &check.block_errors {
        if *error > tolerance {
            let dual = factor.linearize_dual_dyn().expect("linearized above");
            let numeric = factor.linearize_numeric_dyn().expect("linearized above");
            let index = F::variables()
                .iter()
                .position(|v| v.name == *name)
                .expect("known variable");
            panic!(
                "{}: Jacobian w.r.t. `{name}` is off by {error:e} (relative Frobenius, tolerance {tolerance:e})\n\
                 dual:{}numeric:{}",
                F::NAME,
                dual.jacobians[index],
                numeric.jacobians[index]
            );
        }
    }
}
