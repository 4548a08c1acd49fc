//! Unit quaternions as a Lie group (the double cover of SO(3)).
//!
//! The tangent is the rotation vector `ω` of `exp(ω) = [sin(θ/2) ω/θ,
//! cos(θ/2)]`, so the adjoint and the Jacobians are those of SO(3):
//! `q ⊗ exp(ω) ⊗ q⁻¹ = exp(R(q) ω)`, and `Jl`, `Jr` and their inverses are
//! [`crate::lie::so3`]'s. Unlike [`crate::lie::So3`], `q` and `−q` are
//! distinct elements here: [`Quaternion::log`] inverts `exp` on the whole
//! sphere (`|ω| < 2π`), so `minus` of two quaternions on opposite sheets is
//! the long way round.

use nalgebra::{Matrix3, Vector3};

use crate::lie::so3::{left_jacobian, left_jacobian_inverse};
use crate::lie::{LieGroup, Quaternion};
use crate::scalar::Scalar;

/// The group of unit quaternions under the Hamilton product; the inverse is
/// the conjugate (exact on the unit sphere, where [`Quaternion::inverse`]
/// would divide by `|q|² = 1`); `act` rotates a point, `q ⊗ [p, 0] ⊗ q⁻¹`.
impl<S: Scalar> LieGroup<S> for Quaternion<S> {
    const DOF: usize = 3;
    type Tangent = Vector3<S>;
    type Jacobian = Matrix3<S>;
    type Point = Vector3<S>;

    fn identity() -> Self {
        Quaternion::identity()
    }
    fn compose(&self, rhs: &Self) -> Self {
        self.mul(rhs)
    }
    fn inverse(&self) -> Self {
        self.conjugate()
    }
    fn act(&self, point: &Vector3<S>) -> Vector3<S> {
        self.rotate(point)
    }
    fn exp(tau: &Vector3<S>) -> Self {
        Quaternion::exp(tau)
    }
    fn log(&self) -> Vector3<S> {
        Quaternion::log(self)
    }
    fn adjoint(&self) -> Matrix3<S> {
        self.to_rotation_matrix()
    }
    fn left_jacobian(tau: &Vector3<S>) -> Matrix3<S> {
        left_jacobian(tau)
    }
    fn left_jacobian_inverse(tau: &Vector3<S>) -> Matrix3<S> {
        left_jacobian_inverse(tau)
    }
}
