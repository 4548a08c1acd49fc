//! g2o's `EDGE_SE3_LINE3D` error.

use nalgebra::{Matrix3, Vector3, Vector4, Vector6};

use crate::DEGENERACY_TOLERANCE;
use crate::degenerate;
use crate::g2o::check_pose_quaternions;
use crate::g2o::eigen::{Isometry, normalized, pivot_quaternion, quaternion_of, transform_line};
use factor_core::geometry::OrthonormalLine;
use factor_core::lie::Se3RhoTheta;
use factor_core::linalg::{cross, norm, scale};
use factor_core::validation::exceeds;
use factor_core::{Factor, FactorError, Scalar};

/// g2o's `EdgeSE3Line3D` error: the landmark line moved into the robot frame,
/// `L = X⁻¹ · line`, then g2o's `Line3D::ominus` of the measurement: with
/// the orthonormal representations `(U, W)` of both (g2o's
/// `toOrthonormal`: `U = [w/|w|, d/|d|, w×d/|w×d|]`, `W` the rotation by
/// the angle of `(|w|, |d|)`),
/// `e = [q_v(U_Lᵀ U_m), atan2 of W_Lᵀ W_m]`, where `q_v` is the vector part
/// of the normalised quaternion Eigen makes of the matrix (its sign as
/// Eigen's conversion gives it). The measurement is used as written (g2o
/// does not make `w ⟂ d`); the sensor-offset parameter the edge names is not
/// used, as in g2o. Unwhitened: the edge's cost is `eᵀ Ω e`.
///
/// - `pose` `X` maps body to world: **right** perturbation, tangent
///   `[δρ, δθ]` ([`Se3RhoTheta`]); its rotation matrix is Eigen's of the
///   stored quaternion, not normalised ([`crate::g2o`]).
/// - `line`: the world line, **right** perturbation `U ← U Exp(δΘ)`,
///   `W ← W R(δρ)` (g2o's `Line3D::oplus` multiplies on the right too).
///
/// Degenerate: a line through the robot's origin (`w = 0` in the robot
/// frame, to 1e-9 of the magnitudes it is computed from) or a measurement
/// with `w = 0` or `w ∥ d`, where `U` is undefined; the error rotation at
/// 120° where Eigen's conversion changes branch and the error jumps; and a
/// pose quaternion whose norm is off by more than
/// [`crate::g2o::QUATERNION_TOLERANCE`].
#[derive(Debug, Clone, Factor)]
#[factor(
    residual = g2o_line_residual,
    dim = 4,
    validate = validate_g2o_line,
    name = "g2o_se3_line3d"
)]
pub struct G2oLineEdge<S: Scalar = f64> {
    /// The measured line `[w, d]` in the robot frame, as written.
    pub measured: Vector6<S>,
    /// Body-to-world robot pose `X`.
    #[variable(right)]
    pub pose: Se3RhoTheta<S>,
    /// The world line.
    #[variable(right)]
    pub line: OrthonormalLine<S>,
}

/// g2o's `Line3D::toOrthonormal` of `[w, d]`: `U` and `(cos, sin)` of `W`.
fn orthonormal<S: Scalar>(moment: &Vector3<S>, direction: &Vector3<S>) -> (Matrix3<S>, [S; 2]) {
    let (w_norm, d_norm) = (norm(moment), norm(direction));
    let inv = (d_norm * d_norm + w_norm * w_norm).sqrt().recip();
    let normal = cross(moment, direction);
    let u = Matrix3::from_columns(&[
        scale(w_norm.recip(), moment),
        scale(d_norm.recip(), direction),
        scale(norm(&normal).recip(), &normal),
    ]);
    (u, [w_norm * inv, d_norm * inv])
}

/// The landmark in the robot frame, `X⁻¹ · line`.
fn robot_frame_line<S: Scalar>(f: &G2oLineEdge<S>) -> (Vector3<S>, Vector3<S>) {
    let world = f.line.to_plucker();
    let to_robot = Isometry::from_pose(&f.pose.se3()).inverse();
    transform_line(&to_robot, &world.normal, &world.direction)
}

/// `U_Lᵀ U_m`, `W_Lᵀ W_m` as `(cos, sin)`.
fn differences<S: Scalar>(f: &G2oLineEdge<S>) -> (Matrix3<S>, [S; 2]) {
    let (moment, direction) = robot_frame_line(f);
    let (u_l, [c_l, s_l]) = orthonormal(&moment, &direction);
    let m = &f.measured;
    let (u_m, [c_m, s_m]) = orthonormal(
        &Vector3::new(m[0], m[1], m[2]),
        &Vector3::new(m[3], m[4], m[5]),
    );
    (
        u_l.transpose() * u_m,
        [c_l * c_m + s_l * s_m, c_l * s_m - s_l * c_m],
    )
}

/// `[q_v(U_Lᵀ U_m), atan2 of W_Lᵀ W_m]`.
pub fn g2o_line_residual<S: Scalar>(f: &G2oLineEdge<S>) -> Vector4<S> {
    let (u, [c, s]) = differences(f);
    let q = normalized(&quaternion_of(&u));
    Vector4::new(q.x, q.y, q.z, s.atan2(c))
}

/// Rejects pose quaternions off unit norm, a line through the robot's
/// origin, a measurement without an orthonormal representation, and the
/// jump of the error at 120°.
pub fn validate_g2o_line(f: &G2oLineEdge<f64>) -> Result<(), FactorError> {
    let name = G2oLineEdge::NAME;
    check_pose_quaternions(name, &[("pose", &f.pose.se3())])?;
    let world = f.line.to_plucker();
    let (moment, _) = robot_frame_line(f);
    let terms = world.normal.norm() + f.pose.translation().norm() * world.direction.norm();
    if !exceeds(moment.norm(), DEGENERACY_TOLERANCE * terms) {
        return Err(degenerate(
            name,
            "the line passes through the robot's origin (its moment in the robot frame is \
             zero), where its orthonormal representation is undefined"
                .into(),
        ));
    }
    let (w, d) = (f.measured.fixed_rows::<3>(0), f.measured.fixed_rows::<3>(3));
    if !exceeds(
        w.cross(&d).norm(),
        DEGENERACY_TOLERANCE * w.norm() * d.norm(),
    ) {
        return Err(degenerate(
            name,
            "the measured line has a zero moment w or w parallel to d, where its orthonormal \
             representation is undefined"
                .into(),
        ));
    }
    let (u, _) = differences(f);
    // Near trace 0 Eigen switches from the trace branch (`w > 0`) to the
    // pivot branch, whose `w` may be negative: then the error jumps.
    if !exceeds(u.trace().abs(), DEGENERACY_TOLERANCE) && pivot_quaternion(&u).w < 0.0 {
        return Err(degenerate(
            name,
            "the line error is a rotation of 120°, where Eigen's matrix-to-quaternion \
             conversion changes branch and g2o's error jumps"
                .into(),
        ));
    }
    Ok(())
}
