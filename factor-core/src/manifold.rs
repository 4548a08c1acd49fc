//! Manifolds: tangent dimension, retraction and perturbation side.
//!
//! The Jacobian of a factor w.r.t. a variable `x` is the derivative of
//! `residual(retract(x, δ))` at `δ = 0`. Groups can be perturbed on either
//! side, chosen per variable ([`Perturbation`]), never crate-wide: document
//! 000 perturbs its camera pose on the left, document 001 its body pose on the
//! right.
//!
//! Two retractions are offered:
//! - [`Manifold::retract`] is exact (for example `Exp(δ) T` with the full SE(3)
//!   exponential). Numerical differentiation and solvers use it.
//! - [`Manifold::retract_first_order`] agrees with it to first order in `δ`
//!   at `δ = 0` (for example `(I + δ^) T`), which is all a derivative at
//!   `δ = 0` sees. Dual numbers and the symbolic tracer use it: it has no
//!   small-angle branch and costs a handful of operations. The result may be
//!   off the manifold by `O(|δ|²)` (a quaternion of norm `1 + O(|δ|²)`), which
//!   changes no first derivative of a smooth residual.

use nalgebra::{SMatrix, Scalar as NalgebraScalar};

use crate::scalar::Scalar;

/// Which side a group perturbation acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Perturbation {
    /// `x ← Exp(δ) · x`: document 000's convention for its camera pose and
    /// landmarks.
    Left,
    /// `x ← x · Exp(δ)`: document 001's body pose, and the retraction of
    /// GTSAM (`Pose3::retract`), manif (`rplus`) and apex-solver.
    Right,
}

impl Perturbation {
    /// `"left"` or `"right"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Perturbation::Left => "left",
            Perturbation::Right => "right",
        }
    }
}

/// A manifold with a retraction on a tangent space of dimension [`Manifold::DIM`].
pub trait Manifold<S: Scalar>: Sized {
    /// Tangent dimension.
    const DIM: usize;

    /// Exact retraction `x ⊞ δ` on the given side. `delta.len() == DIM`.
    fn retract(&self, delta: &[S], side: Perturbation) -> Self;

    /// A map that agrees with [`Manifold::retract`] to first order at `δ = 0`.
    fn retract_first_order(&self, delta: &[S], side: Perturbation) -> Self {
        self.retract(delta, side)
    }

    /// The perturbation and the tangent's column order in words, for reports.
    fn tangent_description(side: Perturbation) -> &'static str;
}

/// Scalars are a 1-dimensional vector space.
impl<S: Scalar> Manifold<S> for S {
    const DIM: usize = 1;
    fn retract(&self, delta: &[S], _side: Perturbation) -> Self {
        *self + delta[0]
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "additive: x ← x + δ"
    }
}

/// Fixed-size vectors and matrices are vector spaces: `x ← x + δ`, with `δ`
/// in column-major order (for a vector, its entries in order).
impl<S: Scalar + NalgebraScalar, const R: usize, const C: usize> Manifold<S> for SMatrix<S, R, C> {
    const DIM: usize = R * C;
    fn retract(&self, delta: &[S], _side: Perturbation) -> Self {
        let mut out = *self;
        for (x, d) in out.iter_mut().zip(delta) {
            *x += *d;
        }
        out
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "additive: x ← x + δ, columns δ in the vector's order"
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn vectors_retract_additively_on_either_side() {
        let x = Vector3::new(1.0, 2.0, 3.0);
        let d = [0.5, -1.0, 2.0];
        assert_eq!(
            x.retract(&d, Perturbation::Left),
            Vector3::new(1.5, 1.0, 5.0)
        );
        assert_eq!(
            x.retract(&d, Perturbation::Right),
            Vector3::new(1.5, 1.0, 5.0)
        );
        assert_eq!(<Vector3<f64> as Manifold<f64>>::DIM, 3);
    }
}
