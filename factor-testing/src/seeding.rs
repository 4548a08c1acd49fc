//! The dual-number linearization against an independent path to the same
//! derivative: the seeded one pass of `linearize_dual` (each variable
//! seeded through [`Manifold::seeded`](factor_core::Manifold::seeded)) and
//! [`Factor::perturbed_residual_over`] on one-component dual numbers, one
//! tangent column at a time, through every variable's
//! `retract_first_order` at `δ = 0`.
//!
//! The two share the residual but not the seeding: a
//! `Manifold::seeded` override (a closed form) that disagrees with the
//! retraction it stands for is caught here, where central differences
//! would also catch it but at their own tolerance.

use factor_core::dual::Dual;
use factor_core::factor::relative_frobenius_error;
use factor_core::{DynLinearization, Factor};
use nalgebra::{DMatrix, DVector};

/// The residual and Jacobian blocks of `factor` through
/// [`Factor::perturbed_residual_over`], one dual pass per tangent column.
pub fn dual_through_retraction<F: Factor>(factor: &F) -> DynLinearization {
    let stored: Vec<Dual<1>> = factor
        .to_scalars()
        .into_iter()
        .map(Dual::constant)
        .collect();
    let mut delta = vec![Dual::<1>::constant(0.0); F::TANGENT_DIM];
    let residual: Vec<f64> = F::perturbed_residual_over(&stored, &delta)
        .iter()
        .map(|r| r.re)
        .collect();
    let columns: Vec<Vec<f64>> = (0..F::TANGENT_DIM)
        .map(|c| {
            delta[c] = Dual::variable(0.0, 0);
            let column = F::perturbed_residual_over(&stored, &delta);
            delta[c] = Dual::constant(0.0);
            column.iter().map(|r| r.eps[0]).collect()
        })
        .collect();
    let mut offset = 0;
    let jacobians = F::variables()
        .iter()
        .map(|v| {
            let block = DMatrix::from_fn(F::RESIDUAL_DIM, v.tangent_dim, |r, c| {
                columns[offset + c][r]
            });
            offset += v.tangent_dim;
            block
        })
        .collect();
    DynLinearization {
        residual: DVector::from_vec(residual),
        jacobians,
    }
}

/// Panics unless `factor`'s `linearize_dual` (seeded, one pass) agrees with
/// [`dual_through_retraction`] within `tolerance` (relative Frobenius per
/// block, [`relative_frobenius_error`] with a floor of 1). Both are exact to
/// rounding: `1e-13` separates them by far.
///
/// ```
/// use factor_testing::samples::Sampler;
/// factor_testing::seeding::assert_seeding_matches_retraction(
///     &Sampler::new(1).snavely_reprojection(),
///     1e-13,
/// );
/// ```
///
/// # Panics
///
/// If the factor does not linearize, or an output differs beyond `tolerance`.
pub fn assert_seeding_matches_retraction<F: Factor>(factor: &F, tolerance: f64) {
    let seeded = factor
        .linearize_dual_dyn()
        .unwrap_or_else(|e| panic!("{}: {e}", F::NAME));
    let reference = dual_through_retraction(factor);
    let residual =
        (&seeded.residual - &reference.residual).norm() / reference.residual.norm().max(1.0);
    assert!(
        residual <= tolerance,
        "{}: residual differs by {residual:e}",
        F::NAME
    );
    for ((a, b), v) in seeded
        .jacobians
        .iter()
        .zip(&reference.jacobians)
        .zip(F::variables())
    {
        let error = relative_frobenius_error(a, b, 1.0);
        assert!(
            error <= tolerance,
            "{}: the seeded Jacobian w.r.t. `{}` differs from the retraction's by {error:e}:\n\
             seeded {a}\nthrough the retraction {b}",
            F::NAME,
            v.name
        );
    }
}
