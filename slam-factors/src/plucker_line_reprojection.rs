//! Line reprojection over raw Plücker coordinates `[n, v]`, document 000 §III
//! (6)–(8) without the orthonormal parametrisation: the form peer generators
//! are compared on.

use nalgebra::Vector2;

use crate::degenerate;
use crate::line_reprojection::{endpoint_distances, validate_camera_line};
use factor_core::geometry::{Intrinsics, PluckerLine};
use factor_core::lie::Se3;
use factor_core::validation::exceeds;
use factor_core::{Factor, FactorError, Scalar};

/// `γ = [lᵀ p, lᵀ q] / √(l₁² + l₂²)`, `l = 𝒦 n_c`, as
/// [`crate::LineReprojection`], with the world line as a 6-vector.
///
/// - `pose` `T` maps world to camera; **left** perturbation `T ← Exp(δξ) T`,
///   tangent `[δω, δρ]`.
/// - `line` `[n, v]`: **additive**, tangent `[δn, δv]` (6). The residual is
///   invariant to the scale of `[n, v]`, so this block has rank ≤ 4 (5 with
///   the Plücker constraint ignored). A solver gets the line in its
///   orthonormal chart instead (4 dof, on the Klein quadric; for apex-solver
///   `SO3 × SO2`, `factor_core::host::apex`).
///
/// Degenerate: `v = 0`, or the line through the optical centre or in the
/// focal plane, or an image line outside [`crate::MAGNITUDE_LIMIT`] (which
/// bounds the scale of `[n, v]` too), as for [`crate::LineReprojection`].
#[derive(Debug, Clone, Factor)]
#[factor(
    residual = plucker_line_residual,
    dim = 2,
    validate = validate_plucker_line,
    name = "plucker_line_reprojection"
)]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = factor_generated::plucker_line_reprojection::plucker_line_reprojection,
        regenerate = "cargo run --release --no-default-features -- generate",
        hosts(apex)
    )
)]
pub struct PluckerLineReprojection<S: Scalar = f64> {
    /// `K = [f_u, f_v, c_u, c_v]`.
    pub intrinsics: Intrinsics<S>,
    /// Observed start point of the segment (pixels).
    pub start: Vector2<S>,
    /// Observed end point of the segment (pixels).
    pub end: Vector2<S>,
    /// World-to-camera pose.
    #[variable(left)]
    pub pose: Se3<S>,
    /// The world line `[n, v]`.
    #[variable]
    pub line: PluckerLine<S>,
}

/// `[lᵀ p, lᵀ q] / √(l₁² + l₂²)`.
pub fn plucker_line_residual<S: Scalar>(f: &PluckerLineReprojection<S>) -> Vector2<S> {
    endpoint_distances(
        &f.intrinsics,
        &f.line.transform(&f.pose).normal,
        &f.start,
        &f.end,
    )
}

/// Rejects `v = 0`, a line through the optical centre or in the focal plane.
pub fn validate_plucker_line(f: &PluckerLineReprojection<f64>) -> Result<(), FactorError> {
    if !exceeds(f.line.direction.amax(), 0.0) {
        return Err(degenerate(
            PluckerLineReprojection::NAME,
            "line direction v has zero norm".into(),
        ));
    }
    validate_camera_line(
        PluckerLineReprojection::NAME,
        &f.intrinsics,
        &f.pose,
        &f.line,
        [&f.start, &f.end],
    )
}
