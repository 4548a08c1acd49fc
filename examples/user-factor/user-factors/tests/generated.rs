//! The generated kernels of `user-kernels`: `linearize()` goes through them,
//! and they agree with dual numbers to rounding (and with central
//! differences) at 200 random configurations per factor.
//! (`tests/generate_kernels.rs` checks that they are current.)
#![cfg(feature = "kernels")]

use factor_core::factor::relative_frobenius_error;
use factor_core::lie::Se3;
use factor_core::{DynLinearization, Factor, MapScalars};
use factor_testing::samples::Sampler;
use factor_testing::{DEFAULT_TOLERANCE, assert_correct_jacobians};
use nalgebra::Vector3;
use user_factors::{PointToPlane, RelativePose, ScaledRangeBearing};

const CONFIGURATIONS: usize = 200;
/// Generated vs dual numbers: both exact, so only rounding differs.
const VS_DUAL: f64 = 1e-12;
/// Generated vs central differences.
const VS_NUMERIC: f64 = 1e-6;

/// A relative-pose factor between two random poses whose measurement is
/// their true relative pose, perturbed by up to 0.3 rad and 0.2 m, or exact
/// (zero residual, through the small-angle branches of `Log`) every tenth
/// time.
fn relative_pose(sampler: &mut Sampler, i: usize) -> RelativePose {
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
fn point_to_plane(sampler: &mut Sampler, _: usize) -> PointToPlane {
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
fn scaled_range_bearing(sampler: &mut Sampler, i: usize) -> ScaledRangeBearing {
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

/// The largest magnitude among the factor's input scalars, or 1: a residual
/// that is a difference of terms of that size is compared relative to it.
fn input_scale<F: MapScalars<f64>>(factor: &F) -> f64 {
    let mut scale: f64 = 1.0;
    let _ = factor.map_scalars(&mut |x: f64| {
        scale = scale.max(x.abs());
        x
    });
    scale
}

/// Relative errors of `a` w.r.t. `b`: the residual (relative to its norm or
/// the input scale), then each Jacobian block (relative Frobenius, floored
/// at `1e-9`).
fn errors(a: &DynLinearization, b: &DynLinearization, residual_scale: f64) -> Vec<f64> {
    let residual = (&a.residual - &b.residual).norm() / b.residual.norm().max(residual_scale);
    let blocks = a
        .jacobians
        .iter()
        .zip(&b.jacobians)
        .map(|(x, y)| relative_frobenius_error(x, y, 1e-9));
    std::iter::once(residual).chain(blocks).collect()
}

/// Generated vs dual (≤ 1e-12) and vs numeric (≤ 1e-6) at every sample;
/// returns the worst error vs dual.
fn check_agreement<F: Factor + MapScalars<f64>>(
    seed: u64,
    mut sample: impl FnMut(&mut Sampler, usize) -> F,
) -> f64 {
    let mut sampler = Sampler::new(seed);
    let mut worst: f64 = 0.0;
    for i in 0..CONFIGURATIONS {
        let factor = sample(&mut sampler, i);
        let generated = factor
            .linearize_generated_dyn()
            .unwrap_or_else(|| panic!("{} has a generated kernel", F::NAME))
            .unwrap_or_else(|e| panic!("{} configuration {i}: {e}", F::NAME));
        let dual = factor.linearize_dual_dyn().expect("valid");
        let numeric = factor.linearize_numeric_dyn().expect("valid");
        let scale = input_scale(&factor);
        for (k, e) in errors(&generated, &dual, scale).into_iter().enumerate() {
            assert!(
                e <= VS_DUAL,
                "{} configuration {i}, output {k}: generated vs dual {e:e}",
                F::NAME
            );
            worst = worst.max(e);
        }
        for (k, e) in errors(&generated, &numeric, scale).into_iter().enumerate() {
            assert!(
                e <= VS_NUMERIC,
                "{} configuration {i}, output {k}: generated vs numeric {e:e}",
                F::NAME
            );
        }
    }
    println!("{}: worst relative error vs dual {worst:e}", F::NAME);
    worst
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
