//! A factor's generated kernel against its dual-number linearization: both
//! exact, so they differ by rounding only.

use factor_core::factor::{DynLinearization, Factor, FactorError, relative_frobenius_error};

use crate::numeric::JacobianCheck;

/// The tolerance of [`assert_generated_matches_dual`]: rounding only.
pub const GENERATED_TOLERANCE: f64 = 1e-12;

/// The scale a residual's rounding error lives at: the largest magnitude
/// among the factor's stored scalars (pixel coordinates and focal lengths of
/// order 10²–10³, unit-vector entries of order 1), or 1.
///
/// A residual is often the difference of terms of that size (a line
/// residual sums pixel coordinates of order 500 times the line's
/// coefficients down to a fraction of a pixel; plane and free-line residuals
/// are differences of unit-vector products), so two correct evaluation orders
/// differ by rounding of the terms, not of the result. The residual is
/// therefore compared relative to `max(‖r‖, input scale)`: a backward-error
/// measure. Jacobian blocks are compared relatively down to `1e-9`.
pub fn input_scale<F: Factor>(factor: &F) -> f64 {
    factor
        .to_scalars()
        .iter()
        .fold(1.0_f64, |scale, x| scale.max(x.abs()))
}

/// Relative errors of the residual and of each block of `a` w.r.t. `b`, as
/// [`input_scale`] describes.
pub fn compare<F: Factor>(factor: &F, a: &DynLinearization, b: &DynLinearization) -> JacobianCheck {
    let scale = input_scale(factor);
    let residual_error = (&a.residual - &b.residual).norm() / b.residual.norm().max(scale);
    let block_errors = F::variables()
        .iter()
        .zip(a.jacobians.iter().zip(&b.jacobians))
        .map(|(v, (x, y))| (v.name, relative_frobenius_error(x, y, 1e-9)))
        .collect();
    JacobianCheck {
        residual_error,
        block_errors,
        reference_errors: Vec::new(),
    }
}

/// Compares the generated kernel's linearization with dual numbers; `None`
/// when the factor has no kernel (in this build).
///
/// # Errors
///
/// When the factor cannot be linearized at this configuration.
pub fn check_generated<F: Factor>(factor: &F) -> Result<Option<JacobianCheck>, FactorError> {
    let Some(generated) = factor.linearize_generated_dyn() else {
        return Ok(None);
    };
    let generated = generated?;
    let dual = factor.linearize_dual_dyn()?;
    Ok(Some(compare(factor, &generated, &dual)))
}

/// Panics, naming the output, when the generated kernel's residual or a
/// Jacobian block differs from dual numbers by more than `tolerance`
/// (relative, see [`input_scale`]), when the factor has no kernel, or when it
/// cannot be linearized. This is the test that a kernel is current: a
/// residual edited since the kernel was generated fails it (in a debug
/// build with the report of [`FactorError::StaleKernel`], naming the
/// command that regenerates the kernel).
#[track_caller]
pub fn assert_generated_matches_dual<F: Factor>(factor: &F, tolerance: f64) {
    let check = match check_generated(factor) {
        Ok(Some(check)) => check,
        Ok(None) => panic!(
            "{} has no generated kernel in this build (`#[factor(kernel = ...)]`)",
            F::NAME
        ),
        // A debug build's own comparison found the kernel stale first: its
        // report names the output and the command that regenerates it.
        Err(e @ FactorError::StaleKernel { .. }) => panic!("{e}"),
        Err(e) => panic!("{} cannot be linearized: {e}", F::NAME),
    };
    assert!(
        check.residual_error <= tolerance,
        "{}: generated residual differs from dual numbers by {:e} (tolerance {tolerance:e})",
        F::NAME,
        check.residual_error
    );
    for (name, error) in &check.block_errors {
        assert!(
            *error <= tolerance,
            "{}: generated Jacobian w.r.t. `{name}` differs from dual numbers by {error:e} \
             (relative Frobenius, tolerance {tolerance:e})",
            F::NAME
        );
    }
}
