//! Free-line factor with a bearing-vector measurement, document 001.

use nalgebra::{Unit, Vector2, Vector3};

use crate::{DEGENERACY_TOLERANCE, check_magnitude, degenerate};
use factor_core::geometry::{FreeLine, bearing_plane_normal};
use factor_core::lie::Se3;
use factor_core::linalg::{cross, dot, norm, scaled_norm};
use factor_core::validation::{exceeds, magnitude_text, number_text, within};
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
/// Constants: the extrinsics `T_CB` (`X_C = C_CB X_B + t_CB`) and the
/// bearings, stored as unit vectors (users give any scale:
/// [`factor_core::Storage::from_input`] normalises them over the whole `f64`
/// range). Degenerate: bearings not of unit norm or parallel, the camera
/// centre on the line anchor (`p_C = p_L`, to `1e-9` of their magnitudes),
/// and a ray `p_C − p_L` outside [`crate::MAGNITUDE_LIMIT`].
#[derive(Debug, Clone, Factor)]
#[factor(residual = free_line_residual, dim = 2, validate = validate_free_line, name = "free_line")]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = factor_generated::free_line::free_line,
        regenerate = "cargo run --release --no-default-features -- generate",
        hosts(apex)
    )
)]
pub struct FreeLineFactor<S: Scalar = f64> {
    /// Camera extrinsics `T_CB`.
    pub extrinsics: Se3<S>,
    /// Bearing vector `f₁` through the segment's first endpoint (camera frame).
    pub bearing_start: Unit<Vector3<S>>,
    /// Bearing vector `f₂` through the segment's second endpoint (camera frame).
    pub bearing_end: Unit<Vector3<S>>,
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

/// Rejects bearings that are not unit vectors or are parallel, a camera
/// centre on the anchor, and a ray to it outside [`crate::MAGNITUDE_LIMIT`].
pub fn validate_free_line(f: &FreeLineFactor<f64>) -> Result<(), FactorError> {
    let (f1, f2) = (f.bearing_start.into_inner(), f.bearing_end.into_inner());
    for (name, bearing) in [("f₁", f1), ("f₂", f2)] {
        // Users give bearings at any scale: `Storage::from_input` normalises them.
        let norm = scaled_norm(&bearing);
        if !within(norm - 1.0, DEGENERACY_TOLERANCE.sqrt()) {
            return Err(degenerate(
                FreeLineFactor::NAME,
                format!(
                    "bearing vector {name} has norm {}, expected 1",
                    magnitude_text(norm)
                ),
            ));
        }
    }
    if !exceeds(cross(&f1, &f2).norm(), DEGENERACY_TOLERANCE) {
        return Err(degenerate(
            FreeLineFactor::NAME,
            "bearing vectors are parallel: they span no plane".into(),
        ));
    }
    let centre = camera_centre(f);
    let ray = centre - f.line.anchor();
    // Max-abs magnitudes, which do not overflow where Euclidean norms would.
    let scale = centre.amax().max(f.line.anchor().amax()).max(1.0);
    if !ray.iter().all(|x| x.is_finite()) {
        return Err(degenerate(
            FreeLineFactor::NAME,
            "the camera centre or the line anchor overflows f64".into(),
        ));
    }
    if !exceeds(ray.amax(), DEGENERACY_TOLERANCE * scale) {
        return Err(degenerate(
            FreeLineFactor::NAME,
            format!(
                "camera centre lies on the line anchor (distance {})",
                number_text(ray.amax())
            ),
        ));
    }
    check_magnitude(
        FreeLineFactor::NAME,
        "the ray p_C − p_L from the line anchor to the camera centre",
        ray.amax(),
        "the camera is too far from the line anchor, or too close in absolute terms",
    )
}
