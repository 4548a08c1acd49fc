//! The factors of `slamjac solve` (Snavely reprojection, stereo
//! reprojection, between): dual numbers against central differences and the
//! generated kernels against dual numbers at 200 sampled configurations
//! each, their residuals against independent evaluations of the models, and
//! their degenerate configurations.

use factor_core::lie::{Se3, Se3RhoTheta, So3};
use factor_core::{Factor, FactorError, NumericLinearize};
use factor_testing::samples::Sampler;
use factor_testing::{DEFAULT_TOLERANCE, assert_correct_jacobians};
use nalgebra::{Matrix6, Rotation3, Vector2, Vector3, Vector6};
use slam_factors::snavely::radial_map_derivative_minimum;
use slam_factors::{RadialIntrinsics, SnavelyReprojection, SqrtInformation6};

const CONFIGURATIONS: usize = 200;

/// Dual vs central differences (and, with the kernels, generated vs dual)
/// at `CONFIGURATIONS` samples.
fn check_all<F: Factor>(seed: u64, mut sample: impl FnMut(&mut Sampler) -> F) {
    let mut sampler = Sampler::new(seed);
    for _ in 0..CONFIGURATIONS {
        let factor = sample(&mut sampler);
        assert_correct_jacobians(&factor, DEFAULT_TOLERANCE);
        #[cfg(feature = "kernels")]
        factor_testing::assert_generated_matches_dual(&factor, factor_testing::GENERATED_TOLERANCE);
    }
}

#[test]
fn snavely_reprojection_jacobians() {
    check_all(31, Sampler::snavely_reprojection);
}

#[test]
fn stereo_reprojection_jacobians() {
    check_all(32, Sampler::stereo_reprojection);
}

#[test]
fn between_jacobians() {
    check_all(33, Sampler::between);
}

/// Errors below the small-angle threshold of the logarithm, and exactly
/// zero (an odometry edge at its chained initial value): the series
/// branches a converging solver ends in.
#[test]
fn between_jacobians_near_and_at_zero_error() {
    check_all(34, |s| s.between_with_error(1e-4));
    check_all(35, |s| s.between_with_error(0.0));
}

/// The Snavely residual against the model written out independently with
/// nalgebra's rotation (the camera looking down −z).
#[test]
fn snavely_residual_is_the_bal_model() {
    let mut sampler = Sampler::new(36);
    for _ in 0..50 {
        let f = sampler.snavely_reprojection();
        let r = Rotation3::from_matrix_unchecked(f.pose.se3().rotation.matrix());
        let p_c = r * f.point + f.pose.translation();
        let p = -p_c.xy() / p_c.z;
        let RadialIntrinsics { focal, k1, k2 } = f.intrinsics;
        let r2 = p.norm_squared();
        let expected = focal * (1.0 + k1 * r2 + k2 * r2 * r2) * p - f.observed;
        let residual = f.residual().expect("valid");
        assert!((residual - expected).norm() <= 1e-9 * expected.norm().max(1.0));
    }
}

/// The stereo residual against `[u_L, u_R, v]` written out independently.
#[test]
fn stereo_residual_is_the_rectified_stereo_model() {
    let mut sampler = Sampler::new(37);
    for _ in 0..50 {
        let f = sampler.stereo_reprojection();
        let r = f.pose.se3().rotation.matrix();
        let p = r.transpose() * (f.landmark - f.pose.translation());
        let c = f.calibration;
        let u_left = c.fx * p.x / p.z + c.skew * p.y / p.z + c.u0;
        let expected = Vector3::new(
            u_left,
            u_left - c.fx * c.baseline / p.z,
            c.fy * p.y / p.z + c.v0,
        ) - f.observed;
        let residual = f.residual().expect("valid");
        assert!((residual - expected).norm() <= 1e-9 * expected.norm().max(1.0));
    }
}

/// `½ ‖r‖²` is `½ eᵀ Ω e` with `e` the logarithm of the error pose, and `U`
/// is a square root of `Ω`.
#[test]
fn between_residual_is_whitened_by_the_information() {
    let mut sampler = Sampler::new(38);
    for _ in 0..50 {
        let f = sampler.between();
        let u = f.sqrt_information.matrix();
        let information = u.transpose() * u;
        let error = f
            .measured
            .inverse()
            .compose(&f.pose_i.se3().inverse().compose(&f.pose_j.se3()))
            .log();
        let residual = f.residual().expect("valid");
        let expected = (error.transpose() * information * error)[(0, 0)];
        assert!((residual.norm_squared() - expected).abs() <= 1e-9 * expected.max(1.0));
        let roundtrip = SqrtInformation6::from_information(&information).expect("SPD");
        assert!((roundtrip.matrix() - u).norm() <= 1e-9 * u.norm());
    }
    let not_definite = Matrix6::from_diagonal(&Vector6::new(1.0, 1.0, 1.0, 1.0, 1.0, -1.0));
    assert!(SqrtInformation6::from_information(&not_definite).is_none());
}

/// Asserts that every entry point fails with a degenerate-geometry error
/// whose message contains `needle`.
fn assert_degenerate<F: Factor>(factor: &F, needle: &str) {
    let mut residual = vec![0.0; F::RESIDUAL_DIM];
    let mut blocks: Vec<Vec<f64>> = F::variables()
        .iter()
        .map(|v| vec![0.0; F::RESIDUAL_DIM * v.tangent_dim])
        .collect();
    let mut jacobians: Vec<Option<&mut [f64]>> =
        blocks.iter_mut().map(|b| Some(&mut b[..])).collect();
    let into = factor.linearize_into(&mut residual, &mut jacobians);
    let results = [
        factor.residual_dyn().map(|_| ()),
        factor.linearize_dual_dyn().map(|_| ()),
        factor.linearize_numeric_dyn().map(|_| ()),
        into,
    ];
    for result in results {
        match result {
            Err(FactorError::Degenerate { factor, reason }) => {
                assert_eq!(factor, F::NAME);
                assert!(reason.contains(needle), "`{reason}` lacks `{needle}`");
            }
            other => panic!("{}: expected a degenerate error, got {other:?}", F::NAME),
        }
    }
}

/// A Snavely factor whose point is at `p_c` in the camera frame.
fn snavely_with_camera_point(p_c: Vector3<f64>) -> SnavelyReprojection {
    let mut f = Sampler::new(40).snavely_reprojection();
    f.point = f.pose.se3().inverse().transform_point(&p_c);
    f
}

#[test]
fn snavely_point_at_or_behind_the_camera() {
    // The camera looks down −z: +z is behind it.
    assert_degenerate(
        &snavely_with_camera_point(Vector3::new(0.1, 0.2, 2.0)),
        "behind the camera",
    );
    assert_degenerate(
        &snavely_with_camera_point(Vector3::new(0.1, 0.2, 0.0)),
        "behind the camera",
    );
    assert_degenerate(
        &snavely_with_camera_point(Vector3::zeros()),
        "behind the camera",
    );
    assert!(
        snavely_with_camera_point(Vector3::new(1e-4, 2e-4, -1e-3))
            .linearize_dual_dyn()
            .is_ok()
    );
}

#[test]
fn snavely_distortion_that_folds_the_image() {
    // p = (0.5, 0): the radial map's derivative 1 + 3 k1 ρ² + 5 k2 ρ⁴ at
    // ρ = 0.5 is 1 + 0.75 k1 (k2 = 0), zero at k1 = −4/3.
    let mut f = snavely_with_camera_point(Vector3::new(0.5, 0.0, -1.0));
    f.intrinsics.k2 = 0.0;
    f.intrinsics.k1 = -1.4;
    assert_degenerate(&f, "distortion folds the image");
    f.intrinsics.k1 = -1.3;
    assert!(f.linearize_dual_dyn().is_ok());
    // A positive k2 with a negative k1: in s = ρ² the derivative
    // 1 − 9 s + 20.1 s² dips below zero at its vertex s ≈ 0.224 (inside the
    // radius, s = 0.25) and is positive again at the radius, so only the
    // interior minimum catches it.
    f.intrinsics.k1 = -3.0;
    f.intrinsics.k2 = 4.02;
    let (minimum, at) = radial_map_derivative_minimum(-3.0, 4.02, 0.25);
    assert!(
        minimum < 0.0 && at > 0.0 && at < 0.25,
        "{minimum} at ρ² = {at}"
    );
    let end = |k1: f64, k2: f64, s: f64| 1.0 + 3.0 * k1 * s + 5.0 * k2 * s * s;
    assert!(end(-3.0, 4.02, 0.25) > 0.0, "positive again at the radius");
    assert_degenerate(&f, "distortion folds the image");
}

#[test]
fn snavely_focal_length_not_positive() {
    let mut f = Sampler::new(41).snavely_reprojection();
    f.intrinsics.focal = 0.0;
    assert_degenerate(&f, "focal length");
    f.intrinsics.focal = -500.0;
    assert_degenerate(&f, "focal length");
}

#[test]
fn stereo_landmark_at_or_behind_the_camera() {
    for z in [-3.0, 0.0] {
        let mut f = Sampler::new(42).stereo_reprojection();
        f.landmark = f.pose.transform_point(&Vector3::new(0.5, -0.2, z));
        assert_degenerate(&f, "behind the camera");
    }
}

#[test]
fn between_rotation_error_of_pi() {
    let mut f = Sampler::new(43).between();
    let half_turn = Se3::new(
        So3::exp(&Vector3::new(0.0, std::f64::consts::PI, 0.0)),
        Vector3::zeros(),
    );
    f.pose_j = Se3RhoTheta::new(f.pose_i.se3().compose(&f.measured).compose(&half_turn));
    assert_degenerate(&f, "rotation error is π");
}

/// Nothing in the Snavely model depends on the point being named `X`: the
/// pixel of a camera at the identity is `f r (−x/z, −y/z)`.
#[test]
fn snavely_at_the_identity_camera() {
    let f = SnavelyReprojection {
        observed: Vector2::zeros(),
        pose: Se3RhoTheta::new(Se3::identity()),
        intrinsics: RadialIntrinsics::new(500.0, 0.1, 0.01),
        point: Vector3::new(0.2, -0.4, -2.0),
    };
    let p = Vector2::<f64>::new(0.1, -0.2);
    let r2 = p.norm_squared();
    let expected = 500.0 * (1.0 + 0.1 * r2 + 0.01 * r2 * r2) * p;
    let residual: Vector2<f64> = f.residual().expect("valid");
    assert!((residual - expected).norm() < 1e-12);
}
