//! g2o's own errors for its 3D pose, line, plane, point and prior edges,
//! written with the
//! derive so that costs compare exactly with g2o's χ² (`Σ eᵀ Ω e`) on the
//! graphs g2o writes (crate `slam-data` reads them: `g2o::read_graph`).
//!
//! | factor | g2o edge | variables (perturbation) | residual |
//! | --- | --- | --- | --- |
//! | [`G2oSe3Edge`] | `EDGE_SE3:QUAT` (`EdgeSE3`) | two poses (right, `[δρ, δθ]`) | `[q_v, t]` of `Z⁻¹ X_i⁻¹ X_j`, `w ≥ 0` |
//! | [`G2oLineEdge`] | `EDGE_SE3_LINE3D` (`EdgeSE3Line3D`) | pose (right), orthonormal line (right) | `Line3D::ominus`: `[q_v(U_Lᵀ U_m), angle(W_Lᵀ W_m)]` |
//! | [`G2oPlaneEdge`] | `EDGE_SE3_PLANE_CALIB` (`EdgeSE3PlaneSensorCalib`) | pose (right), plane (right), sensor offset (right) | `Plane3D::ominus`: azimuth, elevation, distance |
//! | [`G2oPointEdge`] | `EDGE_SE3_TRACKXYZ` (`EdgeSE3PointXYZ`) | pose (right), point (Euclidean); offset `P` a constant | `(X P)⁻¹ p − m` |
//! | [`G2oPriorEdge`] | `EDGE_SE3_PRIOR` (`EdgeSE3Prior`) | pose (right); offset `P` a constant | `[q_v, t]` of `Z⁻¹ X P`, `w ≥ 0` |
//!
//! and, for the documents' factors on these graphs
//! ([`line_observation`], [`plane_observation`] map the measurements):
//!
//! | factor | g2o edge | variables (perturbation) | residual |
//! | --- | --- | --- | --- |
//! | [`LineObservationOnBody`] | `EDGE_SE3_LINE3D` | pose (right), orthonormal line (right) | [`LineObservation`](crate::LineObservation)'s at `X⁻¹` |
//! | [`PlaneFactorOnBody`] | `EDGE_SE3_PLANE_CALIB`, offset fixed | pose (right), plane (right) | [`PlaneFactor`](crate::PlaneFactor)'s at `X⁻¹` |
//!
//! The factors are unwhitened: the information matrix of an edge weights
//! its residual outside (`eᵀ Ω e`), in the residual order above, which is
//! g2o's order for the line, plane and point edges and that of
//! `slam-data`'s `[δω, δρ]` pose-graph information for [`G2oSe3Edge`] and
//! [`G2oPriorEdge`].
//!
//! # Linearization
//!
//! [`G2oSe3Edge`] has a generated kernel (`generated/src/g2o_se3.rs`);
//! [`G2oPointEdge`] and [`G2oPriorEdge`] linearize through dual numbers
//! (one of each per pose or observation: not where the time goes);
//! [`G2oLineEdge`] and [`G2oPlaneEdge`] linearize through dual numbers:
//! their kernels take the code generator about 2.2 s of CPU together in
//! the debug build, as much as the whole shipped set (2.0 s; measured on
//! 30 November 2026), so every `slamjac generate` and `check`, and the
//! tests that run them, would take twice as long. They still compare exactly with g2o (the cost does not depend
//! on how the Jacobian is formed).
//!
//! # Exactly as g2o computes
//!
//! The errors were reproduced from g2o's headers and sources
//! (`types_slam3d`: `edge_se3`, `isometry3d_mappings`; `types_slam3d_addons`:
//! `line3d`, `plane3d`, `edge_se3_line`, `edge_se3_plane_calib`) as the
//! PyPI wheel `g2opy` 2.3.0 builds them, with Eigen 3.3, and checked on the
//! graphs g2o's simulators wrote (`data/g2o-addons/`): the cost of every
//! factor at the files' values equals g2o's χ² to rounding
//! (`tests/g2o_graphs.rs`). What matters for that:
//!
//! - g2o reads a `VERTEX_SE3:QUAT` quaternion into a rotation matrix
//!   without normalising it (Eigen's `toRotationMatrix`,
//!   [`eigen::rotation_matrix`]), and g2o's files write six significant
//!   digits, so the matrices are orthogonal only to about 1e-6. The factors
//!   do the same with the quaternion they store: a pose read from a file
//!   keeps its quaternion as written. (Normalised, the costs of
//!   `line3d.g2o` change by 2e-7 relative for the line edges and 1e-2 for
//!   the pose edges, whose cost is small.) Quaternions whose norm is off by
//!   more than [`QUATERNION_TOLERANCE`] are rejected.
//! - Inverses of poses transpose the linear part, products multiply it
//!   ([`eigen::Isometry`]); the plane edge takes the polar factor of it
//!   ([`eigen::polar_quaternion`], Eigen 3.3's `Transform::rotation()`;
//!   without it the cost of `plane3d.g2o` changes by 1e-6 relative).
//! - Eigen's matrix-to-quaternion conversion picks a branch and a sign
//!   ([`eigen::quaternion_of`]); the line edge keeps that sign, the pose
//!   edge folds it to `w ≥ 0`.
//! - The line measurement is used as written (its `w ⟂ d` only to its
//!   digits); the plane measurement and landmark are scaled to a unit
//!   normal, as g2o's `Plane3D` does on loading.
//! - The sensor-offset parameter of `EDGE_SE3_LINE3D` is resolved by g2o
//!   but not used: [`G2oLineEdge`] has no offset. Those of
//!   `EDGE_SE3_TRACKXYZ` and `EDGE_SE3_PRIOR` are used (g2o's
//!   `CacheSE3Offset`: `X P` and its isometry inverse) and are constants
//!   of [`G2oPointEdge`] and [`G2oPriorEdge`].

mod documents;
pub mod eigen;
mod line_edge;
mod on_body;
mod plane_edge;
mod point_edge;
mod prior_edge;
mod se3_edge;

pub use documents::{
    line_landmark, line_observation, line_observation_information, plane_observation, world_to_body,
};
pub use line_edge::{G2oLineEdge, g2o_line_residual, validate_g2o_line};
pub use on_body::{
    LineObservationOnBody, PlaneFactorOnBody, line_observation_on_body_residual,
    plane_on_body_residual, validate_line_observation_on_body, validate_plane_on_body,
};
pub use plane_edge::{G2oPlaneEdge, g2o_plane_residual, validate_g2o_plane};
pub use point_edge::{G2oPointEdge, g2o_point_residual, validate_g2o_point};
pub use prior_edge::{G2oPriorEdge, g2o_prior_residual, validate_g2o_prior};
pub use se3_edge::{G2oSe3Edge, g2o_se3_residual, validate_g2o_se3};

use factor_core::FactorError;
use factor_core::lie::Se3;
use factor_core::linalg::scaled_norm;
use factor_core::validation::{number_text, within};

/// The largest deviation from unit norm of a pose quaternion the g2o
/// factors accept (that of `slam-data`'s readers): g2o builds a rotation
/// matrix from the quaternion without normalising it, which is a rotation
/// only for a unit quaternion.
pub const QUATERNION_TOLERANCE: f64 = 1e-5;

/// Rejects a pose whose quaternion's norm is off by more than
/// [`QUATERNION_TOLERANCE`].
fn check_pose_quaternions(
    factor: &'static str,
    poses: &[(&str, &Se3<f64>)],
) -> Result<(), FactorError> {
    for (name, pose) in poses {
        let norm = scaled_norm(&pose.rotation.quaternion.coords());
        if !within(norm - 1.0, QUATERNION_TOLERANCE) {
            return Err(crate::degenerate(
                factor,
                format!(
                    "the quaternion of {name} has norm {}, off unit by more than 1e-5: the \
                     matrix g2o makes of it is not a rotation",
                    number_text(norm)
                ),
            ));
        }
    }
    Ok(())
}
