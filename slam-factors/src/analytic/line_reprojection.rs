//! Line reprojection with the orthonormal line `(U, W)`, document 000 §III, by
//! hand.

use nalgebra::{SMatrix, Vector3};

use crate::LineReprojection;
use crate::analytic::endpoint_distances_with_gradient;
use crate::line_reprojection::LineReprojectionLinearization;

/// Residual `γ = [lᵀp, lᵀq]/√(l₁² + l₂²)`, `l = 𝒦 n_c`, and its Jacobians
/// w.r.t. the pose (left, `[δω, δρ]`) and the orthonormal line (left,
/// `U ← Exp(δΘ) U`, `W ← R(δρ) W`, `[δΘ, δρ]`), document 000 (6)–(12).
///
/// With `n_w = w₁ u₁`, `v_w = w₂ u₂` (9), `v_c = R v_w`,
/// `n_c = R n_w + t × v_c` (8), and `gᵢ = ∂γᵢ/∂n_c` from (6)·(7)
/// ([`endpoint_distances_with_gradient`](crate::analytic)):
/// - pose, (10)/(12), **corrected**: the last line of (10) gives the `v_c`
///   row as `−⌊R n_w⌋×`; it is `[−⌊R v_w⌋×, 0]`, so
///   `∂L_c/∂δξ = [[−⌊R n_w⌋× − ⌊⌊t⌋× R v_w⌋×, −⌊R v_w⌋×], [−⌊R v_w⌋×, 0]]`
///   (as (12) uses it), whose `n_c` row is `[−⌊n_c⌋×, −⌊v_c⌋×]`. Only the
///   `n_c` row reaches `l`, so row `i` is `[(n_c × gᵢ)ᵀ, (v_c × gᵢ)ᵀ]`
///   (`gᵀ(−⌊a⌋×) = (a × g)ᵀ`);
/// - line, (8)·(9)/(11), right as printed:
///   `∂n_c/∂[δΘ, δρ] = [R, ⌊t⌋× R] [[−⌊w₁u₁⌋×, −w₂u₁], [−⌊w₂u₂⌋×, w₁u₂]]`;
///   with `aᵢ = Rᵀ gᵢ` and `bᵢ = Rᵀ (gᵢ × t)` (`gᵢᵀ ⌊t⌋× R = bᵢᵀ`) row `i` is
///   `[(n_w × aᵢ + v_w × bᵢ)ᵀ, −w₂ u₁·aᵢ + w₁ u₂·bᵢ]`.
///
/// Does not validate: the caller rejects `n_c = 0` and `l₁ = l₂ = 0` first.
pub fn line_reprojection(f: &LineReprojection) -> LineReprojectionLinearization {
    let r = f.pose.rotation.matrix();
    let t = f.pose.translation;
    let u = f.line.u.matrix();
    let (w1, w2) = (f.line.w.cos, f.line.w.sin);
    let u1: Vector3<f64> = u.column(0).into_owned();
    let u2: Vector3<f64> = u.column(1).into_owned();
    let (n_w, v_w) = (u1 * w1, u2 * w2);
    let v_c = r * v_w;
    let n_c = r * n_w + t.cross(&v_c);
    let (residual, g) = endpoint_distances_with_gradient(&f.intrinsics, &n_c, &f.start, &f.end);

    let mut pose = SMatrix::<f64, 2, 6>::zeros();
    let mut line = SMatrix::<f64, 2, 4>::zeros();
    let r_t = r.transpose();
    for i in 0..2 {
        let gi: Vector3<f64> = g.row(i).transpose();
        let d_rot = n_c.cross(&gi);
        let d_trans = v_c.cross(&gi);
        let a = r_t * gi;
        let b = r_t * gi.cross(&t);
        let d_theta = n_w.cross(&a) + v_w.cross(&b);
        let d_rho = -w2 * u1.dot(&a) + w1 * u2.dot(&b);
        pose.row_mut(i)
            .copy_from_slice(&[d_rot.x, d_rot.y, d_rot.z, d_trans.x, d_trans.y, d_trans.z]);
        line.row_mut(i)
            .copy_from_slice(&[d_theta.x, d_theta.y, d_theta.z, d_rho]);
    }
    LineReprojectionLinearization {
        residual,
        pose,
        line,
    }
}
