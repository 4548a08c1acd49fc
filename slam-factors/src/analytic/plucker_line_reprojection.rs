//! Line reprojection over raw Plücker coordinates `[n, v]`, document 000 §III
//! (6)–(8), by hand.

use nalgebra::{SMatrix, Vector3};

use crate::PluckerLineReprojection;
use crate::analytic::endpoint_distances_with_gradient;
use crate::plucker_line_reprojection::PluckerLineReprojectionLinearization;

/// Residual `γ = [lᵀp, lᵀq]/√(l₁² + l₂²)`, `l = 𝒦 n_c`, and its Jacobians
/// w.r.t. the pose (left, `[δω, δρ]`) and the world line `[n, v]`
/// (additive, `[δn, δv]`), document 000 (6)–(8) and (10)/(12).
///
/// With `v_c = R v`, `n_c = R n + t × v_c` and `gᵢ = ∂γᵢ/∂n_c` ((6)·(7)):
/// - pose, (10)/(12) **corrected** as in
///   [`line_reprojection`](crate::analytic::line_reprojection()): row `i` is
///   `[(n_c × gᵢ)ᵀ, (v_c × gᵢ)ᵀ]`;
/// - line, (8): `∂n_c/∂[n, v] = [R, ⌊t⌋× R]`, so row `i` is
///   `[(Rᵀ gᵢ)ᵀ, (Rᵀ (gᵢ × t))ᵀ]`.
///
/// Does not validate: the caller rejects `v = 0`, `n_c = 0` and
/// `l₁ = l₂ = 0` first.
pub fn plucker_line_reprojection(
    f: &PluckerLineReprojection,
) -> PluckerLineReprojectionLinearization {
    let r = f.pose.rotation.matrix();
    let t = f.pose.translation;
    let v_c = r * f.line.direction;
    let n_c = r * f.line.normal + t.cross(&v_c);
    let (residual, g) = endpoint_distances_with_gradient(&f.intrinsics, &n_c, &f.start, &f.end);

    let mut pose = SMatrix::<f64, 2, 6>::zeros();
    let mut line = SMatrix::<f64, 2, 6>::zeros();
    let r_t = r.transpose();
    for i in 0..2 {
        let gi: Vector3<f64> = g.row(i).transpose();
        let d_rot = n_c.cross(&gi);
        let d_trans = v_c.cross(&gi);
        let d_n = r_t * gi;
        let d_v = r_t * gi.cross(&t);
        pose.row_mut(i)
            .copy_from_slice(&[d_rot.x, d_rot.y, d_rot.z, d_trans.x, d_trans.y, d_trans.z]);
        line.row_mut(i)
            .copy_from_slice(&[d_n.x, d_n.y, d_n.z, d_v.x, d_v.y, d_v.z]);
    }
    PluckerLineReprojectionLinearization {
        residual,
        pose,
        line,
    }
}
