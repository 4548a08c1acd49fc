//! Degenerate geometry gets a clear error from every entry point (residual,
//! dual and numeric linearization), never a NaN, an infinity or a panic.

use std::f64::consts::PI;

use factor_core::geometry::plane::transpose_transform;
use factor_core::geometry::{FreeLine, InfinitePlane, OrthonormalLine, PluckerLine};
use factor_core::lie::{Quaternion, Se3, Se3RhoTheta, So3};
use factor_core::{Factor, FactorError, NumericLinearize};
use factor_testing::samples::Sampler;
use nalgebra::{Matrix3, Unit, Vector3, Vector4, Vector6};
use slam_factors::{
    FreeLineFactor, G2oLineEdge, G2oPlaneEdge, LineReprojection, PlaneFactor, PointReprojection,
};

/// Asserts that all entry points fail with a degenerate-geometry error whose
/// message contains `needle`.
fn assert_degenerate<F: Factor>(factor: &F, needle: &str) {
    let results = [
        factor.residual_dyn().map(|_| ()),
        factor.linearize_dual_dyn().map(|_| ()),
        factor.linearize_numeric_dyn().map(|_| ()),
    ];
    for result in results {
        match result {
            Err(FactorError::Degenerate { factor, reason }) => {
                assert_eq!(factor, F::NAME);
                assert!(reason.contains(needle), "`{reason}` lacks `{needle}`");
            }
            other => panic!(
                "{}: expected a degenerate-geometry error, got {other:?}",
                F::NAME
            ),
        }
    }
}

fn point_at_camera_depth(z: f64) -> PointReprojection {
    let mut f = Sampler::new(10).point_reprojection();
    let p_c = Vector3::new(0.3, -0.2, z);
    f.point = f.pose.inverse().transform_point(&p_c);
    f
}

#[test]
fn point_behind_at_and_beside_the_camera() {
    assert_degenerate(&point_at_camera_depth(-2.0), "behind the camera");
    assert_degenerate(&point_at_camera_depth(0.0), "behind the camera");
    let mut at_centre = Sampler::new(11).point_reprojection();
    at_centre.point = at_centre.pose.inverse().translation; // P_c = 0
    assert_degenerate(&at_centre, "behind the camera");
    // Just in front is fine.
    assert!(point_at_camera_depth(1e-3).linearize_dual_dyn().is_ok());
}

fn line_through_camera_points(p_c: Vector3<f64>, q_c: Vector3<f64>) -> LineReprojection {
    let mut f = Sampler::new(12).line_reprojection();
    let world = f.pose.inverse();
    let line = PluckerLine::from_points(&world.transform_point(&p_c), &world.transform_point(&q_c));
    f.line = OrthonormalLine::try_from_plucker(&line).expect("not through the world origin");
    f
}

#[test]
fn line_through_the_optical_centre() {
    let p = Vector3::new(0.2, 0.1, 2.0);
    assert_degenerate(&line_through_camera_points(p, p * 3.0), "optical centre");
}

#[test]
fn line_in_the_focal_plane() {
    let f = line_through_camera_points(Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.0, 1.0, 0.0));
    assert_degenerate(&f, "focal plane");
}

#[test]
fn plucker_input_with_zero_normal_or_not_a_line() {
    let zero_n = PluckerLine::new(Vector3::zeros(), Vector3::new(0.0, 0.0, 1.0));
    let e = OrthonormalLine::try_from_plucker(&zero_n).unwrap_err();
    assert!(e.message.contains("zero norm"), "{e}");
    let not_orthogonal = PluckerLine::new(Vector3::new(1.0, 0.0, 0.0), Vector3::new(1.0, 1.0, 0.0));
    let e = OrthonormalLine::try_from_plucker(&not_orthogonal).unwrap_err();
    assert!(e.message.contains("n · v"), "{e}");
}

/// Plücker coordinates are homogeneous: any common scale of the f64 range
/// gives the same line (it gave "n · v = NaN" from 1e154 on, and "zero
/// norm" below 1e-162); only a distance `|n| / |v|` beyond the range is
/// refused.
#[test]
fn plucker_input_at_any_scale() {
    let line = PluckerLine::new(Vector3::new(0.0, -3.0, 2.0), Vector3::new(1.0, 2.0, 3.0));
    let unit = OrthonormalLine::try_from_plucker(&line).expect("a line");
    for exponent in (-300..=300).step_by(25) {
        let s = 10f64.powi(exponent);
        let scaled = PluckerLine::new(line.normal * s, line.direction * s);
        let got = OrthonormalLine::try_from_plucker(&scaled).expect("a line at any scale");
        let diff = (got.u.quaternion.coords() - unit.u.quaternion.coords())
            .amax()
            .max((got.w.cos - unit.w.cos).abs())
            .max((got.w.sin - unit.w.sin).abs());
        assert!(diff <= 1e-15, "scale 1e{exponent}: differs by {diff:e}");
    }
    let far = PluckerLine::new(line.normal * 1e300, line.direction * 1e-300);
    let e = OrthonormalLine::try_from_plucker(&far).unwrap_err();
    assert!(e.message.contains("beyond the range of f64"), "{e}");
    let skew = PluckerLine::new(
        Vector3::new(1e300, 0.0, 0.0),
        Vector3::new(1e300, 1e300, 0.0),
    );
    let e = OrthonormalLine::try_from_plucker(&skew).unwrap_err();
    assert!(
        e.message.contains("n · v ≠ 0 (cosine 0.7071067811865475)"),
        "{e}"
    );
}

#[test]
fn plane_with_zero_or_unnormalised_measured_vector() {
    let mut f = Sampler::new(13).plane();
    f.measured = Unit::new_unchecked(nalgebra::Vector4::zeros());
    assert_degenerate(&f, "measured plane vector has norm 0, expected 1");
    f.measured = Unit::new_unchecked(f.plane.coefficients() * 1e200);
    assert_degenerate(&f, "measured plane vector has norm 1e200, expected 1");
}

#[test]
fn plane_with_antipodal_error_quaternion() {
    let mut f: PlaneFactor = Sampler::new(14).plane_with_error(0.0);
    f.measured = -f.measured; // the same plane, on the other sheet
    assert_degenerate(&f, "antipodal");
}

#[test]
fn free_line_with_parallel_zero_or_unnormalised_bearings() {
    let mut f: FreeLineFactor = Sampler::new(15).free_line();
    f.bearing_end = f.bearing_start;
    assert_degenerate(&f, "parallel");
    f.bearing_end = -f.bearing_start;
    assert_degenerate(&f, "parallel");
    f.bearing_end = Unit::new_unchecked(Vector3::zeros());
    assert_degenerate(&f, "bearing vector f₂ has norm 0, expected 1");
    f.bearing_end = Unit::new_unchecked(f.bearing_start.into_inner() * 2.5);
    assert_degenerate(&f, "bearing vector f₂ has norm 2.5, expected 1");
}

#[test]
fn free_line_with_camera_centre_on_the_anchor() {
    let mut f: FreeLineFactor = Sampler::new(16).free_line();
    // The camera centre in the world, p_C = −(T_CB T_BW)⁻¹ translation part.
    let camera: Se3<f64> = f.extrinsics.compose(&f.body_pose);
    let centre = camera.inverse().translation;
    let z = centre.normalize();
    let x = z.cross(&Vector3::new(0.3, -0.5, 0.8)).normalize();
    let frame = Matrix3::from_columns(&[x, z.cross(&x), z]);
    f.line = FreeLine::new(So3::from_matrix(&frame).quaternion, centre.norm());
    assert_degenerate(&f, "anchor");
}

#[test]
fn zero_rotation_is_not_degenerate() {
    let mut f = Sampler::new(17).point_reprojection();
    let p_c = f.pose.transform_point(&f.point);
    f.pose = Se3::new(
        So3::from_quaternion(Quaternion::identity()),
        Vector3::zeros(),
    );
    f.point = p_c;
    let lin = f.linearize_dual_dyn().expect("identity pose is fine");
    assert!(
        lin.jacobians
            .iter()
            .all(|j| j.iter().all(|x| x.is_finite()))
    );
}

/// `pose` with its quaternion scaled by `s`.
fn scaled_quaternion(pose: &Se3<f64>, s: f64) -> Se3<f64> {
    let q = pose.rotation.quaternion.coords() * s;
    Se3::new(
        So3::from_quaternion(Quaternion::from_coords(q)),
        pose.translation,
    )
}

/// `pose` with a unit quaternion: the samplers' g2o poses are off unit by
/// up to 1e-6, as in g2o's files, which moves g2o's errors off their
/// degeneracies by as much.
fn unit(pose: &Se3<f64>) -> Se3<f64> {
    scaled_quaternion(pose, pose.rotation.quaternion.coords().norm().recip())
}

fn unit_rho_theta(pose: &Se3RhoTheta<f64>) -> Se3RhoTheta<f64> {
    Se3RhoTheta::new(unit(&pose.se3()))
}

#[test]
fn g2o_se3_with_a_half_turn_error_or_a_quaternion_off_unit() {
    let mut f = Sampler::new(18).g2o_se3_with_error(0.0);
    let axis = Vector3::new(0.3, -0.4, 0.5).normalize();
    let half_turn = Se3::new(So3::exp(&(axis * PI)), Vector3::zeros());
    f.measured = unit(&f.measured).compose(&half_turn);
    f.pose_i = unit_rho_theta(&f.pose_i);
    f.pose_j = unit_rho_theta(&f.pose_j);
    assert_degenerate(&f, "relative rotation error is π");
    let mut f = Sampler::new(18).g2o_se3();
    let unit_j = unit(&f.pose_j.se3());
    f.pose_j = Se3RhoTheta::new(scaled_quaternion(&unit_j, 1.001));
    assert_degenerate(&f, "the quaternion of pose_j has norm 1.001");
    // Off by the 1e-6 of a six-digit file is fine.
    f.pose_j = Se3RhoTheta::new(scaled_quaternion(&unit_j, 1.0 + 1e-6));
    assert!(f.linearize_dual_dyn().is_ok());
}

#[test]
fn g2o_line_through_the_robot_origin_or_measured_without_a_moment() {
    let mut f = Sampler::new(19).g2o_line();
    f.pose = unit_rho_theta(&f.pose);
    // The world line through X's translation.
    let pose = f.pose.se3();
    let direction = pose.rotation.rotate(&Vector3::new(0.5, -0.2, 3.0));
    let world = PluckerLine::new(pose.translation.cross(&direction), direction);
    f.line = OrthonormalLine::from_plucker(&world);
    assert_degenerate(&f, "passes through the robot's origin");
    let mut f = Sampler::new(19).g2o_line();
    f.measured.fixed_rows_mut::<3>(0).fill(0.0);
    assert_degenerate(&f, "zero moment w or w parallel to d");
}

/// The g2o line edge measuring its robot-frame line turned by `angle` about
/// `axis` (in the line's `U` frame).
fn g2o_line_turned(axis: Vector3<f64>, angle: f64) -> G2oLineEdge {
    let mut f = Sampler::new(20).g2o_line_with_error(0.0);
    f.pose = unit_rho_theta(&f.pose);
    let to_robot = f.pose.se3().inverse();
    let local = OrthonormalLine::from_plucker(&f.line.to_plucker().transform(&to_robot));
    let turn = So3::exp(&(axis.normalize() * angle));
    let m = OrthonormalLine::new(local.u.compose(&turn), local.w).to_plucker();
    f.measured = Vector6::new(
        m.normal.x,
        m.normal.y,
        m.normal.z,
        m.direction.x,
        m.direction.y,
        m.direction.z,
    );
    f
}

/// A line error of exactly 120° about an axis whose largest component is
/// negative: there Eigen's conversion switches from `w > 0` to `w < 0`.
#[test]
fn g2o_line_error_at_the_branch_switch_of_eigens_conversion() {
    let axis = Vector3::new(-0.8, 0.36, 0.48);
    let at_switch = g2o_line_turned(axis, 2.0 * PI / 3.0);
    assert_degenerate(&at_switch, "rotation of 120°");
    // With the largest component positive the error is continuous there.
    assert!(g2o_line_turned(-axis, 2.0 * PI / 3.0).residual().is_ok());
}

/// The g2o plane edge with its measured normal `R(n_L) v` for a direction
/// `v` in the predicted normal's frame.
fn g2o_plane_measuring(v: Vector3<f64>) -> G2oPlaneEdge {
    let mut f = Sampler::new(21).g2o_plane_with_error(0.0);
    f.pose = unit_rho_theta(&f.pose);
    f.offset = unit_rho_theta(&f.offset);
    let n = f.measured.xyz().normalize();
    let (azimuth, elevation) = (n.y.atan2(n.x), n.z.atan2(n.xy().norm()));
    let r = So3::exp(&(Vector3::z() * azimuth)).compose(&So3::exp(&(Vector3::y() * -elevation)));
    let m = r.rotate(&v.normalize());
    let distance = f.measured.w / f.measured.xyz().norm();
    f.measured = Vector4::new(m.x, m.y, m.z, distance);
    f
}

#[test]
fn g2o_plane_where_its_azimuths_are_undefined_or_jump() {
    assert!(
        g2o_plane_measuring(Vector3::new(1.0, 0.1, 0.2))
            .residual()
            .is_ok()
    );
    assert_degenerate(
        &g2o_plane_measuring(Vector3::z()),
        "perpendicular to the predicted one",
    );
    assert_degenerate(
        &g2o_plane_measuring(Vector3::new(-1.0, 0.0, 0.3)),
        "branch cut",
    );
    // A normal along the sensor's z axis.
    let mut f = Sampler::new(22).g2o_plane();
    f.pose = unit_rho_theta(&f.pose);
    f.offset = unit_rho_theta(&f.offset);
    let to_world = f.pose.se3().compose(&f.offset.se3());
    let pi_s = Vector4::new(0.0, 0.0, 1.0, 3.0);
    f.plane = InfinitePlane::from_coefficients(&transpose_transform(&to_world.inverse(), &pi_s));
    assert_degenerate(&f, "along the sensor's z axis");
    let mut f = Sampler::new(22).g2o_plane();
    let offset = unit(&f.offset.se3());
    f.offset = Se3RhoTheta::new(scaled_quaternion(&offset, 0.99));
    assert_degenerate(&f, "the quaternion of offset has norm 0.98999");
    f.offset = Se3RhoTheta::new(offset);
    f.measured = Vector4::new(0.0, 0.0, 0.0, 1.0);
    assert_degenerate(&f, "measured plane's normal is zero");
}

#[test]
fn line_observation_through_the_optical_centre_or_measured_the_other_way_round() {
    let mut f = Sampler::new(23).line_observation();
    let world = f.pose.inverse();
    let p = Vector3::new(0.3, -0.2, 2.0);
    f.line = OrthonormalLine::from_plucker(&PluckerLine::from_points(
        &world.transform_point(&p),
        &world.transform_point(&(p * 3.0)),
    ));
    assert_degenerate(&f, "passes through the optical centre");
    // The measured line as [−n, −v]: U turned by π about u₃.
    let mut f = Sampler::new(24).line_observation_with_error(0.0);
    let flipped = f.measured.to_plucker();
    f.measured =
        OrthonormalLine::from_plucker(&PluckerLine::new(-flipped.normal, -flipped.direction));
    assert_degenerate(&f, "half-turn");
}
