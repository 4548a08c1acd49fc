//! Point reprojection, document 000 §II, by hand.

use nalgebra::{Matrix2x3, SMatrix, Vector2};

use crate::PointReprojection;
use crate::point_reprojection::PointReprojectionLinearization;

/// Residual `ρ = p_obs − π(K, R X_w + t)` and its Jacobians w.r.t. the pose
/// (left, `[δω, δρ]`) and the point (additive), document 000 (2)–(5).
///
/// With `P = R X_w + t`, `x = P_x/P_z`, `y = P_y/P_z`:
/// - (2): `∂π/∂P = [[f_u/P_z, 0, −f_u x/P_z], [0, f_v/P_z, −f_v y/P_z]]` (the
///   document's `[f_u 0 c_u; 0 f_v c_v]` times a 3 × 3 with a zero last row
///   is the same matrix; (5) repeats that matrix's second row by a typo);
/// - (3): `∂P/∂X_w = R`, so `∂ρ/∂X_w = −∂π/∂P R`;
/// - (4), **corrected**: the document's `[I, −⌊P⌋×]` has the tangent halves
///   swapped; for `δξ = [δω, δρ]` (rotation first, as the document itself
///   defines `ξ = {ω, ρ}`) it is `∂P/∂δξ = [−⌊P⌋×, I]`, so
///   `∂ρ/∂δξ = [∂π/∂P ⌊P⌋×, −∂π/∂P]`. The rotation half is written out:
///   `∂π/∂P ⌊P⌋× = [[f_u x y, −f_u (1 + x²), f_u y], [f_v (1 + y²), −f_v x y, −f_v x]]`.
///
/// Does not validate: the caller rejects `P_z ≤ 0` first.
pub fn point_reprojection(f: &PointReprojection) -> PointReprojectionLinearization {
    let k = &f.intrinsics;
    let r = f.pose.rotation.matrix();
    let p = r * f.point + f.pose.translation;
    let inv_z = 1.0 / p.z;
    let (x, y) = (p.x * inv_z, p.y * inv_z);
    let residual = Vector2::new(
        f.observed.x - (k.fu * x + k.cu),
        f.observed.y - (k.fv * y + k.cv),
    );

    // ∂π/∂P, (2), and ∂ρ/∂X_w = −∂π/∂P R, (3): row-wise, skipping the
    // zeros, −[f_u/P_z (R₀ − x R₂); f_v/P_z (R₁ − y R₂)] with Rᵢ the rows of R.
    let (fu_z, fv_z) = (k.fu * inv_z, k.fv * inv_z);
    let (r0, r1, r2) = (r.row(0), r.row(1), r.row(2));
    let point = Matrix2x3::from_rows(&[(r2 * x - r0) * fu_z, (r2 * y - r1) * fv_z]);

    // −∂π/∂P [−⌊P⌋×, I], (4) corrected.
    let (fu_xy, fv_xy) = (k.fu * x * y, k.fv * x * y);
    #[rustfmt::skip]
    let pose = SMatrix::<f64, 2, 6>::new(
        fu_xy, -k.fu * (1.0 + x * x), k.fu * y, -fu_z, 0.0, fu_z * x,
        k.fv * (1.0 + y * y), -fv_xy, -k.fv * x, 0.0, -fv_z, fv_z * y,
    );
    PointReprojectionLinearization {
        residual,
        pose,
        point,
    }
}
