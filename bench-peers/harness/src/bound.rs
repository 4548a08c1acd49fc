//! The fewest-operations formulas for the two factors, written by hand as
//! scalar `f64` code in the generated kernels' layout: a reference for how
//! fast the same contract can be without SIMD written by hand, timed beside
//! the generated kernel and wrenfold's by `ab`.
//!
//! Both materialise the rotation matrix `R` of the (unit) quaternion once,
//! in its homogeneous form (as the generated kernels and wrenfold's do), and
//! are straight-line `let`s, as generated code is. The Plücker line computes
//! each per-row value of its two residual rows in one isomorphic statement
//! (`[0, 1].map(..)`), so that the optimiser may pack the rows two to a
//! register. (The same formulas through small vector helpers, `cross` and
//! `copy_from_slice`, ran at 61 ns instead of 35: LLVM did not scalarise
//! them.)
//!
//! - Point, `r = obs − c − f ⊙ X_c[0..2] / Z`, `X_c = R X + t`: with
//!   `gᵢ = ∂rᵢ/∂X_c`, the pose row `i` is `[(X_c × gᵢ)ᵀ, gᵢᵀ]` and the point
//!   row `Rᵀ gᵢ`.
//! - Plücker line, `rᵢ = eᵢᵀ 𝒦 n_c / √(l₁² + l₂²)`, `n_c = R n + t × R v`:
//!   the pose row `i` is `[(n_c × gᵢ)ᵀ, (v_c × gᵢ)ᵀ]`, the line row
//!   `[(Rᵀ gᵢ)ᵀ, ((Rᵀ gᵢ) × (Rᵀ t))ᵀ]`, the last because
//!   `Rᵀ (gᵢ × t) = (Rᵀ gᵢ) × (Rᵀ t)` for a rotation: one `Rᵀ t` shared by
//!   both rows instead of one `Rᵀ (gᵢ × t)` per row. This identity needs
//!   `R` orthogonal (a unit quaternion, which every sample is); a generator
//!   differentiating the homogeneous form cannot assume it.
//!
//! The outputs are checked against the generated kernels' ([`check_point`],
//! [`check_plucker`]) before anything is timed.

use slam_factors::{PluckerLineReprojection, PointReprojection};

use crate::ours::{PluckerArrayOutputs, PluckerArrays, PointArrayOutputs, PointArrays, matrix};
use crate::{Agreement, check, relative_error};

/// The rotation matrix of the quaternion `[x, y, z, w]` at the start of
/// `q`, row-major, in its homogeneous form (`|q|² R`).
#[inline(always)]
fn rotation(q: &[f64; 7]) -> [f64; 9] {
    let (x, y, z, w) = (q[0], q[1], q[2], q[3]);
    let (xx, yy, zz, ww) = (x * x, y * y, z * z, w * w);
    let (xy, zw, xz, yw, yz, xw) = (x * y, z * w, x * z, y * w, y * z, x * w);
    [
        (ww + xx) - (yy + zz),
        2.0 * (xy - zw),
        2.0 * (xz + yw),
        2.0 * (xy + zw),
        (ww - xx) + (yy - zz),
        2.0 * (yz - xw),
        2.0 * (xz - yw),
        2.0 * (yz + xw),
        (ww - xx) - (yy - zz),
    ]
}

/// The point factor, every block: residual, 2×6 left pose block, 2×3 point
/// block, row-major (the generated kernel's layout).
#[inline]
pub fn point_reprojection(input: &PointArrays) -> PointArrayOutputs {
    let mut residual = [0.0; 2];
    let mut d_pose = [0.0; 12];
    let mut d_point = [0.0; 6];
    let [r00, r01, r02, r10, r11, r12, r20, r21, r22] = rotation(&input.pose);
    let px = r00 * input.point[0] + r01 * input.point[1] + r02 * input.point[2] + input.pose[4];
    let py = r10 * input.point[0] + r11 * input.point[1] + r12 * input.point[2] + input.pose[5];
    let pz = r20 * input.point[0] + r21 * input.point[1] + r22 * input.point[2] + input.pose[6];
    // gᵢ = ∂rᵢ/∂X_c: −fᵢ/Z at column i, (fᵢ Xᵢ/Z)/Z at column 2.
    let iz = 1.0 / pz;
    let fx = input.intrinsics[0] * iz;
    let fy = input.intrinsics[1] * iz;
    let u = fx * px;
    let v = fy * py;
    residual[0] = (input.observed[0] - input.intrinsics[2]) - u;
    residual[1] = (input.observed[1] - input.intrinsics[3]) - v;
    let g02 = u * iz;
    let g12 = v * iz;
    {
        d_pose[0] = py * g02;
        d_pose[1] = -(input.intrinsics[0] + px * g02);
        d_pose[2] = py * fx;
        d_pose[3] = -fx;
        d_pose[4] = 0.0;
        d_pose[5] = g02;
        d_pose[6] = input.intrinsics[1] + py * g12;
        d_pose[7] = -(px * g12);
        d_pose[8] = -(px * fy);
        d_pose[9] = 0.0;
        d_pose[10] = -fy;
        d_pose[11] = g12;
    }
    {
        d_point[0] = r20 * g02 - r00 * fx;
        d_point[1] = r21 * g02 - r01 * fx;
        d_point[2] = r22 * g02 - r02 * fx;
        d_point[3] = r20 * g12 - r10 * fy;
        d_point[4] = r21 * g12 - r11 * fy;
        d_point[5] = r22 * g12 - r12 * fy;
    }
    (residual, d_pose, d_point)
}

/// The Plücker-line factor, every block: residual, 2×6 left pose block, 2×6
/// block w.r.t. `[n, v]`, row-major.
#[inline]
pub fn plucker_line_reprojection(input: &PluckerArrays) -> PluckerArrayOutputs {
    let mut residual = [0.0; 2];
    let [r00, r01, r02, r10, r11, r12, r20, r21, r22] = rotation(&input.pose);
    let (t0, t1, t2) = (input.pose[4], input.pose[5], input.pose[6]);
    let vc0 = r00 * input.line[3] + r01 * input.line[4] + r02 * input.line[5];
    let vc1 = r10 * input.line[3] + r11 * input.line[4] + r12 * input.line[5];
    let vc2 = r20 * input.line[3] + r21 * input.line[4] + r22 * input.line[5];
    let nc0 =
        r00 * input.line[0] + r01 * input.line[1] + r02 * input.line[2] + (t1 * vc2 - t2 * vc1);
    let nc1 =
        r10 * input.line[0] + r11 * input.line[1] + r12 * input.line[2] + (t2 * vc0 - t0 * vc2);
    let nc2 =
        r20 * input.line[0] + r21 * input.line[1] + r22 * input.line[2] + (t0 * vc1 - t1 * vc0);
    let (fu, fv, cu, cv) = (
        input.intrinsics[0],
        input.intrinsics[1],
        input.intrinsics[2],
        input.intrinsics[3],
    );
    // l = 𝒦 n_c = [a0, a1, l2].
    let a0 = fv * nc0;
    let a1 = fu * nc1;
    let fufv = fu * fv;
    let ss = a0 * a0 + a1 * a1;
    let inv = 1.0 / ss.sqrt();
    let l2 = fufv * nc2 - cu * a0 - cv * a1;
    let ex = [input.start[0], input.end[0]];
    let ey = [input.start[1], input.end[1]];
    let r = [0, 1].map(|i| (ex[i] * a0 + ey[i] * a1 + l2) * inv);
    residual[0] = r[0];
    residual[1] = r[1];
    // gᵢ = ∂rᵢ/∂n_c = (𝒦ᵀ eᵢ − rᵢ [f_v a0, f_u a1, 0] / s) / s, s = √(a0² + a1²);
    // its last entry f_u f_v / s is the same for both rows.
    let p0 = fv * a0 * inv;
    let p1 = fu * a1 * inv;
    let g2 = fufv * inv;
    let g0 = [0, 1].map(|i| (fv * (ex[i] - cu) - r[i] * p0) * inv);
    let g1 = [0, 1].map(|i| (fu * (ey[i] - cv) - r[i] * p1) * inv);
    let d_pose = {
        let a = [0, 1].map(|i| nc1 * g2 - nc2 * g1[i]);
        let b = [0, 1].map(|i| nc2 * g0[i] - nc0 * g2);
        let c = [0, 1].map(|i| nc0 * g1[i] - nc1 * g0[i]);
        let d = [0, 1].map(|i| vc1 * g2 - vc2 * g1[i]);
        let e = [0, 1].map(|i| vc2 * g0[i] - vc0 * g2);
        let f = [0, 1].map(|i| vc0 * g1[i] - vc1 * g0[i]);
        rows_of([a, b, c, d, e, f])
    };
    let d_line = {
        // Rᵀ gᵢ, then (Rᵀ gᵢ) × (Rᵀ t).
        let tw0 = r00 * t0 + r10 * t1 + r20 * t2;
        let tw1 = r01 * t0 + r11 * t1 + r21 * t2;
        let tw2 = r02 * t0 + r12 * t1 + r22 * t2;
        let dn0 = [0, 1].map(|i| r00 * g0[i] + r10 * g1[i] + r20 * g2);
        let dn1 = [0, 1].map(|i| r01 * g0[i] + r11 * g1[i] + r21 * g2);
        let dn2 = [0, 1].map(|i| r02 * g0[i] + r12 * g1[i] + r22 * g2);
        let d3 = [0, 1].map(|i| dn1[i] * tw2 - dn2[i] * tw1);
        let d4 = [0, 1].map(|i| dn2[i] * tw0 - dn0[i] * tw2);
        let d5 = [0, 1].map(|i| dn0[i] * tw1 - dn1[i] * tw0);
        rows_of([dn0, dn1, dn2, d3, d4, d5])
    };
    (residual, d_pose, d_line)
}

/// A 2 × 6 row-major block from its six columns, each `[row 0, row 1]`.
#[inline(always)]
fn rows_of(columns: [[f64; 2]; 6]) -> [f64; 12] {
    std::array::from_fn(|k| columns[k % 6][k / 6])
}

/// The worst relative error per output of `bound` against `generated` over
/// `outputs` pairs, or the first configuration above `tolerance`.
fn compare<const B: usize, const C: usize>(
    factor: &str,
    other: &str,
    outputs: impl Iterator<
        Item = (
            ([f64; 2], [f64; 12], [f64; B]),
            ([f64; 2], [f64; 12], [f64; B]),
        ),
    >,
    tolerance: f64,
) -> Result<Agreement, String> {
    let mut agreement = Agreement::default();
    for (i, (ours, generated)) in outputs.enumerate() {
        let errors = [
            (
                "residual",
                relative_error(&matrix::<2, 1>(&ours.0), &matrix::<2, 1>(&generated.0)),
            ),
            (
                "pose",
                relative_error(&matrix::<2, 6>(&ours.1), &matrix::<2, 6>(&generated.1)),
            ),
            (
                other,
                relative_error(&matrix::<2, C>(&ours.2), &matrix::<2, C>(&generated.2)),
            ),
        ];
        check(
            i,
            factor,
            ("the scalar bound's", "the generated kernel's"),
            &errors,
            tolerance,
        )?;
        agreement.update(errors[0].1, errors[1].1, errors[2].1);
    }
    Ok(agreement)
}

/// Compares [`point_reprojection`] with the generated kernel at every
/// configuration.
///
/// # Errors
///
/// The first configuration and block that differ by more than `tolerance`
/// (relative), NaN included.
pub fn check_point(factors: &[PointReprojection], tolerance: f64) -> Result<Agreement, String> {
    let pairs = factors
        .iter()
        .map(PointArrays::new)
        .map(|x| (point_reprojection(&x), x.generated()));
    compare::<6, 3>("point_reprojection", "point", pairs, tolerance)
}

/// As [`check_point`], for [`plucker_line_reprojection`].
///
/// # Errors
///
/// As [`check_point`].
pub fn check_plucker(
    factors: &[PluckerLineReprojection],
    tolerance: f64,
) -> Result<Agreement, String> {
    let pairs = factors
        .iter()
        .map(PluckerArrays::new)
        .map(|x| (plucker_line_reprojection(&x), x.generated()));
    compare::<12, 6>("plucker_line_reprojection", "line", pairs, tolerance)
}
