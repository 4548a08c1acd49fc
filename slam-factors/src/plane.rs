//! Infinite-plane factor, document 000 §IV.

use nalgebra::{Unit, Vector3, Vector4};

use crate::{DEGENERACY_TOLERANCE, degenerate};
use factor_core::geometry::InfinitePlane;
use factor_core::geometry::plane::transpose_transform;
use factor_core::lie::{Quaternion, Se3};
use factor_core::linalg::{norm_ratio, scaled_norm, unit_of};
use factor_core::validation::{exceeds, magnitude_text, number_text, within};
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
/// The measured plane is stored at unit norm (users give any scale:
/// [`factor_core::Storage::from_input`] normalises it over the whole `f64`
/// range, as [`factor_core::linalg::unit_of`] does).
/// Degenerate: a measured plane or a landmark not of unit norm, a predicted
/// or landmark plane farther than [`PLANE_DISTANCE_LIMIT`] from the world
/// origin in units of its normal (its quaternion keeps less than 1e-7 of the
/// normal's direction), and the exactly antipodal error quaternion
/// (`e_w < 0`, `|e_v| ≤ 1e-9`), where the logarithm has no direction.
#[derive(Debug, Clone, Factor)]
#[factor(residual = plane_residual, dim = 3, validate = validate_plane, name = "plane")]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = factor_generated::plane::plane,
        regenerate = "cargo run --release --no-default-features -- generate",
        hosts(apex)
    )
)]
pub struct PlaneFactor<S: Scalar = f64> {
    /// The measured plane `π_c = [a, b, c, d]` in the camera frame, any scale.
    pub measured: Unit<Vector4<S>>,
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

/// The largest distance of the predicted and landmark planes from the world
/// origin, in units of their normals (`|w| / |(x, y, z)|` of the quaternion),
/// that [`validate_plane`] accepts.
pub const PLANE_DISTANCE_LIMIT: f64 = 1e9;

/// Rejects a measured plane or a landmark that is not of unit norm, a plane
/// beyond [`PLANE_DISTANCE_LIMIT`], and the antipodal error quaternion.
pub fn validate_plane(f: &PlaneFactor<f64>) -> Result<(), FactorError> {
    for (what, v) in [
        ("measured plane vector", f.measured.into_inner()),
        ("plane landmark quaternion", f.plane.quaternion.coords()),
    ] {
        // Within 3e-5 of 1; the inputs are normalised at any scale by
        // `Unit::new_normalize` or `Storage::from_input`.
        let norm = scaled_norm(&v);
        if !within(norm - 1.0, DEGENERACY_TOLERANCE.sqrt()) {
            return Err(degenerate(
                PlaneFactor::NAME,
                format!("{what} has norm {}, expected 1", magnitude_text(norm)),
            ));
        }
    }
    // A plane far from the world origin (in units of its normal) is a
    // quaternion near (0, 0, 0, ±1) whose vector part, the normal, keeps only
    // a fraction `1/κ` of its digits: beyond κ = 1e9, less than 1e-7.
    let predicted = transpose_transform(&f.pose, &f.measured);
    for (what, plane) in [
        ("predicted", predicted),
        ("landmark", f.plane.quaternion.coords()),
    ] {
        let kappa = norm_ratio(&Vector3::new(0.0, 0.0, plane.w), &plane.xyz());
        // `within` is false for a NaN ratio (an overflowing plane) too.
        if !within(kappa, PLANE_DISTANCE_LIMIT) {
            return Err(degenerate(
                PlaneFactor::NAME,
                format!(
                    "the {what} world plane is {} from the world origin in units of its normal, \
                     beyond 1e9 where its quaternion keeps less than 1e-7 of the normal's \
                     direction (move the world origin nearer)",
                    magnitude_text(kappa)
                ),
            ));
        }
    }
    let e = Quaternion::from_coords(
        unit_of(&scaled_error_quaternion(f).coords()).expect("unit quaternions of bounded planes"),
    );
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
