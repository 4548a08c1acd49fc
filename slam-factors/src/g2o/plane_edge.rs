//! g2o's `EDGE_SE3_PLANE_CALIB` error.

use nalgebra::{Vector3, Vector4};

use crate::DEGENERACY_TOLERANCE;
use crate::degenerate;
use crate::g2o::check_pose_quaternions;
use crate::g2o::eigen::{Isometry, normalized, polar_quaternion};
use crate::plane::PLANE_DISTANCE_LIMIT;
use factor_core::geometry::InfinitePlane;
use factor_core::lie::Se3RhoTheta;
use factor_core::linalg::{dot, norm, scale};
use factor_core::validation::{exceeds, magnitude_text, within};
use factor_core::{Factor, FactorError, Scalar};

/// g2o's `EdgeSE3PlaneSensorCalib` error: the landmark plane mapped into the
/// sensor frame through `(X · S)⁻¹` (robot pose `X`, sensor offset `S`),
/// then g2o's `Plane3D::ominus` of the measurement: with both planes `[n,
/// d]` scaled to unit normals (`n · x + d = 0`), the measured normal rotated
/// by `R(n_L)ᵀ`, where `R(n) = Rz(azimuth n) Ry(−elevation n)` brings
/// `(1, 0, 0)` to `n`, gives `e = [azimuth, elevation, d_m − d_L]`
/// (`azimuth = atan2(y, x)`, `elevation = atan2(z, |(x, y)|)`; g2o's
/// distance is `−d`). Unwhitened: the edge's cost is `eᵀ Ω e`.
///
/// g2o maps the plane with `Isometry3::rotation()`, which Eigen 3.3
/// computes as the polar factor of the linear part (an SVD): reproduced by
/// [`crate::g2o::eigen::polar_quaternion`]. The translation and the linear
/// parts are Eigen's of the quaternions as stored ([`crate::g2o`]).
///
/// - `pose` `X` (body to world) and `offset` `S` (sensor to body): **right**
///   perturbation, tangent `[δρ, δθ]` ([`Se3RhoTheta`]).
/// - `plane`: the world plane as a unit quaternion ([`InfinitePlane`]),
///   **right** perturbation `q ← q ⊗ exp(δω)`; g2o's unit-normal form is
///   `q / |q_xyz|`.
///
/// Degenerate: a predicted normal along the sensor's z axis (`|(x, y)|`
/// below 1e-9), where the azimuth of `R(n_L)` is undefined; a rotated
/// measured normal perpendicular to the predicted one or on the azimuth's
/// branch cut (`x < 0`, `|y|` below 1e-9), where the error is not
/// differentiable or jumps; a landmark beyond [`PLANE_DISTANCE_LIMIT`] from
/// the world origin in units of its normal; a pose quaternion whose norm is
/// off by more than [`crate::g2o::QUATERNION_TOLERANCE`].
#[derive(Debug, Clone, Factor)]
#[factor(
    residual = g2o_plane_residual,
    dim = 3,
    validate = validate_g2o_plane,
    name = "g2o_se3_plane_calib"
)]
pub struct G2oPlaneEdge<S: Scalar = f64> {
    /// The measured plane `[n, d]` in the sensor frame, as written (any
    /// non-zero normal).
    pub measured: Vector4<S>,
    /// Body-to-world robot pose `X`.
    #[variable(right)]
    pub pose: Se3RhoTheta<S>,
    /// The world plane.
    #[variable(right)]
    pub plane: InfinitePlane<S>,
    /// Sensor-to-body offset `S`.
    #[variable(right)]
    pub offset: Se3RhoTheta<S>,
}

/// `[n, d] · (1 / |n|)`, g2o's `Plane3D` normalisation.
fn unit_normal<S: Scalar>(plane: &Vector4<S>) -> Vector4<S> {
    scale(norm(&plane.xyz()).recip(), plane)
}

/// The predicted plane in the sensor frame, unit normal.
fn sensor_plane<S: Scalar>(f: &G2oPlaneEdge<S>) -> Vector4<S> {
    let (pose, offset) = (f.pose.se3(), f.offset.se3());
    let to_sensor = Isometry::from_pose(&pose)
        .compose(&Isometry::from_pose(&offset))
        .inverse();
    // The polar factor of `(L_X L_S)ᵀ`: `(P_X P_S)ᵀ`.
    let polar = polar_quaternion(&pose.rotation.quaternion)
        .mul(&polar_quaternion(&offset.rotation.quaternion));
    let world = unit_normal(&f.plane.coefficients());
    let n = normalized(&polar).conjugate().rotate(&world.xyz());
    let d = world.w - dot(&to_sensor.translation, &n);
    unit_normal(&Vector4::new(n.x, n.y, n.z, d))
}

/// The measured normal seen from the predicted one, `R(n_L)ᵀ n_m`, and the
/// distance difference `d_m − d_L`.
fn measured_in_predicted<S: Scalar>(f: &G2oPlaneEdge<S>) -> (Vector3<S>, S) {
    let predicted = sensor_plane(f);
    let measured = unit_normal(&f.measured);
    let (x, y, z) = (predicted.x, predicted.y, predicted.z);
    // cos and sin of the azimuth and elevation of n_L, as ratios.
    let horizontal = (x * x + y * y).sqrt();
    let (ca, sa) = (x / horizontal, y / horizontal);
    let length = (horizontal * horizontal + z * z).sqrt();
    let (ce, se) = (horizontal / length, z / length);
    let m = measured.xyz();
    let rotated = Vector3::new(
        ca * ce * m.x + sa * ce * m.y + se * m.z,
        ca * m.y - sa * m.x,
        ce * m.z - ca * se * m.x - sa * se * m.y,
    );
    (rotated, measured.w - predicted.w)
}

/// `[azimuth, elevation, d_m − d_L]` of the measured plane seen from the
/// predicted one.
pub fn g2o_plane_residual<S: Scalar>(f: &G2oPlaneEdge<S>) -> Vector3<S> {
    let (n, distance) = measured_in_predicted(f);
    let horizontal = (n.x * n.x + n.y * n.y).sqrt();
    Vector3::new(n.y.atan2(n.x), n.z.atan2(horizontal), distance)
}

/// Rejects pose quaternions off unit norm, a landmark too far from the
/// origin, and the configurations where the azimuths are undefined or jump.
pub fn validate_g2o_plane(f: &G2oPlaneEdge<f64>) -> Result<(), FactorError> {
    let name = G2oPlaneEdge::NAME;
    check_pose_quaternions(
        name,
        &[("pose", &f.pose.se3()), ("offset", &f.offset.se3())],
    )?;
    if f.measured.xyz().norm() == 0.0 {
        return Err(degenerate(
            name,
            "the measured plane's normal is zero".into(),
        ));
    }
    let q = f.plane.quaternion.coords();
    let kappa = q.w.abs() / q.xyz().norm();
    if !within(kappa, PLANE_DISTANCE_LIMIT) {
        return Err(degenerate(
            name,
            format!(
                "the landmark plane is {} from the world origin in units of its normal, beyond \
                 1e9",
                magnitude_text(kappa)
            ),
        ));
    }
    let predicted = sensor_plane(f);
    if !exceeds(predicted.xy().norm(), DEGENERACY_TOLERANCE) {
        return Err(degenerate(
            name,
            "the predicted normal is along the sensor's z axis, where g2o's azimuth of it is \
             undefined"
                .into(),
        ));
    }
    let (n, _) = measured_in_predicted(f);
    if !exceeds(n.xy().norm(), DEGENERACY_TOLERANCE) {
        return Err(degenerate(
            name,
            "the measured normal is perpendicular to the predicted one, where the elevation \
             error is not differentiable"
                .into(),
        ));
    }
    if n.x < 0.0 && !exceeds(n.y.abs(), DEGENERACY_TOLERANCE) {
        return Err(degenerate(
            name,
            "the measured normal is on the azimuth's branch cut (more than 90° from the \
             predicted one, in its x-z plane), where the error jumps by 2π"
                .into(),
        ));
    }
    Ok(())
}
