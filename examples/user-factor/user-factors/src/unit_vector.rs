//! S²: unit vectors of R³ (directions: bearings, surface normals, gravity,
//! vanishing directions), a manifold that is not a group, with a 2-dof
//! tangent.
//!
//! # Tangent basis
//!
//! The tangent plane at `v` is spanned by the columns of a 3×2 orthonormal
//! basis `B(v) = [b₁, b₂]` with `b₁ × b₂ = v`, the branch-free-per-hemisphere
//! basis of T. Duff et al., "Building an Orthonormal Basis, Revisited",
//! JCGT 6(1), 2017: with `s = ±1` the sign of `v_z` and `a = −1/(s + v_z)`,
//!
//! `b₁ = [1 + s a v_x², s a v_x v_y, −s v_x]`, `b₂ = [a v_x v_y, s + a v_y², −v_y]`.
//!
//! Each branch is a rational function of `v` whose denominator `s + v_z` is at
//! least 1 in magnitude on its closed hemisphere (`v_z ≥ 0` for `s = +1`,
//! `v_z < 0` for `s = −1`), so `B` is smooth on each branch and finite at its
//! boundary. The branch is chosen by one `Scalar::select_lt(v_z, 0, −1, 1)`;
//! at a tie (`v_z = 0` or `−0`) `select_lt` takes its `otherwise` arm, `s = +1`,
//! in every scalar type (`f64`, dual numbers, the tracer, generated kernels).
//!
//! No choice can be continuous everywhere (a continuous tangent frame on S²
//! would be a nowhere-vanishing tangent field, which the hairy-ball theorem
//! rules out), so `B` jumps across the equator `v_z = 0`: on either side the
//! bases differ by a rotation of the tangent plane (at `v = [1, 0, 0]` they
//! are opposite, `B₋ = −B₊`).
//!
//! # What that means for Jacobians
//!
//! A Jacobian w.r.t. a `UnitVector3` is `∂r(v ⊞ δ)/∂δ = J_v B(v)`, where `J_v`
//! is the derivative w.r.t. the three coordinates: it is exact and well
//! defined at every `v`, in the coordinates of *that branch's* basis. Two
//! Jacobians at points on either side of the equator (or one computed with a
//! basis of another library) are therefore not comparable column by column:
//! compare `J B(v)ᵀ` (the derivative along the sphere, in R³), or move one to
//! the other's basis with the 2×2 rotation `B₁ᵀ B₂`. A solver is unaffected:
//! it steps `v ← v ⊞ δ` with the basis of the `v` it linearised at. A
//! covariance of a direction, however, is expressed in that basis too.

use factor_core::lie::SMALL_ANGLE_SQUARED;
use factor_core::lie::so3::{one_minus_cos_over_theta2, sin_over_theta};
use factor_core::manifold::NoLocal;
use factor_core::validation::number_text;
use factor_core::{Layout, Manifold, Perturbation, Scalar, Storage, StorageError};
use nalgebra::{Matrix3x2, Vector2, Vector3};

/// How far from 1 the norm of a direction given by a user may be; within it
/// [`Storage::from_input`] re-normalises it, beyond it rejects it (the
/// tolerance of `factor_core` for quaternions).
pub const UNIT_NORM_TOLERANCE: f64 = factor_core::storage::QUATERNION_NORM_TOLERANCE;

/// A unit vector `v ∈ S²`, stored `[x, y, z]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnitVector3<S> {
    vector: Vector3<S>,
}

impl<S: Scalar> UnitVector3<S> {
    /// From a vector of unit norm, taken as it is (not checked: values from
    /// users go through [`Storage::from_input`]).
    pub fn from_unit(vector: Vector3<S>) -> Self {
        UnitVector3 { vector }
    }

    /// The direction of a non-zero vector, `v / ‖v‖`.
    pub fn from_direction(vector: &Vector3<S>) -> Self {
        Self::from_unit(factor_core::linalg::normalized(vector))
    }

    /// The unit vector's coordinates.
    pub fn vector(&self) -> Vector3<S> {
        self.vector
    }

    /// The tangent basis `B(v) = [b₁, b₂]`, 3×2 orthonormal with
    /// `b₁ × b₂ = v`, on the branch of the sign of `v_z` (see the module
    /// documentation).
    pub fn basis(&self) -> Matrix3x2<S> {
        let (x, y, z) = (self.vector.x, self.vector.y, self.vector.z);
        let one = S::one();
        // The one branch: s = −1 below the equator, +1 on and above it.
        let s = S::select_lt(z, S::zero(), -one, one);
        let a = -(s + z).recip();
        let xy = x * y * a;
        // Row by row: the columns are b₁ and b₂.
        Matrix3x2::new(one + s * a * x * x, xy, s * xy, s + a * y * y, -(s * x), -y)
    }
}

/// Stored `[x, y, z]`; from users, a norm within [`UNIT_NORM_TOLERANCE`] of 1,
/// re-normalised.
impl<S: Scalar> Storage<S> for UnitVector3<S> {
    type With<T: Scalar> = UnitVector3<T>;
    const SCALARS: usize = 3;
    fn layout() -> Layout {
        Layout::array(&["x", "y", "z"])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> UnitVector3<T> {
        UnitVector3::from_unit(self.vector.map_scalars(f))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        Self::from_unit(Vector3::read_scalars(next))
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        let norm = input.iter().map(|x| x * x).sum::<f64>().sqrt();
        if (norm - 1.0).abs() <= UNIT_NORM_TOLERANCE {
            Ok(input.iter().map(|x| x / norm).collect())
        } else {
            Err(StorageError::new(format!(
                "unit vector [x, y, z] has norm {}, expected 1 (within {UNIT_NORM_TOLERANCE:e})",
                number_text(norm)
            )))
        }
    }
}

/// Tangent `δ = [δ₁, δ₂]`, the coordinates along `B(v) = [b₁, b₂]`. S² is
/// not a group: both sides are the same retraction.
///
/// - Exact: the geodesic `v ⊞ δ = cos θ v + (sin θ/θ) B(v) δ`, `θ = ‖δ‖`
///   (the rotation of `v` by `Exp(v × B(v) δ)`), with the small-angle
///   coefficients of `factor_core` (series in `θ²`).
/// - First order: `v + B(v) δ`, of norm `1 + O(‖δ‖²)`.
///
/// The basis is `B` of the point `v`, never of `v ⊞ δ`: the branch is decided
/// by the point alone.
///
/// `local` inverts the geodesic: with `b = B(v)ᵀ w` and `c = v · w` for the
/// other point `w`, `θ = atan2(‖b‖, c)` and `δ = θ b/‖b‖`, every direction
/// but `−v` (a solver's manifold, Ceres' `Minus`, is generated from it).
/// Near `v` (`‖b‖²/c² <` the small-angle threshold, `c > 0`) `θ/‖b‖` is the
/// series `(1 − r/3 + r²/5)/c` in `r = ‖b‖²/c²`, as the quaternion
/// logarithm of `factor_core` writes it: `‖b‖` has an infinite derivative at
/// `w = v`, where `local` is differentiated. Both forms are homogeneous of
/// degree 0 in `w`, so `w` off the sphere gives the same `δ` as `w/‖w‖`.
impl<S: Scalar> Manifold<S> for UnitVector3<S> {
    const DIM: usize = 2;
    fn retract(&self, delta: &[S], _side: Perturbation) -> Self {
        let d = Vector2::new(delta[0], delta[1]);
        let theta2 = d.x * d.x + d.y * d.y;
        let cos = S::one() - theta2 * one_minus_cos_over_theta2(theta2);
        let sinc = sin_over_theta(theta2);
        let step = self.basis() * d;
        Self::from_unit(self.vector.map(|x| cos * x) + step.map(|x| sinc * x))
    }
    fn retract_first_order(&self, delta: &[S], _side: Perturbation) -> Self {
        Self::from_unit(self.vector + self.basis() * Vector2::new(delta[0], delta[1]))
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "either side: v ← cos‖δ‖ v + sin‖δ‖/‖δ‖ B(v) δ, columns [δ₁, δ₂] along B(v) = [b₁, b₂] \
         (Duff et al. 2017, branch on the sign of v_z)"
    }
    fn local(&self, other: &Self, _side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        let b = self.basis().transpose() * other.vector;
        let c = factor_core::linalg::dot(&self.vector, &other.vector);
        let s2 = b.x * b.x + b.y * b.y;
        let r = s2 / (c * c);
        let series = (S::one() - r / S::from_f64(3.0) + r * r / S::from_f64(5.0)) / c;
        let s = s2.sqrt();
        let exact = s.atan2(c) / s;
        let near = S::select_lt(r, S::from_f64(SMALL_ANGLE_SQUARED), series, exact);
        let k = S::select_lt(S::zero(), c, near, exact);
        delta[..2].copy_from_slice(&[k * b.x, k * b.y]);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Directions on both branches, on the boundary (`z = ±0`), next to it,
    /// and at the poles.
    const DIRECTIONS: [[f64; 3]; 9] = [
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, -1.0, -0.0],
        [0.6, 0.8, 1e-12],
        [0.6, 0.8, -1e-12],
        [0.3, -0.4, 0.5],
        [-0.2, 0.1, -0.9],
        [0.5, 0.5, -0.5],
    ];

    #[test]
    fn the_basis_is_orthonormal_right_handed_and_tangent() {
        for d in DIRECTIONS {
            let v = UnitVector3::from_direction(&Vector3::from(d));
            let b = v.basis();
            let (b1, b2) = (b.column(0).into_owned(), b.column(1).into_owned());
            let e = (b.transpose() * b - nalgebra::Matrix2::identity()).amax();
            assert!(e < 1e-15, "{d:?}: BᵀB − I = {e:e}");
            assert!((b1.cross(&b2) - v.vector()).amax() < 1e-15, "{d:?}");
            assert!((b.transpose() * v.vector()).amax() < 1e-15, "{d:?}");
        }
    }

    /// `−0` is a tie and takes the `z ≥ 0` branch, as `+0` does; just below
    /// zero the other branch, whose basis differs by a rotation of the plane.
    #[test]
    fn the_branch_boundary_is_z_equal_zero() {
        let at = |z: f64| UnitVector3::from_unit(Vector3::new(1.0, 0.0, z)).basis();
        assert_eq!(at(0.0), at(-0.0));
        let (above, below) = (at(1e-300), at(-1e-300));
        assert_eq!(above, at(0.0));
        assert!((below + above).amax() < 1e-15, "B₋ = −B₊ at [1, 0, 0]");
    }

    /// The geodesic stays on the sphere, moves by the angle `‖δ‖` along
    /// `B δ`, and agrees with the first-order retraction to `O(‖δ‖²)`.
    #[test]
    fn retractions_are_geodesic_and_agree_to_first_order() {
        for d in DIRECTIONS {
            let v = UnitVector3::from_direction(&Vector3::from(d));
            for delta in [[0.3, -0.2], [1e-4, 2e-4], [0.0, 0.0], [2.0, 1.0]] {
                let moved = v.retract(&delta, Perturbation::Left).vector();
                let angle = v.vector().angle(&moved);
                let norm = (delta[0] * delta[0] + delta[1] * delta[1]).sqrt();
                assert!((moved.norm() - 1.0).abs() < 1e-15);
                assert!((angle - norm).abs() < 1e-7, "{d:?} {delta:?}");
                let step = v.basis() * Vector2::from(delta);
                let first = v.retract_first_order(&delta, Perturbation::Right).vector();
                assert!((moved - first).norm() <= norm * norm, "{d:?} {delta:?}");
                // It moves towards B δ: the component along it is sin θ.
                assert!((moved.dot(&step) - norm * norm.sin()).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn users_write_unit_vectors_within_tolerance() {
        let stored = UnitVector3::<f64>::from_input(&[0.0, 0.6, 0.8000004]).unwrap();
        assert!((Vector3::from_row_slice(&stored).norm() - 1.0).abs() < 1e-15);
        let error = UnitVector3::<f64>::from_input(&[0.0, 0.0, 2.0]).unwrap_err();
        assert_eq!(
            error.to_string(),
            "unit vector [x, y, z] has norm 2, expected 1 (within 1e-6)"
        );
        assert!(UnitVector3::<f64>::from_input(&[0.0, 0.0, 0.0]).is_err());
    }

    #[test]
    fn storage_is_x_y_z() {
        let v = UnitVector3::from_unit(Vector3::new(0.0, 0.6, 0.8));
        assert_eq!(v.to_scalars(), vec![0.0, 0.6, 0.8]);
        assert_eq!(UnitVector3::<f64>::from_scalars(&[0.0, 0.6, 0.8]), v);
        assert_eq!(UnitVector3::<f64>::layout().to_string(), "[x, y, z]");
    }
}
