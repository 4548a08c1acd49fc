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
    /// `x ← Exp(δ) · x` (GTSAM's and document 000's convention for poses).
    Left,
    /// `x ← x · Exp(δ)` (document 001's body pose).
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

/// A value stored as a fixed list of scalars that can be rebuilt over another
/// scalar type: `f64` values are lifted to dual numbers or to symbols this way.
///
/// `map_scalars` visits the stored scalars in a fixed order (the order of
/// [`MapScalars::SCALARS`] storage slots), which is also the layout of a
/// generated kernel's input arrays.
pub trait MapScalars<S: Scalar> {
    /// The same value type over scalar `T`.
    type With<T: Scalar>;
    /// How many scalars are stored.
    const SCALARS: usize;
    /// Rebuilds the value with every stored scalar passed through `f`.
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Self::With<T>;
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
impl<S: Scalar> MapScalars<S> for S {
    type With<T: Scalar> = T;
    const SCALARS: usize = 1;
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> T {
        f(*self)
    }
}

impl<S: Scalar> Manifold<S> for S {
    const DIM: usize = 1;
    fn retract(&self, delta: &[S], _side: Perturbation) -> Self {
        *self + delta[0]
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "additive: x ← x + δ"
    }
}

impl<S: Scalar, const R: usize, const C: usize> MapScalars<S> for SMatrix<S, R, C> {
    type With<T: Scalar> = SMatrix<T, R, C>;
    const SCALARS: usize = R * C;
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> SMatrix<T, R, C> {
        // Column-major, nalgebra's storage order.
        SMatrix::<T, R, C>::from_iterator(self.iter().map(|&s| f(s)))
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
    use nalgebra::{Vector2, Vector3};

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

    #[test]
    fn map_scalars_changes_the_scalar_type_in_storage_order() {
        let v = Vector2::new(1.0_f64, 2.0);
        let w: Vector2<f32> = v.map_scalars(&mut |s| s as f32 * 2.0);
        assert_eq!(w, Vector2::new(2.0_f32, 4.0));
        assert_eq!(<Vector2<f64> as MapScalars<f64>>::SCALARS, 2);
    }
}
