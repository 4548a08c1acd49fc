//! The generated kernels of `user-kernels`: `linearize()` goes through them,
//! and they agree with dual numbers to rounding (and with central
//! differences) at 200 random configurations per factor.
//! (`user-cli check`, a test of `user-cli`, checks that they are current.)
#![cfg(feature = "kernels")]

use factor_core::Factor;
use factor_core::lie::Se3;
use factor_testing::samples::Sampler;
use factor_testing::{
    DEFAULT_TOLERANCE, GENERATED_TOLERANCE, assert_correct_jacobians, assert_generated_matches_dual,
};
use nalgebra::Vector3;
use user_factors::{PointToPlane, RelativePose, ScaledRangeBearing};

const CONFIGURATIONS: usize = 200;

/// A relative-pose factor between two random poses whose measurement is
/// their true relative pose, perturbed by up to 0.3 rad and 0.2 m, or exact
/// (zero residual, through the small-angle branches of `Log`) every tenth
/// time.
pub(crate) fn relative_pose(sampler: &mut Sampler, i: usize) -> RelativePose {
    let pose_i = sampler.pose();
    let pose_j = sampler.pose();
    let truth = pose_i.inverse().compose(&pose_j);
    let measured = if i.is_multiple_of(10) {
        truth
    } else {
        let noise = Se3::new(sampler.small_rotation(0.3), sampler.vector3(0.2));
        truth.compose(&noise)
    };
    RelativePose {
        measured,
        pose_i,
        pose_j,
    }
}

/// A point-to-plane factor: a random scan pose, a scan point within 5 m,
/// and a map plane through its true position, offset along the normal by up
/// to 0.1 m and slid along the plane by up to 1 m.
pub(crate) fn point_to_plane(sampler: &mut Sampler, _: usize) -> PointToPlane {
    let pose = sampler.pose();
    let point = sampler.vector3(5.0);
    let normal = loop {
        let n = sampler.vector3(1.0);
        if (0.1..1.0).contains(&n.norm()) {
            break n.normalize();
        }
    };
    let along = sampler.vector3(1.0);
    let along: Vector3<f64> = along - normal * normal.dot(&along);
    let plane_point = pose.transform_point(&point) + normal * sampler.uniform(-0.1, 0.1) + along;
    PointToPlane {
        point,
        plane_point,
        normal,
        pose,
    }
}

/// A range-bearing factor: a random sensor pose, a landmark in front of it
/// (`x ∈ [0.5, 10]`, `|y|, |z| ≤ 5` in the sensor frame), a log scale in
/// `[−1, 1]`, and the true measurement perturbed by up to 0.05 (exact every
/// tenth time).
pub(crate) fn scaled_range_bearing(sampler: &mut Sampler, i: usize) -> ScaledRangeBearing {
    let pose = sampler.pose();
    let in_sensor = Vector3::new(
        sampler.uniform(0.5, 10.0),
        sampler.uniform(-5.0, 5.0),
        sampler.uniform(-5.0, 5.0),
    );
    let landmark = pose.inverse().transform_point(&in_sensor);
    let log_scale = sampler.uniform(-1.0, 1.0);
    let range = in_sensor.norm();
    let truth = Vector3::new(
        (in_sensor.y / in_sensor.x).atan(),
        (in_sensor.z / range).asin(),
        log_scale + range.ln(),
    );
    let noise = if i.is_multiple_of(10) {
        Vector3::zeros()
    } else {
        sampler.vector3(0.05)
    };
    ScaledRangeBearing {
        landmark,
        measured: truth + noise,
        pose,
        log_scale,
    }
}

/// At every sample, the generated kernel against dual numbers (to rounding)
/// and the dual Jacobians against numerical differentiation: one line each.
fn check_agreement<F: Factor>(seed: u64, mut sample: impl FnMut(&mut Sampler, usize) -> F) {
    let mut sampler = Sampler::new(seed);
    for i in 0..CONFIGURATIONS {
        let factor = sample(&mut sampler, i);
        assert_generated_matches_dual(&factor, GENERATED_TOLERANCE);
        assert_correct_jacobians(&factor, DEFAULT_TOLERANCE);
    }
}

#[test]
fn relative_pose_generated_matches_dual_and_numeric() {
    check_agreement(1, relative_pose);
}

#[test]
fn point_to_plane_generated_matches_dual_and_numeric() {
    check_agreement(2, point_to_plane);
}

#[test]
fn scaled_range_bearing_generated_matches_dual_and_numeric() {
    check_agreement(5, scaled_range_bearing);
}

/// The dual-number Jacobians themselves are right (the reference above).
#[test]
fn dual_jacobians_are_correct() {
    let mut sampler = Sampler::new(3);
    for i in 0..10 {
        assert_correct_jacobians(&relative_pose(&mut sampler, i), DEFAULT_TOLERANCE);
        assert_correct_jacobians(&point_to_plane(&mut sampler, i), DEFAULT_TOLERANCE);
        assert_correct_jacobians(&scaled_range_bearing(&mut sampler, i), DEFAULT_TOLERANCE);
    }
}

/// `linearize()` is the generated kernel: `KERNEL` names it and the result is
/// `linearize_generated()`'s, bit for bit.
#[test]
fn linearize_goes_through_the_generated_kernel() {
    assert_eq!(
        <RelativePose as Factor>::KERNEL,
        Some("user_kernels::relative_pose::relative_pose")
    );
    assert_eq!(
        <PointToPlane as Factor>::KERNEL,
        Some("user_kernels::point_to_plane::point_to_plane")
    );
    let mut sampler = Sampler::new(4);
    let f = relative_pose(&mut sampler, 1);
    assert_eq!(f.linearize(), f.linearize_generated());
    let g = point_to_plane(&mut sampler, 1);
    assert_eq!(g.linearize(), g.linearize_generated());
    assert_eq!(
        <ScaledRangeBearing as Factor>::KERNEL,
        Some("user_kernels::scaled_range_bearing::scaled_range_bearing")
    );
    let h = scaled_range_bearing(&mut sampler, 1);
    assert_eq!(h.linearize(), h.linearize_generated());
}
