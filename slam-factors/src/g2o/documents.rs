//! g2o's line and plane graphs in the documents' terms: the landmarks as
//! the orthonormal line and the unit-quaternion plane, each measurement as
//! a [`LineObservation`] or a [`PlaneFactor`], with its information moved
//! into that factor's residual space.
//!
//! - Poses: g2o's `X` maps body to world; the documents' factors take the
//!   world-to-camera `T = X⁻¹` (here the body is the camera), with the
//!   quaternion normalised (the documents' poses are rotations). A solver
//!   holding `X` moves their Jacobian blocks with
//!   [`factor_core::lie::inverse_pose_block`].
//! - Lines: the measurement of `EDGE_SE3_LINE3D` is the line in the robot
//!   frame (g2o ignores the edge's sensor offset, so does the mapping): it
//!   is the measured line of a [`LineObservation`], oriented as g2o wrote
//!   it. g2o's simulator perturbs it as `U ← U R(q(ν))`, `W ← W R(ν₄)`
//!   with `q(ν) = [ν, √(1 − |ν|²)]`, which to first order moves the
//!   residual by `[−2ν, −ν₄]`: the information in the residual space is
//!   `D Ω D`, `D = diag(−½, −½, −½, −1)` ([`line_observation_information`]).
//! - Planes: the measurement of `EDGE_SE3_PLANE_CALIB` is in the frame of
//!   the sensor at offset `S` on the robot; the documents' plane factor has
//!   one pose, so the measurement is moved into the body frame through `S`
//!   taken as known (fixed, as in `plane3d.g2o`; a free offset, the
//!   calibration of `plane3d_calib.g2o`, has no counterpart in the
//!   documents' factor). g2o's noise is in its `Plane3D::oplus` chart
//!   (azimuth, elevation, distance), the residual of [`PlaneFactor`] a
//!   quaternion logarithm in the world frame: the information is moved by
//!   the Jacobian `J` of that residual w.r.t. g2o's chart of the measured
//!   plane at the given values, `Jᵀ⁻¹ Ω J⁻¹` ([`plane_observation`]), a
//!   noise model linearised once.

use factor_core::dual::Dual;
use nalgebra::{Matrix3, Matrix4, Unit, Vector3, Vector4, Vector6};

use crate::line_observation::LineObservation;
use crate::plane::{PlaneFactor, plane_residual};
use factor_core::geometry::plane::transpose_transform;
use factor_core::geometry::{InfinitePlane, OrthonormalLine, PluckerLine};
use factor_core::lie::{Se3, So3};
use factor_core::linalg::normalized;
use factor_core::{Factor, FactorError, Scalar, Storage, StorageError};

/// A g2o line `[w, d]` (`VERTEX_LINE3D`, or a measurement) as an orthonormal
/// line: the moment is first made perpendicular to the direction, `w ← w −
/// (w · d̂) d̂` (g2o writes six digits, so `w · d` is zero only to about
/// 1e-6 of `|w| |d|`), then converted by
/// [`OrthonormalLine::try_from_plucker`]. Fails for a zero direction or a
/// line through the origin (`w = 0`, where the orthonormal representation is
/// undefined).
pub fn line_landmark(line: &Vector6<f64>) -> Result<OrthonormalLine<f64>, StorageError> {
    let (w, d) = (
        line.fixed_rows::<3>(0).into_owned(),
        line.fixed_rows::<3>(3).into_owned(),
    );
    let along = d.dot(&d);
    let moment = if along > 0.0 {
        w - d * (w.dot(&d) / along)
    } else {
        w
    };
    OrthonormalLine::try_from_plucker(&PluckerLine::new(moment, d))
}

/// The documents' world-to-camera pose of g2o's body-to-world `X`: `X⁻¹`,
/// its quaternion normalised.
pub fn world_to_body(pose: &Se3<f64>) -> Se3<f64> {
    inverse_of_normalized(pose)
}

/// [`world_to_body`] over any scalar (the factors on the body pose,
/// [`super::LineObservationOnBody`] and [`super::PlaneFactorOnBody`],
/// differentiate through it).
pub(super) fn inverse_of_normalized<S: Scalar>(pose: &Se3<S>) -> Se3<S> {
    let q = pose.rotation.quaternion.normalized();
    Se3::new(So3::from_quaternion(q), pose.translation).inverse()
}

/// The information of a g2o line edge (`[q_v, angle]` order) in the
/// residual space of [`LineObservation`]: `D Ω D`, `D = diag(−½, −½, −½,
/// −1)` (see the module documentation).
pub fn line_observation_information(information: &Matrix4<f64>) -> Matrix4<f64> {
    let d = Matrix4::from_diagonal(&Vector4::new(-0.5, -0.5, -0.5, -1.0));
    d * information * d
}

/// A g2o line edge as a [`LineObservation`] at the robot pose `pose` (`X`,
/// body to world) and the landmark `line`, with the edge's information in
/// its residual space. Fails when the measurement has no orthonormal
/// representation ([`line_landmark`]).
pub fn line_observation(
    pose: &Se3<f64>,
    line: &OrthonormalLine<f64>,
    measurement: &Vector6<f64>,
    information: &Matrix4<f64>,
) -> Result<(LineObservation, Matrix4<f64>), StorageError> {
    let factor = LineObservation {
        measured: line_landmark(measurement).map_err(|e| e.within("measurement"))?,
        pose: world_to_body(pose),
        line: *line,
    };
    Ok((factor, line_observation_information(information)))
}

/// g2o's `Plane3D::oplus` of a plane `[n, d]` (unit `n`) by `v =
/// [azimuth, elevation, distance]`: the normal of azimuth `v₀` and
/// elevation `v₁` in the frame `R(n) = Rz(azimuth n) Ry(−elevation n)`,
/// and g2o's distance `−d` moved by `v₂`.
fn plane_oplus<const N: usize>(plane: &Vector4<f64>, v: &Vector3<Dual<N>>) -> Vector4<Dual<N>> {
    let n = plane.xyz();
    let (azimuth, elevation) = (n.y.atan2(n.x), n.z.atan2(n.xy().norm()));
    let frame = So3::exp(&(Vector3::z() * azimuth))
        .compose(&So3::exp(&(Vector3::y() * -elevation)))
        .matrix()
        .map(Dual::constant);
    let (a, e) = (v.x, v.y);
    let local = Vector3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin());
    let normal = frame * local;
    Vector4::new(normal.x, normal.y, normal.z, Dual::constant(plane.w) - v.z)
}

/// A g2o plane edge as a [`PlaneFactor`] at the robot pose `pose` (`X`,
/// body to world), the landmark `plane` and the sensor offset `offset`
/// (`S`, sensor to body, taken as known): the measurement moved into the
/// body frame, `π_b = S⁻ᵀ π_s`, and the edge's information in the factor's
/// residual space, `Jᵀ⁻¹ Ω J⁻¹` with `J` the Jacobian of the residual
/// w.r.t. g2o's `oplus` chart of the measured plane at these values.
/// Fails when the factor is degenerate there, or `J` singular.
pub fn plane_observation(
    pose: &Se3<f64>,
    plane: &InfinitePlane<f64>,
    offset: &Se3<f64>,
    measurement: &Vector4<f64>,
    information: &Matrix3<f64>,
) -> Result<(PlaneFactor, Matrix3<f64>), FactorError> {
    // `S⁻¹` (quaternion normalised) maps body to sensor: `Tᵀ` of it takes a
    // sensor-frame plane to the body frame.
    let body_to_sensor = world_to_body(offset);
    let measured_s = measurement / measurement.xyz().norm();
    let factor = PlaneFactor {
        measured: Unit::new_normalize(transpose_transform(&body_to_sensor, &measured_s)),
        pose: world_to_body(pose),
        plane: *plane,
    };
    factor.validate()?;
    // The residual as a function of g2o's chart of the measurement.
    type D3 = Dual<3>;
    let seeded = Vector3::from_fn(|i, _| D3::variable(0.0, i));
    let moved = plane_oplus(&measured_s, &seeded);
    let to_sensor = body_to_sensor.map_scalars(&mut D3::constant);
    let pi_b = transpose_transform(&to_sensor, &moved);
    let dual = PlaneFactor {
        measured: Unit::new_unchecked(normalized(&pi_b)),
        pose: factor.pose.map_scalars(&mut D3::constant),
        plane: factor.plane.map_scalars(&mut D3::constant),
    };
    let r = plane_residual(&dual);
    let j = Matrix3::from_fn(|i, k| r[i].eps[k]);
    let inverse = j.try_inverse().ok_or_else(|| {
        crate::degenerate(
            PlaneFactor::NAME,
            "the residual does not depend on all of g2o's chart of the measurement \
             (singular Jacobian): no information can be moved into it"
                .into(),
        )
    })?;
    Ok((factor, inverse.transpose() * information * inverse))
}
