//! Line reprojection with the orthonormal representation, document 000 §III.

use nalgebra::{Vector2, Vector3};

use crate::{DEGENERACY_TOLERANCE, check_magnitude, check_residual_digits, degenerate};
use factor_core::geometry::{Intrinsics, OrthonormalLine, PluckerLine};
use factor_core::lie::Se3;
use factor_core::linalg::{dot, norm_ratio, scaled_norm};
use factor_core::validation::{exceeds, magnitude_text, number_text};
use factor_core::{Factor, FactorError, Scalar};

/// The distances of the observed endpoints to the projected line,
/// `γ = [lᵀ p, lᵀ q] / √(l₁² + l₂²)` with `l = 𝒦 n_c` and `p`, `q` the observed
/// endpoint pixels `[u, v, 1]` (document 000 §III, (6)–(12)).
///
/// - `pose` `T` maps world to camera; **left** perturbation `T ← Exp(δξ) T`,
///   tangent `[δω, δρ]`.
/// - `line` `(U, W)`: **left** perturbation `U ← Exp(δΘ) U`, `W ← R(δρ) W`,
///   tangent `[δΘ, δρ]` (4), as in 000 (9).
///
/// Degenerate: the line through the optical centre (`n_c = 0`: it projects to
/// a point) or in the focal plane `Z = 0` (`l₁ = l₂ = 0`: it projects to the
/// line at infinity), each to `1e-9` of the magnitudes it is computed from,
/// and an image line `l` outside [`crate::MAGNITUDE_LIMIT`]: where the
/// outputs would not be accurate to 1e-6 (`n_c` below `1e-9` of the terms
/// it sums leaves a relative error of about `1e-7` and more).
#[derive(Debug, Clone, Factor)]
#[factor(residual = line_reprojection_residual, dim = 2, validate = validate_line_reprojection)]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = factor_generated::line_reprojection::line_reprojection,
        regenerate = "cargo run --release --no-default-features -- generate",
        hosts(apex)
    )
)]
pub struct LineReprojection<S: Scalar = f64> {
    /// `K = [f_u, f_v, c_u, c_v]`.
    pub intrinsics: Intrinsics<S>,
    /// Observed start point of the segment (pixels).
    pub start: Vector2<S>,
    /// Observed end point of the segment (pixels).
    pub end: Vector2<S>,
    /// World-to-camera pose.
    #[variable(left)]
    pub pose: Se3<S>,
    /// The world line.
    #[variable(left)]
    pub line: OrthonormalLine<S>,
}

/// `[lᵀ p, lᵀ q] / √(l₁² + l₂²)`.
pub fn line_reprojection_residual<S: Scalar>(f: &LineReprojection<S>) -> Vector2<S> {
    let camera_line = f.line.to_plucker().transform(&f.pose);
    endpoint_distances(&f.intrinsics, &camera_line.normal, &f.start, &f.end)
}

/// The signed distances of two pixels to the image line `l = 𝒦 n_c`:
/// `[lᵀ p, lᵀ q] / √(l₁² + l₂²)` with `p = [u, v, 1]`.
///
/// Computed as `lᵀ p = n_cᵀ (𝒦ᵀ p)`, the same number: `𝒦ᵀ p =
/// [f_v (u − c_u), f_u (v − c_v), f_u f_v]` involves only constants, so a
/// derivative of the residual meets one dot product per endpoint instead of
/// the product with `𝒦` and then with `p`.
pub(crate) fn endpoint_distances<S: Scalar>(
    intrinsics: &Intrinsics<S>,
    n_c: &Vector3<S>,
    start: &Vector2<S>,
    end: &Vector2<S>,
) -> Vector2<S> {
    let k = intrinsics;
    let (l1, l2) = (k.fv * n_c.x, k.fu * n_c.y);
    let inv = (l1 * l1 + l2 * l2).sqrt().recip();
    let through =
        |p: &Vector2<S>| Vector3::new(k.fv * (p.x - k.cu), k.fu * (p.y - k.cv), k.fu * k.fv);
    Vector2::new(
        dot(n_c, &through(start)) * inv,
        dot(n_c, &through(end)) * inv,
    )
}

/// Rejects a line through the optical centre or in the focal plane, and an
/// image line of a magnitude the residual cannot square.
pub fn validate_line_reprojection(f: &LineReprojection<f64>) -> Result<(), FactorError> {
    validate_camera_line(
        LineReprojection::NAME,
        &f.intrinsics,
        &f.pose,
        &f.line.to_plucker(),
        [&f.start, &f.end],
    )
}

/// Rejects a world line that, seen from `pose`, passes through the optical
/// centre (`n_c = 0`: it projects to a point) or lies in the focal plane
/// (`l₁ = l₂ = 0` for `l = 𝒦 n_c`: it projects to the line at infinity), each
/// to `1e-9` of the magnitudes it is computed from, or whose image line `l`
/// is outside [`crate::MAGNITUDE_LIMIT`]; and observed endpoints so close to
/// the image of a line that near the optical centre that their distances
/// lose their digits ([`crate::check_residual_digits`]).
///
/// `n_c = R n + t × R v` is a sum of terms of magnitude `|n|` and `|t| |v|`:
/// when `|n_c|` falls below `1e-9` of that, rounding leaves it (and the
/// residual) with a relative error of about `1e-7` and more. The distance
/// of an endpoint `p`, `n_cᵀ (𝒦ᵀ [p, 1]) / ‖l₁₂‖`, is a sum of terms of
/// `|n_c| ‖𝒦ᵀ [p, 1]‖ / ‖l₁₂‖` pixels, each carrying that relative error.
pub(crate) fn validate_camera_line(
    factor: &'static str,
    intrinsics: &Intrinsics<f64>,
    pose: &Se3<f64>,
    world_line: &PluckerLine<f64>,
    endpoints: [&Vector2<f64>; 2],
) -> Result<(), FactorError> {
    let camera_line = world_line.transform(pose);
    let (n, v) = (camera_line.normal, camera_line.direction);
    let l = intrinsics.project_line(&n);
    if !n
        .iter()
        .chain(v.iter())
        .chain(l.iter())
        .all(|x| x.is_finite())
    {
        return Err(degenerate(
            factor,
            "the camera-frame line or its image overflows f64".into(),
        ));
    }
    // Magnitudes scaled first: finite over the whole f64 range.
    let terms = scaled_norm(&world_line.normal)
        + scaled_norm(&pose.translation) * scaled_norm(&world_line.direction);
    if !exceeds(scaled_norm(&n), DEGENERACY_TOLERANCE * terms) {
        return Err(degenerate(
            factor,
            format!(
                "line passes through the optical centre (distance |n_c|/|v_c| = {}; |n_c| is \
                 below 1e-9 of the |n| + |t| |v| = {} it is computed from)",
                number_text(norm_ratio(&n, &v)),
                magnitude_text(terms)
            ),
        ));
    }
    if !exceeds(
        norm_ratio(&Vector3::new(l.x, l.y, 0.0), &l),
        DEGENERACY_TOLERANCE,
    ) {
        return Err(degenerate(
            factor,
            "line lies in the focal plane Z = 0 and projects to the line at infinity".into(),
        ));
    }
    check_magnitude(
        factor,
        "the image line l = 𝒦 n_c",
        l.amax(),
        "the camera is too far from the line for its focal lengths, or the line's \
         coordinates are too large or too small",
    )?;
    let k = intrinsics;
    let through = |p: &Vector2<f64>| {
        Vector3::new(k.fv * (p.x - k.cu), k.fu * (p.y - k.cv), k.fu * k.fv).norm()
    };
    let n_norm = scaled_norm(&n);
    let pixels = n_norm * (through(endpoints[0]) + through(endpoints[1])) / l.xy().norm();
    let residual = || endpoint_distances(k, &n, endpoints[0], endpoints[1]).norm();
    check_residual_digits(factor, residual, terms / n_norm, pixels)
}
