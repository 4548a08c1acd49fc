//! g2o's `EDGE_SE3_TRACKXYZ` error.

use nalgebra::Vector3;

use crate::g2o::check_pose_quaternions;
use crate::g2o::eigen::Isometry;
use factor_core::lie::{Se3, Se3RhoTheta};
use factor_core::{Factor, FactorError, Scalar};

/// g2o's `EdgeSE3PointXYZ` error, `(X · P)⁻¹ · p − m`: the world point `p`
/// (a `VERTEX_TRACKXYZ`) in the frame of the sensor mounted at the offset
/// `P` (the edge's `PARAMS_SE3OFFSET`, sensor to robot) on the robot at
/// pose `X`, minus the measured point `m`. Unwhitened: the edge's cost is
/// `eᵀ Ω e`, `Ω` in the order `[x, y, z]`.
///
/// `X` and `P` are used as g2o uses them ([`crate::g2o`]): Eigen's matrices
/// of their quaternions as stored, and Eigen's isometry inverse of their
/// product (the transpose of its linear part).
///
/// - `pose` `X` (body to world): **right** perturbation, tangent `[δρ, δθ]`
///   ([`Se3RhoTheta`]).
/// - `point` `p`: Euclidean.
///
/// Degenerate: a quaternion whose norm is off by more than
/// [`crate::g2o::QUATERNION_TOLERANCE`]; the error is linear in `p` and
/// smooth in `X` everywhere else.
#[derive(Debug, Clone, Factor)]
#[factor(
    residual = g2o_point_residual,
    dim = 3,
    validate = validate_g2o_point,
    name = "g2o_se3_trackxyz"
)]
pub struct G2oPointEdge<S: Scalar = f64> {
    /// The measured point `m` in the sensor frame.
    pub measured: Vector3<S>,
    /// The sensor offset `P` (sensor to body), quaternion as written.
    pub offset: Se3<S>,
    /// Body-to-world robot pose `X`.
    #[variable(right)]
    pub pose: Se3RhoTheta<S>,
    /// The point in the world.
    #[variable]
    pub point: Vector3<S>,
}

/// `(X · P)⁻¹ · p − m`.
pub fn g2o_point_residual<S: Scalar>(f: &G2oPointEdge<S>) -> Vector3<S> {
    let world_to_sensor = Isometry::from_pose(&f.pose.se3())
        .compose(&Isometry::from_pose(&f.offset))
        .inverse();
    world_to_sensor.apply(&f.point) - f.measured
}

/// Rejects quaternions off unit norm.
pub fn validate_g2o_point(f: &G2oPointEdge<f64>) -> Result<(), FactorError> {
    check_pose_quaternions(
        G2oPointEdge::NAME,
        &[("offset", &f.offset), ("pose", &f.pose.se3())],
    )
}
