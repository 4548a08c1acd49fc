//! Hand-written analytic Jacobians of the five factors, in plain `f64` with
//! `nalgebra`: the documents' derivations with their mistakes corrected, as an
//! engineer writes them by hand (rotation matrices and intermediate points
//! computed once, cross products instead of skew-matrix products where a row
//! times a skew matrix is wanted, no dual numbers and no symbolic engine).
//!
//! Each function returns the derive-generated typed linearization of its
//! factor (residual and one block per variable, on the same tangents as
//! [`factor_core::Factor::variables`] describes). None validates its input: call
//! the factor's `validate()` first, as `linearize_generated()` does.
//! `factor-core/tests/analytic.rs` checks every block against
//! `linearize_dual()`; `benches/linearize.rs` times them beside the generated
//! kernels.
//!
//! | function | document | corrections made |
//! | --- | --- | --- |
//! | [`point_reprojection()`] | 000 (2)–(5) | (4): tangent halves swapped, `∂P/∂δξ = [−⌊P⌋×, I]` for `δξ = [δω, δρ]` |
//! | [`line_reprojection()`] | 000 (6)–(12) | (10): the `v_c` row is `[−⌊R v⌋×, 0]`, not `−⌊R n⌋×` |
//! | [`plucker_line_reprojection()`] | 000 (6)–(8), (10)/(12) | as above |
//! | [`plane()`] | 000 §IV (13) and B | `∂E/∂u = Jl(E)⁻¹ Jl(u)`; exponent 3 in `∂φ/∂y`, `∂u/∂φ`; the `∂u/∂φ₄` column; the `δρ` half of `∂y/∂ξ` |
//! | [`free_line()`] | 001 §4 | the line block `[δθ, δd]`, which the document does not derive |

pub mod free_line;
pub mod line_reprojection;
pub mod plane;
pub mod plucker_line_reprojection;
pub mod point_reprojection;

pub use free_line::free_line;
pub use line_reprojection::line_reprojection;
pub use plane::{plane, plane_document_chain};
pub use plucker_line_reprojection::plucker_line_reprojection;
pub use point_reprojection::point_reprojection;

use nalgebra::{Matrix2x3, Matrix3, Vector2, Vector3};

use factor_core::geometry::Intrinsics;

/// `⌊v⌋×`, with `⌊v⌋× b = v × b`.
pub(crate) fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// The line residual `γ = [lᵀp, lᵀq]/√(l₁² + l₂²)`, `l = 𝒦 n_c`, and its
/// gradient `∂γ/∂n_c` (2 × 3): document 000 (6) times (7), `∂γ/∂l · 𝒦`.
///
/// With `k = 𝒦ᵀ p = [f_v (u − c_u), f_u (v − c_v), f_u f_v]` (constants only)
/// the residual is `γᵢ = n_c · kᵢ / s`, `s = √(l₁² + l₂²)`, and row `i` of the
/// gradient is `(kᵢ − γᵢ [f_v l₁, f_u l₂, 0]/s)/s`: (6)'s row
/// `(p − (lᵀp/s²) [l₁, l₂, 0])/s` times `𝒦`. (6) is right as printed (its last
/// entry `1` is `p₃ = 1` with `1/s` factored out).
pub(crate) fn endpoint_distances_with_gradient(
    k: &Intrinsics<f64>,
    n_c: &Vector3<f64>,
    start: &Vector2<f64>,
    end: &Vector2<f64>,
) -> (Vector2<f64>, Matrix2x3<f64>) {
    let (l1, l2) = (k.fv * n_c.x, k.fu * n_c.y);
    let inv_s = 1.0 / (l1 * l1 + l2 * l2).sqrt();
    let fuv = k.fu * k.fv;
    let kp = Vector3::new(k.fv * (start.x - k.cu), k.fu * (start.y - k.cv), fuv);
    let kq = Vector3::new(k.fv * (end.x - k.cu), k.fu * (end.y - k.cv), fuv);
    let residual = Vector2::new(n_c.dot(&kp) * inv_s, n_c.dot(&kq) * inv_s);
    // ∂s/∂n_c = [f_v l₁, f_u l₂, 0]/s.
    let (ds_x, ds_y) = (k.fv * l1 * inv_s, k.fu * l2 * inv_s);
    let gradient = Matrix2x3::new(
        (kp.x - residual.x * ds_x) * inv_s,
        (kp.y - residual.x * ds_y) * inv_s,
        kp.z * inv_s,
        (kq.x - residual.y * ds_x) * inv_s,
        (kq.y - residual.y * ds_y) * inv_s,
        kq.z * inv_s,
    );
    (residual, gradient)
}

/// Below this `θ²` the angle functions are evaluated by their Taylor series.
pub(crate) const SMALL_ANGLE_SQUARED: f64 = 1e-6;

/// The full-sphere quaternion logarithm `2 atan2(|v|, w) v/|v|` of `[v, w]`,
/// homogeneous of degree 0 (any positive scale of the quaternion gives the
/// same result), with the angle `θ = |log|`. Near the identity (`w > 0`,
/// `|v|² < 1e-6 w²`) the series `2/w (1 − r/3 + r²/5) v`, `r = |v|²/w²`.
pub(crate) fn quaternion_log(v: &Vector3<f64>, w: f64) -> (Vector3<f64>, f64) {
    let s2 = v.norm_squared();
    let k = if w > 0.0 && s2 < SMALL_ANGLE_SQUARED * w * w {
        let r = s2 / (w * w);
        2.0 / w * (1.0 - r / 3.0 + r * r / 5.0)
    } else {
        2.0 * s2.sqrt().atan2(w) / s2.sqrt()
    };
    (v * k, k * s2.sqrt())
}

/// `Jl(ω)⁻¹ = I − ½ ⌊ω⌋× + c ⌊ω⌋×²` given `c = 1/θ² − cot(θ/2)/(2θ)`
/// (finite for `θ < 2π`); `Jr(ω)⁻¹ = Jl(−ω)⁻¹`.
pub(crate) fn left_jacobian_inverse(omega: &Vector3<f64>, c: f64) -> Matrix3<f64> {
    let w = skew(omega);
    Matrix3::identity() - w * 0.5 + w * w * c
}

/// `Jl(ω) = I + (1 − cos θ)/θ² ⌊ω⌋× + (θ − sin θ)/θ³ ⌊ω⌋×²`.
pub(crate) fn left_jacobian(omega: &Vector3<f64>) -> Matrix3<f64> {
    let t2 = omega.norm_squared();
    let (a, b) = if t2 < SMALL_ANGLE_SQUARED {
        (
            0.5 - t2 / 24.0 + t2 * t2 / 720.0,
            1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0,
        )
    } else {
        let t = t2.sqrt();
        ((1.0 - t.cos()) / t2, (t - t.sin()) / (t2 * t))
    };
    let w = skew(omega);
    Matrix3::identity() + w * a + w * w * b
}
