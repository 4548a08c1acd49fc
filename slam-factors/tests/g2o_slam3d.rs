//! g2o's `EDGE_SE3_PRIOR` and `EDGE_SE3_TRACKXYZ` errors
//! ([`G2oPriorEdge`], [`G2oPointEdge`]) against their definitions in g2o's
//! `edge_se3_prior.cpp`, `edge_se3_pointxyz.cpp` and `parameter_se3_offset.cpp`
//! written again here with nalgebra's own isometries, at random poses with
//! unit quaternions (where g2o's unnormalised matrices are rotations):
//!
//! - prior: `Δ = Z⁻¹ · (X · P)`, error `toVectorMQT(Δ) = [t, q_v]` with `q`
//!   the unit quaternion of `Δ`'s rotation taken with `w ≥ 0`; the factor
//!   orders it `[q_v, t]`;
//! - point: `(X · P)⁻¹ · p − m`.
//!
//! Their costs on the graphs g2o's simulators wrote, against g2o's own χ²,
//! are checked in `tests/g2o_graphs.rs`.

use factor_core::Factor;
use factor_core::lie::{Se3, Se3RhoTheta};
use factor_testing::samples::Sampler;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3, Vector6};
use slam_factors::{G2oPointEdge, G2oPriorEdge};

const CONFIGURATIONS: usize = 200;
const TOLERANCE: f64 = 1e-12;

fn isometry(pose: &Se3<f64>) -> Isometry3<f64> {
    let q = pose.rotation.quaternion;
    let unit = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q.w, q.x, q.y, q.z));
    Isometry3::from_parts(Translation3::from(pose.translation), unit)
}

/// g2o's prior error `[t, q_v]`, from g2o's formula.
fn prior_error(z: &Isometry3<f64>, x: &Isometry3<f64>, p: &Isometry3<f64>) -> Vector6<f64> {
    let delta = z.inverse() * x * p;
    let mut q = delta.rotation.into_inner();
    if q.w < 0.0 {
        q = -q;
    }
    let t = delta.translation.vector;
    Vector6::new(t.x, t.y, t.z, q.i, q.j, q.k)
}

#[test]
fn the_prior_error_is_g2os() {
    let mut sampler = Sampler::new(31);
    let mut worst = 0.0_f64;
    for i in 0..CONFIGURATIONS {
        let (z, x, p) = (sampler.pose(), sampler.pose(), sampler.pose());
        let factor = G2oPriorEdge {
            measured: z,
            offset: p,
            pose: Se3RhoTheta::new(x),
        };
        let ours = factor.residual().unwrap();
        let g2o = prior_error(&isometry(&z), &isometry(&x), &isometry(&p));
        // g2o's [t, q_v] is the factor's [q_v, t].
        let swapped = Vector6::new(ours[3], ours[4], ours[5], ours[0], ours[1], ours[2]);
        let error = (swapped - g2o).amax();
        assert!(error <= TOLERANCE, "configuration {i}: {swapped} vs {g2o}");
        worst = worst.max(error);
    }
    println!("g2o_se3_prior: worst difference {worst:e}");
}

#[test]
fn the_prior_vanishes_at_its_measurement_and_measures_the_sensor_not_the_robot() {
    let mut sampler = Sampler::new(32);
    for _ in 0..CONFIGURATIONS {
        let (x, p) = (sampler.pose(), sampler.pose());
        let at = |measured: Se3<f64>| {
            G2oPriorEdge {
                measured,
                offset: p,
                pose: Se3RhoTheta::new(x),
            }
            .residual()
            .unwrap()
        };
        assert!(at(x.compose(&p)).amax() <= TOLERANCE);
        // Measured the robot's pose instead, the error is the offset's own
        // `[q_v, t]` (w ≥ 0): unless the offset is the identity, not zero.
        let off = at(x);
        let q = p.rotation.quaternion;
        let sign = if q.w < 0.0 { -1.0 } else { 1.0 };
        let expected = Vector6::new(
            sign * q.x,
            sign * q.y,
            sign * q.z,
            p.translation.x,
            p.translation.y,
            p.translation.z,
        );
        assert!((off - expected).amax() <= TOLERANCE, "{off} vs {expected}");
    }
}

#[test]
fn the_point_error_is_g2os() {
    let mut sampler = Sampler::new(33);
    let mut worst = 0.0_f64;
    for i in 0..CONFIGURATIONS {
        let (x, p) = (sampler.pose(), sampler.pose());
        let point = sampler.vector3(20.0);
        let measured = sampler.vector3(5.0);
        let factor = G2oPointEdge {
            measured,
            offset: p,
            pose: Se3RhoTheta::new(x),
            point,
        };
        let ours = factor.residual().unwrap();
        let sensor = isometry(&x) * isometry(&p);
        let g2o: Vector3<f64> = sensor.inverse_transform_point(&point.into()).coords - measured;
        let error = (ours - g2o).amax();
        assert!(error <= TOLERANCE, "configuration {i}: {ours} vs {g2o}");
        worst = worst.max(error);
    }
    println!("g2o_se3_trackxyz: worst difference {worst:e}");
}

#[test]
fn a_quaternion_off_unit_is_refused_by_both() {
    let mut sampler = Sampler::new(34);
    let mut prior = sampler.g2o_prior();
    let q = prior.offset.rotation.quaternion.coords() * 1.01;
    prior.offset.rotation =
        factor_core::lie::So3::from_quaternion(factor_core::lie::Quaternion::from_coords(q));
    let message = prior.residual_dyn().unwrap_err().to_string();
    assert!(
        message.contains("the quaternion of offset has norm"),
        "{message}"
    );
    let mut point = sampler.g2o_point();
    point.offset = prior.offset;
    let message = point.residual_dyn().unwrap_err().to_string();
    assert!(
        message.contains("the quaternion of offset has norm"),
        "{message}"
    );
}
