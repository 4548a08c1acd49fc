//! Infinite-plane factor, document 000 §IV, by hand.

use nalgebra::{Matrix3, Matrix3x4, Matrix4, SMatrix, Vector3, Vector4};

use crate::PlaneFactor;
use crate::analytic::{
    SMALL_ANGLE_SQUARED, left_jacobian, left_jacobian_inverse, quaternion_log, skew,
};
use crate::plane::PlaneFactorLinearization;

/// The pieces shared by both forms: `y = Tᵀ π_c`, the error `E` and
/// `Jl(E)⁻¹`, `Jr(E)⁻¹`.
struct PlaneError {
    /// `Rᵀ`.
    r_t: Matrix3<f64>,
    /// `n_c`, the measured plane's normal part (unnormalised).
    n: Vector3<f64>,
    /// `y_v = Rᵀ n_c`.
    y_v: Vector3<f64>,
    /// `y_w = tᵀ n_c + d_c`.
    y_w: f64,
    /// `E = log(q(y) ⊗ q_w⁻¹)`.
    e: Vector3<f64>,
    /// `Jl(E)⁻¹`.
    jl_inv: Matrix3<f64>,
    /// `Jr(E)⁻¹ = Jl(−E)⁻¹`.
    jr_inv: Matrix3<f64>,
}

impl PlaneError {
    fn new(f: &PlaneFactor) -> Self {
        let r_t = f.pose.rotation.matrix().transpose();
        let t = f.pose.translation;
        let n = f.measured.xyz();
        // y = Tᵀ π_c = [Rᵀ n_c, tᵀ n_c + d_c]. q(π_c) and q(y) are positive
        // scalings, and the logarithm is homogeneous of degree 0: neither
        // normalisation changes E.
        let y_v = r_t * n;
        let y_w = t.dot(&n) + f.measured.w;
        // z = y ⊗ q_w* = [q_w,w y_v − y_w q_w,v − y_v × q_w,v, y_w q_w,w + y_v · q_w,v].
        let q = f.plane.quaternion;
        let q_v = Vector3::new(q.x, q.y, q.z);
        let z_v = y_v * q.w - q_v * y_w - y_v.cross(&q_v);
        let z_w = y_w * q.w + y_v.dot(&q_v);
        let (e, theta) = quaternion_log(&z_v, z_w);
        // c = 1/θ² − cot(θ/2)/(2θ), with cot(θ/2) = z_w/|z_v| read off z.
        let t2 = theta * theta;
        let c = if t2 < SMALL_ANGLE_SQUARED {
            1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0
        } else {
            1.0 / t2 - z_w / (2.0 * theta * z_v.norm())
        };
        PlaneError {
            r_t,
            n,
            y_v,
            y_w,
            e,
            jl_inv: left_jacobian_inverse(&e, c),
            jr_inv: left_jacobian_inverse(&-e, c),
        }
    }

    /// `∂y/∂δξ` (4 × 6), (13)'s last factor **corrected**: under
    /// `T ← Exp(δξ) T`, `δy = [Rᵀ ⌊n_c⌋× δω, (t × n_c)·δω + n_c·δρ]`, i.e.
    /// `[[Rᵀ ⌊n_c⌋×, 0], [(t × n_c)ᵀ, n_cᵀ]]`. The document's derivation has
    /// the `q_vᵀ δρ` term on its way but drops it: its result has no `δρ`
    /// columns.
    fn d_y(&self, t: &Vector3<f64>) -> SMatrix<f64, 4, 6> {
        let mut d = SMatrix::<f64, 4, 6>::zeros();
        d.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(self.r_t * skew(&self.n)));
        let tn = t.cross(&self.n);
        d.fixed_view_mut::<1, 3>(3, 0).copy_from(&tn.transpose());
        d.fixed_view_mut::<1, 3>(3, 3)
            .copy_from(&self.n.transpose());
        d
    }
}

/// Residual `E = log(q(Tᵀ q(π_c)) ⊗ q_w⁻¹)` and its Jacobians w.r.t. the pose
/// (left, `[δω, δρ]`) and the plane landmark (left, `q_w ← exp(δω) ⊗ q_w`),
/// document 000 §IV (13) and B, with (13) corrected and its middle links
/// fused.
///
/// (13) is `∂E/∂ξ = ∂E/∂u ∂u/∂φ ∂φ/∂y ∂y/∂ξ` with `y = Tᵀ π_c`, `φ = y/|y|`,
/// `u = log φ`. Corrected (see [`plane_document_chain`], which evaluates it
/// link by link): `∂E/∂u = Jl(E)⁻¹ Jl(u)` (the document's `Jl(β)⁻¹` treats
/// `δu` as a perturbation on the left of `exp(u)`, but `u` is additive);
/// `∂y/∂ξ` keeps its `δρ` half. Here the middle links are fused: on the
/// tangent of the sphere, `Jl(u) ∂u/∂φ` maps `δφ` to the rotation `a` with
/// `δφ = [a/2, 0] ⊗ φ`, i.e. `a = 2 vec(δφ ⊗ φ*)`, and `vec(φ ⊗ φ*) = 0`
/// absorbs `∂φ/∂y`'s projection, so
///
/// `∂E/∂δξ = 2/|y|² Jl(E)⁻¹ [y_w I + ⌊y_v⌋×, −y_v] ∂y/∂δξ`,
///
/// free of the chain's singularities at `u = 0` and `|u| → 2π` (where the
/// factor is regular). With `y_v = Rᵀ n_c` the `δω` half is
/// `Rᵀ (y_w ⌊n_c⌋× + n_c n_cᵀ − |n_c|² I) − y_v (t × n_c)ᵀ` and the `δρ` half
/// `−y_v n_cᵀ`.
///
/// B: `∂E/∂δω_plane = −Jr(E)⁻¹`, right as printed.
///
/// Does not validate: the caller rejects `π_c = 0` and the antipodal error.
pub fn plane(f: &PlaneFactor) -> PlaneFactorLinearization {
    let p = PlaneError::new(f);
    let t = f.pose.translation;
    let n = p.n;
    let scale = 2.0 / (p.y_v.norm_squared() + p.y_w * p.y_w);
    let m = skew(&n) * p.y_w + n * n.transpose() - Matrix3::from_diagonal_element(n.norm_squared());
    let a_rot = p.r_t * m - p.y_v * t.cross(&n).transpose();
    let d_rot = p.jl_inv * a_rot * scale;
    let d_trans = (p.jl_inv * p.y_v) * (n.transpose() * -scale);
    let mut pose = SMatrix::<f64, 3, 6>::zeros();
    pose.fixed_view_mut::<3, 3>(0, 0).copy_from(&d_rot);
    pose.fixed_view_mut::<3, 3>(0, 3).copy_from(&d_trans);
    PlaneFactorLinearization {
        residual: p.e,
        pose,
        plane: -p.jr_inv,
    }
}

/// The same linearization as [`plane()`], by document 000 (13) link by link
/// with its corrections, for checking them:
///
/// - `∂E/∂u = Jl(E)⁻¹ Jl(u)`: `exp(u + δu) = exp(Jl(u) δu) ⊗ exp(u)` to first
///   order, then BCH (1) on the left of `exp(E)`; the document's
///   `Jl(β)⁻¹` (`β = E`) alone treats `δu` as a left perturbation;
/// - `∂u/∂φ = [2 cos⁻¹(φ₄) (I/|φ_v| − φ_v φ_vᵀ/|φ_v|³),
///   −2 φ_v/(|φ_v| √(1 − φ₄²))]`: exponent 3, not 3/2, and the `φ₄` column
///   is the derivative of `2 cos⁻¹(φ₄)`, not `2 cos⁻¹(φ₄)/√(1 − φ₄²) φ_v`;
/// - `∂φ/∂y = I/|y| − y yᵀ/|y|³`: exponent 3, not 3/2;
/// - `∂y/∂ξ = [[Rᵀ ⌊n_c⌋×, 0], [(t × n_c)ᵀ, n_cᵀ]]`, with its `δρ` half.
///
/// Singular where the chain is (`u = 0`, `φ₄ = ±1`), unlike the factor.
pub fn plane_document_chain(f: &PlaneFactor) -> PlaneFactorLinearization {
    let p = PlaneError::new(f);
    let y = Vector4::new(p.y_v.x, p.y_v.y, p.y_v.z, p.y_w);
    let y_norm = y.norm();
    let phi = y / y_norm;
    let phi_v = phi.xyz();
    let s = phi_v.norm();
    let angle = 2.0 * phi.w.acos();
    let u = phi_v * (angle / s);

    let d_e_d_u = p.jl_inv * left_jacobian(&u);
    let mut d_u_d_phi = Matrix3x4::zeros();
    d_u_d_phi
        .fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&((Matrix3::identity() / s - phi_v * phi_v.transpose() / (s * s * s)) * angle));
    d_u_d_phi
        .fixed_view_mut::<3, 1>(0, 3)
        .copy_from(&(phi_v * (-2.0 / (s * (1.0 - phi.w * phi.w).sqrt()))));
    let d_phi_d_y = Matrix4::identity() / y_norm - y * y.transpose() / (y_norm * y_norm * y_norm);
    let pose = d_e_d_u * d_u_d_phi * d_phi_d_y * p.d_y(&f.pose.translation);
    PlaneFactorLinearization {
        residual: p.e,
        pose,
        plane: -p.jr_inv,
    }
}
