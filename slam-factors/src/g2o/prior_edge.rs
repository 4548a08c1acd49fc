//! g2o's `EDGE_SE3_PRIOR` error.

use nalgebra::Vector6;

use crate::g2o::check_pose_quaternions;
use crate::g2o::eigen::Isometry;
use crate::g2o::se3_edge::{check_not_half_turn, vector_mqt};
use factor_core::lie::{Se3, Se3RhoTheta};
use factor_core::{Factor, FactorError, Scalar};

/// g2o's `EdgeSE3Prior` error, `[q_v, t]` of `Δ = Z⁻¹ · (X · P)`: the
/// measured world-from-sensor pose `Z` against the robot pose `X` carrying
/// the sensor offset `P` (the edge's `PARAMS_SE3OFFSET`, sensor to robot),
/// `q` the unit quaternion of `Δ`'s linear part with `w ≥ 0`. This is g2o's
/// `toVectorMQT(Δ)` with its halves swapped, as [`crate::G2oSe3Edge`]'s,
/// so that the prior's information as crate `slam-data` reads it
/// (reordered to `[δω, δρ]`) applies as it is. Unwhitened: the edge's cost
/// is `eᵀ Ω e`.
///
/// `Z`, `X` and `P` are used as g2o uses them: Eigen's rotation matrices of
/// their quaternions as stored, not normalised ([`crate::g2o`]; the g2o
/// library `g2opy` 2.3.0 reads `PARAMS_SE3OFFSET` so, while g2o's master
/// branch normalises the parameter's quaternion on reading: the same within
/// the 1e-5 the readers accept).
///
/// - `pose` `X` (body to world): **right** perturbation, tangent `[δρ, δθ]`
///   ([`Se3RhoTheta`]).
///
/// Degenerate: a rotation error of π (`w = 0`, where g2o's choice `w ≥ 0`
/// flips the sign of `q_v`), and a quaternion whose norm is off by more
/// than [`crate::g2o::QUATERNION_TOLERANCE`].
#[derive(Debug, Clone, Factor)]
#[factor(
    residual = g2o_prior_residual,
    dim = 6,
    validate = validate_g2o_prior,
    name = "g2o_se3_prior"
)]
pub struct G2oPriorEdge<S: Scalar = f64> {
    /// The measured world-from-sensor pose `Z`, quaternion as written.
    pub measured: Se3<S>,
    /// The sensor offset `P` (sensor to body), quaternion as written.
    pub offset: Se3<S>,
    /// Body-to-world robot pose `X`.
    #[variable(right)]
    pub pose: Se3RhoTheta<S>,
}

/// `Z⁻¹ · (X · P)`.
fn error_isometry<S: Scalar>(f: &G2oPriorEdge<S>) -> Isometry<S> {
    let sensor = Isometry::from_pose(&f.pose.se3()).compose(&Isometry::from_pose(&f.offset));
    Isometry::from_pose(&f.measured).inverse().compose(&sensor)
}

/// `[q_v, t]` of `Z⁻¹ · (X · P)`, `q` with `w ≥ 0`.
pub fn g2o_prior_residual<S: Scalar>(f: &G2oPriorEdge<S>) -> Vector6<S> {
    vector_mqt(&error_isometry(f))
}

/// Rejects quaternions off unit norm and a rotation error of π.
pub fn validate_g2o_prior(f: &G2oPriorEdge<f64>) -> Result<(), FactorError> {
    check_pose_quaternions(
        G2oPriorEdge::NAME,
        &[
            ("measured", &f.measured),
            ("offset", &f.offset),
            ("pose", &f.pose.se3()),
        ],
    )?;
    check_not_half_turn(G2oPriorEdge::NAME, "the rotation error", &error_isometry(f))
}
