//! The documents' line and plane factors on g2o's robot pose: the
//! residual of [`LineObservation`] or [`PlaneFactor`] at the world-to-camera
//! pose `T = X⁻¹` of the body-to-world vertex `X` that g2o's graphs hold
//! (the body is the camera, see [`super::documents`]), as factors of their
//! own on `X` (`Se3RhoTheta`, right chart), so that any solver holding
//! g2o's vertices differentiates them like g2o's own edges: the inverse is
//! part of the residual, and dual numbers (or a generated kernel) give the
//! exact blocks on `X`'s chart, with no adjoint applied afterwards.
//!
//! The landmarks use the right charts of g2o's edges on the same vertices
//! ([`super::G2oLineEdge`], [`super::G2oPlaneEdge`]), so a graph keeps one
//! chart per vertex type whichever factors measure it. Build them from a
//! g2o edge with [`super::line_observation`] or [`super::plane_observation`]
//! (the measurement and the information in the documents' residual space),
//! then [`LineObservationOnBody::new`] or [`PlaneFactorOnBody::new`].

use nalgebra::{Unit, Vector3, Vector4};

use super::documents::inverse_of_normalized;
use crate::line_observation::{
    LineObservation, line_observation_residual, validate_line_observation,
};
use crate::plane::{PlaneFactor, plane_residual, validate_plane};
use factor_core::geometry::{InfinitePlane, OrthonormalLine};
use factor_core::lie::Se3RhoTheta;
use factor_core::{Factor, FactorError, Scalar};

/// [`LineObservation`] at `T = X⁻¹`: `[Log(U_mᵀ U_c), Log(W_mᵀ W_c)]` of
/// the line seen from the body-to-world robot pose `X`.
#[derive(Debug, Clone, Factor)]
#[factor(
    residual = line_observation_on_body_residual,
    dim = 4,
    validate = validate_line_observation_on_body,
    name = "line_observation_on_body"
)]
pub struct LineObservationOnBody<S: Scalar = f64> {
    /// The measured line in the robot (camera) frame.
    pub measured: OrthonormalLine<S>,
    /// Body-to-world robot pose `X`.
    #[variable(right)]
    pub pose: Se3RhoTheta<S>,
    /// The world line.
    #[variable(right)]
    pub line: OrthonormalLine<S>,
}

/// [`PlaneFactor`] at `T = X⁻¹`: `log(q(Tᵀ q(π_c)) ⊗ q_w⁻¹)` of the plane
/// measured from the body-to-world robot pose `X`.
#[derive(Debug, Clone, Factor)]
#[factor(
    residual = plane_on_body_residual,
    dim = 3,
    validate = validate_plane_on_body,
    name = "plane_on_body"
)]
pub struct PlaneFactorOnBody<S: Scalar = f64> {
    /// The measured plane in the robot (camera) frame, unit norm.
    pub measured: Unit<Vector4<S>>,
    /// Body-to-world robot pose `X`.
    #[variable(right)]
    pub pose: Se3RhoTheta<S>,
    /// The world plane landmark.
    #[variable(right)]
    pub plane: InfinitePlane<S>,
}

impl LineObservationOnBody {
    /// `factor` (its pose world-to-camera) on the body-to-world pose `pose`
    /// in place of `factor.pose` (which the caller derived from it).
    pub fn new(factor: &LineObservation, pose: Se3RhoTheta<f64>) -> Self {
        LineObservationOnBody {
            measured: factor.measured,
            pose,
            line: factor.line,
        }
    }
}

impl PlaneFactorOnBody {
    /// `factor` (its pose world-to-camera) on the body-to-world pose `pose`
    /// in place of `factor.pose` (which the caller derived from it).
    pub fn new(factor: &PlaneFactor, pose: Se3RhoTheta<f64>) -> Self {
        PlaneFactorOnBody {
            measured: factor.measured,
            pose,
            plane: factor.plane,
        }
    }
}

impl<S: Scalar> LineObservationOnBody<S> {
    /// The documents' factor at `T = X⁻¹` (`X`'s quaternion normalised, as
    /// [`super::world_to_body`] does).
    pub fn at_camera(&self) -> LineObservation<S> {
        LineObservation {
            measured: self.measured,
            pose: inverse_of_normalized(&self.pose.se3()),
            line: self.line,
        }
    }
}

impl<S: Scalar> PlaneFactorOnBody<S> {
    /// The documents' factor at `T = X⁻¹` (`X`'s quaternion normalised, as
    /// [`super::world_to_body`] does).
    pub fn at_camera(&self) -> PlaneFactor<S> {
        PlaneFactor {
            measured: self.measured,
            pose: inverse_of_normalized(&self.pose.se3()),
            plane: self.plane,
        }
    }
}

/// [`line_observation_residual`] at `X⁻¹`.
pub fn line_observation_on_body_residual<S: Scalar>(f: &LineObservationOnBody<S>) -> Vector4<S> {
    line_observation_residual(&f.at_camera())
}

/// [`validate_line_observation`] at `X⁻¹` (its errors name
/// `line_observation`, the documents' factor).
pub fn validate_line_observation_on_body(
    f: &LineObservationOnBody<f64>,
) -> Result<(), FactorError> {
    validate_line_observation(&f.at_camera())
}

/// [`plane_residual`] at `X⁻¹`.
pub fn plane_on_body_residual<S: Scalar>(f: &PlaneFactorOnBody<S>) -> Vector3<S> {
    plane_residual(&f.at_camera())
}

/// [`validate_plane`] at `X⁻¹` (its errors name `plane`, the documents'
/// factor).
pub fn validate_plane_on_body(f: &PlaneFactorOnBody<f64>) -> Result<(), FactorError> {
    validate_plane(&f.at_camera())
}
