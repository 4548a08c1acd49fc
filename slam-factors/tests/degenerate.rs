//! Degenerate geometry gets a clear error from every entry point (residual,
//! dual and numeric linearization), never a NaN, an infinity or a panic.

use factor_core::geometry::{FreeLine, OrthonormalLine, PluckerLine};
use factor_core::lie::{Quaternion, Se3, So3};
use factor_core::{Factor, FactorError};
use factor_testing::samples::Sampler;
use nalgebra::{Matrix3, Vector3};
use slam_factors::{FreeLineFactor, LineReprojection, PlaneFactor, PointReprojection};

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

#[test]
fn plane_with_zero_measured_vector() {
    let mut f = Sampler::new(13).plane();
    f.measured = nalgebra::Vector4::zeros();
    assert_degenerate(&f, "zero norm");
}

#[test]
fn plane_with_antipodal_error_quaternion() {
    let mut f: PlaneFactor = Sampler::new(14).plane_with_error(0.0);
    f.measured = -f.measured; // the same plane, on the other sheet
    assert_degenerate(&f, "antipodal");
}

#[test]
fn free_line_with_parallel_or_zero_bearings() {
    let mut f: FreeLineFactor = Sampler::new(15).free_line();
    f.bearing_end = f.bearing_start * 2.5;
    assert_degenerate(&f, "parallel");
    f.bearing_end = -f.bearing_start;
    assert_degenerate(&f, "parallel");
    f.bearing_end = Vector3::zeros();
    assert_degenerate(&f, "parallel or zero");
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
