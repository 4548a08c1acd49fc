//! Infinite-plane factor, document 000 §IV.

use nalgebra::{Vector3, Vector4};

use crate::{DEGENERACY_TOLERANCE, degenerate};
use factor_core::geometry::InfinitePlane;
use factor_core::geometry::plane::transpose_transform;
use factor_core::lie::{Quaternion, Se3};
use factor_core::validation::{exceeds, number_text, within};
use factor_core::{Factor, FactorError, Scalar};

/// The plane error `e = log(q(Tᵀ q(π_c)) ⊗ q_w⁻¹)` (document 000 §IV), with
/// `q(π) = π/|π|` read as a quaternion `[a, b, c, d]` and the full-sphere
/// quaternion logarithm ([`Quaternion::log`], `|e| < 2π`).
///
/// - `pose` `T` maps world to camera; **left** perturbation `T ← Exp(δξ) T`,
///   tangent `[δω, δρ]`.
/// - `plane` `q_w`: **left** perturbation `q_w ← exp(δω) ⊗ q_w`, tangent `δω` (3).
///
/// The error is not folded onto `w ≥ 0`: a measured plane whose quaternion is
/// the antipode of the predicted one is the same plane, with `|e|` near 2π.
/// Degenerate: a measured plane vector of zero norm, and the exactly
/// antipodal error quaternion (`e_w < 0`, `|e_v| ≤ 1e-9`), where the logarithm
/// has no direction.
#[derive(Debug, Clone, Factor)]
#[factor(residual = plane_residual, dim = 3, validate = validate_plane, name = "plane")]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = factor_generated::plane::plane,
        regenerate = "cargo run --release --no-default-features -- generate"
    )
)]
pub struct PlaneFactor<S: Scalar = f64> {
    /// The measured plane `π_c = [a, b, c, d]` in the camera frame, any scale.
    pub measured: Vector4<S>,
    /// World-to-camera pose.
    #[variable(left)]
    pub pose: Se3<S>,
    /// The world plane landmark.
    #[variable(left)]
    pub plane: InfinitePlane<S>,
}

/// `Tᵀ π_c ⊗ q_w⁻¹`: the error quaternion `q(Tᵀ q(π_c)) ⊗ q_w⁻¹` up to a
/// positive scale. Both `q(·)` are positive scalings, and the quaternion
/// logarithm is homogeneous of degree 0 ([`Quaternion::log`]), so the
/// residual is the same without them (and cheaper to differentiate).
fn scaled_error_quaternion<S: Scalar>(f: &PlaneFactor<S>) -> Quaternion<S> {
    let y = transpose_transform(&f.pose, &f.measured);
    Quaternion::from_coords(y).mul(&f.plane.quaternion.conjugate())
}

/// `log(q(Tᵀ q(π_c)) ⊗ q_w⁻¹)`.
pub fn plane_residual<S: Scalar>(f: &PlaneFactor<S>) -> Vector3<S> {
    scaled_error_quaternion(f).log()
}

/// Rejects a zero measured plane and the antipodal error quaternion.
pub fn validate_plane(f: &PlaneFactor<f64>) -> Result<(), FactorError> {
    if !exceeds(f.measured.norm(), 0.0) {
        return Err(degenerate(
            PlaneFactor::NAME,
            "measured plane vector has zero norm".into(),
        ));
    }
    let landmark = f.plane.quaternion.coords().norm();
    if !within(landmark - 1.0, DEGENERACY_TOLERANCE.sqrt()) {
        return Err(degenerate(
            PlaneFactor::NAME,
            format!(
                "plane landmark quaternion has norm {}, expected 1",
                number_text(landmark)
            ),
        ));
    }
    let e = scaled_error_quaternion(f).normalized();
    // Only at the antipode itself (angle 2π) has the logarithm no direction;
    // within 1e-9 of it its Jacobian (~2π/|e_v|) is not worth returning.
    if e.w < 0.0 && !exceeds(e.vector().norm(), DEGENERACY_TOLERANCE) {
        return Err(degenerate(
            PlaneFactor::NAME,
            format!(
                "predicted and landmark plane quaternions are antipodal (error quaternion w = {}): \
                 the logarithm has no direction",
                number_text(e.w)
            ),
        ));
    }
    Ok(())
}
