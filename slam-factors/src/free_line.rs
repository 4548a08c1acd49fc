//! Free-line factor with a bearing-vector measurement, document 001.

use nalgebra::{Vector2, Vector3};

use crate::{DEGENERACY_TOLERANCE, degenerate};
use factor_core::geometry::{FreeLine, bearing_plane_normal};
use factor_core::lie::Se3;
use factor_core::linalg::{cross, dot, norm};
use factor_core::validation::{exceeds, number_text};
use factor_core::{Factor, FactorError, Scalar};

/// The two error terms of document 001 §3 for a line `[q_WL, d_L]` seen by a
/// camera on a body:
///
/// - `ε₁ = ñᵀ C_CB C_BW x_L` (3.1), the line direction against the measured
///   plane;
/// - `ε₂ = ñᵀ C_CB C_BW (p_C − p_L) / ‖p_C − p_L‖` (3.3), with the camera
///   centre `p_C = −C_BWᵀ (C_CBᵀ t_CB + t_BW)` (3.6) and the anchor `p_L`;
///
/// where `ñ = f₁ × f₂ / ‖f₁ × f₂‖` is the measurement (§2).
///
/// - `body_pose` `T_BW` (`X_B = C_BW X_W + t_BW`): **right** perturbation
///   `C_BW ← C_BW Exp(δφ)`, `t_BW ← t_BW + C_BW δt`, tangent `[δφ, δt]` (4.1)–(4.2).
/// - `line` `[q_WL, d_L]`: **left** `q_WL ← exp(δθ) ⊗ q_WL`, `d_L ← d_L + δd`,
///   tangent `[δθ, δd]` (the document does not derive this Jacobian).
///
/// Constant: the extrinsics `T_CB` (`X_C = C_CB X_B + t_CB`).
/// Degenerate: parallel (or zero) bearing vectors, and the camera centre on
/// the line anchor (`p_C = p_L`).
#[derive(Debug, Clone, Factor)]
#[factor(residual = free_line_residual, dim = 2, validate = validate_free_line, name = "free_line")]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = factor_generated::free_line::free_line,
        regenerate = "cargo run --release --no-default-features -- generate"
    )
)]
pub struct FreeLineFactor<S: Scalar = f64> {
    /// Camera extrinsics `T_CB`.
    pub extrinsics: Se3<S>,
    /// Bearing vector `f₁` through the segment's first endpoint (camera frame).
    pub bearing_start: Vector3<S>,
    /// Bearing vector `f₂` through the segment's second endpoint (camera frame).
    pub bearing_end: Vector3<S>,
    /// Body pose `T_BW`.
    #[variable(right)]
    pub body_pose: Se3<S>,
    /// The line `[q_WL, d_L]`.
    #[variable(left)]
    pub line: FreeLine<S>,
}

/// The camera centre in the world, `p_C = −C_BWᵀ (C_CBᵀ t_CB + t_BW)` (001 (3.6)).
fn camera_centre<S: Scalar>(f: &FreeLineFactor<S>) -> Vector3<S> {
    let in_body = f
        .extrinsics
        .rotation
        .inverse_rotate(&f.extrinsics.translation)
        + f.body_pose.translation;
    -f.body_pose.rotation.inverse_rotate(&in_body)
}

/// `[ε₁, ε₂]`.
pub fn free_line_residual<S: Scalar>(f: &FreeLineFactor<S>) -> Vector2<S> {
    let n_c = bearing_plane_normal(&f.bearing_start, &f.bearing_end);
    // ñᵀ C_CB C_BW a = (C_BWᵀ C_CBᵀ ñ) · a: rotate ñ into the world once.
    let n_w = f
        .body_pose
        .rotation
        .inverse_rotate(&f.extrinsics.rotation.inverse_rotate(&n_c));
    let ray = camera_centre(f) - f.line.anchor();
    Vector2::new(dot(&n_w, &f.line.direction()), dot(&n_w, &ray) / norm(&ray))
}

/// Rejects parallel bearings and a camera centre on the anchor.
pub fn validate_free_line(f: &FreeLineFactor<f64>) -> Result<(), FactorError> {
    let (f1, f2) = (f.bearing_start, f.bearing_end);
    let scale = f1.norm() * f2.norm();
    if !exceeds(cross(&f1, &f2).norm(), DEGENERACY_TOLERANCE * scale) {
        return Err(degenerate(
            FreeLineFactor::NAME,
            "bearing vectors are parallel or zero: they span no plane".into(),
        ));
    }
    let centre = camera_centre(f);
    let distance = (centre - f.line.anchor()).norm();
    if !exceeds(distance, DEGENERACY_TOLERANCE * centre.norm().max(1.0)) {
        return Err(degenerate(
            FreeLineFactor::NAME,
            format!(
                "camera centre lies on the line anchor (distance {})",
                number_text(distance)
            ),
        ));
    }
    Ok(())
}
