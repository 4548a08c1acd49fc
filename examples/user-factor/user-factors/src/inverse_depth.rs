//! A visual-inertial projection factor with an extrinsic and an inverse
//! depth, as VINS-Mono's `ProjectionFactor` writes it.

use std::cmp::Ordering;

use factor_core::lie::Se3RhoTheta;
use factor_core::{Factor, FactorError, Scalar};
use nalgebra::{Vector2, Vector3};

/// A feature first seen by the camera of body pose `i` along the normalized
/// ray `[x_i, y_i, 1]` at inverse depth `λ`, observed again by the camera of
/// body pose `j` at the normalized coordinates `[x_j, y_j]`:
///
/// `p_ci = [x_i, y_i, 1] / λ`, `p_w = T_i (T_bc p_ci)`,
/// `p_cj = T_bc⁻¹ (T_j⁻¹ p_w)`, residual `w (p_cj,xy / p_cj,z − [x_j, y_j])`.
///
/// The body poses `T_i`, `T_j` map body to world and the extrinsic `T_bc`
/// camera to body, each perturbed on the right in apex-solver's chart
/// ([`Se3RhoTheta`]); the inverse depth is additive. Degenerate: an inverse
/// depth that is not positive, or the point at or behind camera `j`.
#[derive(Debug, Clone, Factor)]
#[factor(
    residual = inverse_depth_projection_residual,
    dim = 2,
    validate = validate_inverse_depth_projection
)]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = user_kernels::inverse_depth_projection::inverse_depth_projection,
        regenerate = "cargo run -p user-cli --no-default-features -- generate"
    )
)]
pub struct InverseDepthProjection<S: Scalar = f64> {
    /// The feature's normalized coordinates `[x_i, y_i]` in camera `i`.
    pub observed_i: Vector2<S>,
    /// Its normalized coordinates `[x_j, y_j]` in camera `j`.
    pub observed_j: Vector2<S>,
    /// The weight `w` (VINS-Mono: the focal length / 1.5 px).
    pub weight: S,
    /// Body pose `T_i`, body to world.
    #[variable(right)]
    pub pose_i: Se3RhoTheta<S>,
    /// Body pose `T_j`, body to world.
    #[variable(right)]
    pub pose_j: Se3RhoTheta<S>,
    /// The extrinsic `T_bc`, camera to body.
    #[variable(right)]
    pub extrinsic: Se3RhoTheta<S>,
    /// The inverse depth `λ` of the feature in camera `i`.
    #[variable]
    pub inverse_depth: S,
}

/// The point in camera `j`, `T_bc⁻¹ T_j⁻¹ T_i T_bc [x_i, y_i, 1] / λ`.
fn point_in_camera_j<S: Scalar>(f: &InverseDepthProjection<S>) -> Vector3<S> {
    let depth = f.inverse_depth.recip();
    let ray = Vector3::new(f.observed_i.x, f.observed_i.y, S::one());
    let in_body_i = f.extrinsic.transform_point(&(ray * depth));
    let in_world = f.pose_i.transform_point(&in_body_i);
    let in_body_j = f.pose_j.inverse_transform_point(&in_world);
    f.extrinsic.inverse_transform_point(&in_body_j)
}

/// The residual of [`InverseDepthProjection`].
pub fn inverse_depth_projection_residual<S: Scalar>(f: &InverseDepthProjection<S>) -> Vector2<S> {
    let p = point_in_camera_j(f);
    let inverse_z = p.z.recip();
    Vector2::new(
        (p.x * inverse_z - f.observed_j.x) * f.weight,
        (p.y * inverse_z - f.observed_j.y) * f.weight,
    )
}

/// Rejects an inverse depth that is not positive and a point at or behind
/// camera `j` (depth below 1e-9 of its distance).
pub fn validate_inverse_depth_projection(
    f: &InverseDepthProjection<f64>,
) -> Result<(), FactorError> {
    let degenerate = |reason: String| FactorError::Degenerate {
        factor: InverseDepthProjection::NAME,
        reason,
    };
    // `partial_cmp` so that NaN is rejected too.
    if f.inverse_depth.partial_cmp(&0.0) != Some(Ordering::Greater) {
        return Err(degenerate(format!(
            "inverse depth {} is not positive",
            f.inverse_depth
        )));
    }
    let p = point_in_camera_j(f);
    if p.z.partial_cmp(&(1e-9 * p.norm())) != Some(Ordering::Greater) {
        return Err(degenerate(format!(
            "the point is at or behind camera j (depth {})",
            p.z
        )));
    }
    Ok(())
}
