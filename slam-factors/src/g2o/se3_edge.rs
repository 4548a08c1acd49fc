//! g2o's `EDGE_SE3:QUAT` error.

use nalgebra::Vector6;

use crate::degenerate;
use crate::g2o::check_pose_quaternions;
use crate::g2o::eigen::{Isometry, normalized, quaternion_of};
use factor_core::lie::{Quaternion, Se3, Se3RhoTheta};
use factor_core::validation::{exceeds, number_text};
use factor_core::{Factor, FactorError, Scalar};

/// g2o's `EdgeSE3` error, `[q_v, t]` of `Δ = Z⁻¹ · X_i⁻¹ · X_j` with `q` the
/// unit quaternion of `Δ`'s linear part taken with `w ≥ 0` (g2o's
/// `toVectorMQT`, whose order is `[t, q_v]`: here the halves are swapped so
/// that an edge's information as crate `slam-data` reads it, reordered to
/// `[δω, δρ]`, applies as it is). Unwhitened: the edge's cost is `eᵀ Ω e`.
///
/// Poses are used as g2o uses them: their rotation matrices are Eigen's of
/// the stored quaternions, not normalised ([`crate::g2o`]).
///
/// - `pose_i`, `pose_j` map body to world: **right** perturbation, tangent
///   `[δρ, δθ]` ([`Se3RhoTheta`]).
///
/// Degenerate: a relative rotation error of π (`w = 0`, where g2o's choice
/// `w ≥ 0` flips the sign of `q_v`), and a pose quaternion whose norm is
/// off by more than [`crate::g2o::QUATERNION_TOLERANCE`].
#[derive(Debug, Clone, Factor)]
#[factor(residual = g2o_se3_residual, dim = 6, validate = validate_g2o_se3, name = "g2o_se3")]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = factor_generated::g2o_se3::g2o_se3,
        regenerate = "cargo run --release --no-default-features -- generate",
        hosts(apex)
    )
)]
pub struct G2oSe3Edge<S: Scalar = f64> {
    /// The measured pose `Z` of `j` in the frame of `i`, quaternion as written.
    pub measured: Se3<S>,
    /// Body-to-world pose `X_i`.
    #[variable(right)]
    pub pose_i: Se3RhoTheta<S>,
    /// Body-to-world pose `X_j`.
    #[variable(right)]
    pub pose_j: Se3RhoTheta<S>,
}

/// `Z⁻¹ · X_i⁻¹ · X_j`.
fn error_isometry<S: Scalar>(f: &G2oSe3Edge<S>) -> Isometry<S> {
    Isometry::from_pose(&f.measured)
        .inverse()
        .compose(&Isometry::from_pose(&f.pose_i.se3()).inverse())
        .compose(&Isometry::from_pose(&f.pose_j.se3()))
}

/// The quaternion of `delta`'s linear part (normalised, sign as Eigen's
/// conversion gives it).
fn error_quaternion<S: Scalar>(delta: &Isometry<S>) -> Quaternion<S> {
    normalized(&quaternion_of(&delta.linear))
}

/// g2o's `toVectorMQT` of `delta` with its halves swapped: `[q_v, t]`, `q`
/// the unit quaternion of the linear part taken with `w ≥ 0`.
pub(crate) fn vector_mqt<S: Scalar>(delta: &Isometry<S>) -> Vector6<S> {
    let q = error_quaternion(delta);
    let q = Quaternion::select(q.w, S::zero(), &q.negated(), &q);
    let t = delta.translation;
    Vector6::new(q.x, q.y, q.z, t.x, t.y, t.z)
}

/// Rejects a rotation error of π in `delta` (`w = 0`), where the sign
/// choice of [`vector_mqt`] flips `q_v`; `what` names the error.
pub(crate) fn check_not_half_turn(
    factor: &'static str,
    what: &str,
    delta: &Isometry<f64>,
) -> Result<(), FactorError> {
    let q = error_quaternion(delta);
    if !exceeds(q.w.abs(), crate::DEGENERACY_TOLERANCE) {
        return Err(degenerate(
            factor,
            format!(
                "{what} is π (error quaternion w = {}), where g2o's error changes sign",
                number_text(q.w)
            ),
        ));
    }
    Ok(())
}

/// `[q_v, t]` of `Z⁻¹ · X_i⁻¹ · X_j`, `q` with `w ≥ 0`.
pub fn g2o_se3_residual<S: Scalar>(f: &G2oSe3Edge<S>) -> Vector6<S> {
    vector_mqt(&error_isometry(f))
}

/// Rejects pose quaternions off unit norm and a relative rotation of π.
pub fn validate_g2o_se3(f: &G2oSe3Edge<f64>) -> Result<(), FactorError> {
    check_pose_quaternions(
        G2oSe3Edge::NAME,
        &[
            ("measured", &f.measured),
            ("pose_i", &f.pose_i.se3()),
            ("pose_j", &f.pose_j.se3()),
        ],
    )?;
    check_not_half_turn(
        G2oSe3Edge::NAME,
        "the relative rotation error",
        &error_isometry(f),
    )
}
