//! Free-line factor with a bearing-vector measurement, document 001, by hand.

use nalgebra::{SMatrix, Vector2, Vector3};

use crate::FreeLineFactor;
use crate::free_line::FreeLineFactorLinearization;

/// Residual `[ε₁, ε₂]` (001 (3.1), (3.3)) and its Jacobians w.r.t. the body
/// pose `T_BW` (right, `C_BW ← C_BW Exp(δφ)`, `t_BW ← t_BW + C_BW δt`,
/// `[δφ, δt]`) and the line `[q_WL, d_L]` (left, `q_WL ← exp(δθ) ⊗ q_WL`,
/// `d_L ← d_L + δd`, `[δθ, δd]`).
///
/// With `_W ñ = C_BWᵀ C_CBᵀ ñ`, the direction `x = R(q_WL) e_x`, the anchor
/// `p_L = d_L z_L` (`z_L = R(q_WL) e_z`), the camera centre
/// `p_C = −C_BWᵀ (C_CBᵀ t_CB + t_BW)` (3.6), `w = p_C − p_L`, `v = w/‖w‖`
/// (4.7), so `ε₁ = _W ñ · x`, `ε₂ = _W ñ · v`, and
/// `g = (I − v vᵀ) _W ñ/‖w‖ = (_W ñ − ε₂ v)/‖w‖` (the gradient of `ε₂`
/// w.r.t. `p_C`, (4.17)):
///
/// - body pose, §4: `∂_W ñ/∂δφ = ⌊_W ñ⌋×`, `∂p_C/∂δφ = ⌊p_C⌋×` (4.26, with
///   `_W t_CB + _W t_BW = −p_C`), `∂p_C/∂δt = −I` (4.27), so
///   `∂ε₁/∂δφ = −_W ñᵀ ⌊x⌋× = (x × _W ñ)ᵀ` (4.5), `∂ε₁/∂δt = 0` (4.6),
///   `∂ε₂/∂δφ = (v × _W ñ + g × p_C)ᵀ` (4.33) and `∂ε₂/∂δt = −gᵀ` (4.38).
///   The derivation of (4.18)–(4.24) drops only second-order terms, and
///   (4.33), (4.38) agree with these (checked against dual numbers in
///   `factor-core/tests/analytic.rs`) once `_W t` is read as world-expressed.
/// - line, which the document does not derive: `δx = δθ × x`,
///   `δp_L = δθ × p_L + δd z_L`, `δw = −δp_L`, so
///   `∂ε₁/∂[δθ, δd] = [(x × _W ñ)ᵀ, 0]` and
///   `∂ε₂/∂[δθ, δd] = [(g × p_L)ᵀ, −g·z_L]`.
///
/// Does not validate: the caller rejects parallel bearings and `p_C = p_L`.
pub fn free_line(f: &FreeLineFactor) -> FreeLineFactorLinearization {
    let c_bw = f.body_pose.rotation.matrix();
    let c_cb = f.extrinsics.rotation.matrix();
    let m = f.bearing_start.cross(&f.bearing_end);
    let n_c = m / m.norm();
    // _W ñ = C_BWᵀ C_CBᵀ ñ, the camera centre and the line in the world.
    let n_w = c_bw.tr_mul(&c_cb.tr_mul(&n_c));
    let p_c = -c_bw.tr_mul(&(c_cb.tr_mul(&f.extrinsics.translation) + f.body_pose.translation));
    let r_l = f.line.rotation.to_rotation_matrix();
    let x: Vector3<f64> = r_l.column(0).into_owned();
    let z_l: Vector3<f64> = r_l.column(2).into_owned();
    let p_l = z_l * f.line.distance;
    let w = p_c - p_l;
    let inv_w = 1.0 / w.norm();
    let v = w * inv_w;
    let residual = Vector2::new(n_w.dot(&x), n_w.dot(&v));
    let g = (n_w - v * residual.y) * inv_w;

    let d1 = x.cross(&n_w);
    let d2_phi = v.cross(&n_w) + g.cross(&p_c);
    let d2_theta = g.cross(&p_l);
    #[rustfmt::skip]
    let body_pose = SMatrix::<f64, 2, 6>::new(
        d1.x, d1.y, d1.z, 0.0, 0.0, 0.0,
        d2_phi.x, d2_phi.y, d2_phi.z, -g.x, -g.y, -g.z,
    );
    #[rustfmt::skip]
    let line = SMatrix::<f64, 2, 4>::new(
        d1.x, d1.y, d1.z, 0.0,
        d2_theta.x, d2_theta.y, d2_theta.z, -g.dot(&z_l),
    );
    FreeLineFactorLinearization {
        residual,
        body_pose,
        line,
    }
}
