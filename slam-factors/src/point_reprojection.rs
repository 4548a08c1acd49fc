//! Point reprojection, document 000 §II.

use nalgebra::{Vector2, Vector3};

use crate::{DEGENERACY_TOLERANCE, check_residual_digits, degenerate};
use factor_core::geometry::Intrinsics;
use factor_core::lie::Se3;
use factor_core::validation::{exceeds, number_text};
use factor_core::{Factor, FactorError, Scalar};

/// The reprojection error of a world point, `ρ = p_obs − π(K, R X_w + t)`
/// (document 000 (2)).
///
/// - `pose` `T = [R t; 0 1]` maps world to camera; **left** perturbation
///   `T ← Exp(δξ) T`, tangent `δξ = [δω, δρ]` (000 (4) derives it with the
///   columns in the other order; see the audit).
/// - `point` `X_w`: **additive** `X_w ← X_w + δ`.
///
/// Degenerate: the point at or behind the camera (`Z ≤ 1e-9` times the
/// largest coordinate of `P_c`, `X_w` or `t`), or observed so close to a
/// far off-axis prediction that the residual loses its digits
/// ([`crate::check_residual_digits`]).
#[derive(Debug, Clone, Factor)]
#[factor(residual = point_reprojection_residual, dim = 2, validate = validate_point_reprojection)]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = factor_generated::point_reprojection::point_reprojection,
        regenerate = "cargo run --release --no-default-features -- generate",
        hosts(apex)
    )
)]
pub struct PointReprojection<S: Scalar = f64> {
    /// `K = [f_u, f_v, c_u, c_v]`.
    pub intrinsics: Intrinsics<S>,
    /// The observed pixel `p_obs`.
    pub observed: Vector2<S>,
    /// World-to-camera pose.
    #[variable(left)]
    pub pose: Se3<S>,
    /// The world point.
    #[variable]
    pub point: Vector3<S>,
}

/// `p_obs − π(K, R X_w + t)`.
pub fn point_reprojection_residual<S: Scalar>(f: &PointReprojection<S>) -> Vector2<S> {
    let p_c = f.pose.transform_point(&f.point);
    f.observed - f.intrinsics.project(&p_c)
}

/// Rejects a point at or behind the camera, and a residual that has lost its
/// digits to the depth's rounding.
pub fn validate_point_reprojection(f: &PointReprojection<f64>) -> Result<(), FactorError> {
    let p_c = f.pose.transform_point(&f.point);
    if !p_c.iter().all(|x| x.is_finite()) {
        return Err(degenerate(
            PointReprojection::NAME,
            "the point's camera-frame coordinates R X + t overflow f64".into(),
        ));
    }
    // The depth is compared with the magnitudes it is computed from (max-abs
    // norms, which cannot overflow), so a point at the centre up to rounding
    // (`P_c ≈ 1e-16`) is caught too.
    let scale = p_c
        .amax()
        .max(f.point.amax())
        .max(f.pose.translation.amax());
    if !exceeds(p_c.z, DEGENERACY_TOLERANCE * scale) {
        return Err(degenerate(
            PointReprojection::NAME,
            format!(
                "point is at or behind the camera (depth Z = {})",
                number_text(p_c.z)
            ),
        ));
    }
    // The pixel `f X/Z + c` moves by `|f| (1 + |X/Z|)` per relative error of
    // the depth and of `X`.
    let (x, y) = (p_c.x / p_c.z, p_c.y / p_c.z);
    let k = &f.intrinsics;
    let terms = k.fu.abs() * (1.0 + x.abs()) + k.fv.abs() * (1.0 + y.abs());
    let residual = || (f.observed - k.project(&p_c)).norm();
    check_residual_digits(PointReprojection::NAME, residual, scale / p_c.z, terms)
}
