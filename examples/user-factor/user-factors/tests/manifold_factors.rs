//! The factors over this crate's own manifolds, [`Direction`] (S²) and
//! [`RelativeSim3`] (Sim(3)): dual-number Jacobians against central
//! differences through the exact retractions, and the generated kernels
//! against dual numbers, at 200 sampled configurations each, with extra
//! weight on the S² basis branch boundary (`z` of the direction or of the
//! measurement at `±0`, `±1e-12`, ...) and on Sim(3) errors near zero
//! rotation and scale and at the switches of `W`'s series.

use factor_core::lie::{SMALL_ANGLE_SQUARED, So3};
use factor_testing::samples::Sampler;
use factor_testing::{DEFAULT_TOLERANCE, assert_correct_jacobians};
use nalgebra::{Matrix2, Vector3};
use user_factors::sim3::Sim3;
use user_factors::sim3::w_matrix::SERIES_RADIUS_SQUARED;
use user_factors::unit_vector::UnitVector3;
use user_factors::{Direction, RelativeSim3};

const CONFIGURATIONS: usize = 200;

/// `z` coordinates on and next to the S² basis branch boundary `z = 0`.
const NEAR_EQUATOR: [f64; 8] = [0.0, -0.0, 1e-300, -1e-300, 1e-12, -1e-12, 1e-4, -1e-4];

/// A direction uniform on the sphere (a uniform point of the unit ball's
/// shell, by rejection).
fn uniform_direction(sampler: &mut Sampler) -> Vector3<f64> {
    loop {
        let v = sampler.vector3(1.0);
        if (0.1..1.0).contains(&v.norm()) {
            return v.normalize();
        }
    }
}

/// A direction of height `z` at a random azimuth.
fn direction_at_height(sampler: &mut Sampler, z: f64) -> Vector3<f64> {
    let azimuth = sampler.uniform(-std::f64::consts::PI, std::f64::consts::PI);
    let r = (1.0 - z * z).sqrt();
    Vector3::new(r * azimuth.cos(), r * azimuth.sin(), z)
}

/// A direction factor at a random orientation. By `i % 3`: a uniform world
/// direction; a world direction on or next to the equator of its basis; or
/// a measurement there. The measurement is the prediction rotated by up to
/// 0.2 rad, exactly the prediction every tenth time.
pub(crate) fn direction(sampler: &mut Sampler, i: usize) -> Direction {
    let orientation = sampler.rotation();
    let noise = if i.is_multiple_of(10) {
        So3::identity()
    } else {
        sampler.small_rotation(0.2)
    };
    let z = NEAR_EQUATOR[(i / 3) % NEAR_EQUATOR.len()];
    let (measured, direction) = match i % 3 {
        0 => {
            let d = uniform_direction(sampler);
            (noise.rotate(&orientation.rotate(&d)), d)
        }
        1 => {
            let d = direction_at_height(sampler, z);
            (noise.rotate(&orientation.rotate(&d)), d)
        }
        _ => {
            let m = direction_at_height(sampler, z);
            let d = orientation.inverse_rotate(&noise.inverse().rotate(&m));
            (m, d)
        }
    };
    Direction {
        measured: UnitVector3::from_unit(measured),
        orientation,
        direction: UnitVector3::from_direction(&direction),
    }
}

/// A similarity transform with a uniform rotation, a translation in
/// `[−2, 2)³` and a log-scale in `[−1, 1)`.
fn similarity(sampler: &mut Sampler) -> Sim3<f64> {
    let rotation = sampler.rotation();
    let translation = sampler.vector3(2.0);
    Sim3::new(rotation, translation, sampler.uniform(-1.0, 1.0))
}

/// The error `S̃_ij⁻¹ S_i⁻¹ S_j` of a [`RelativeSim3`] sample: its rotation
/// angle `θ` and log-scale `σ`, by `i % 5`: zero (an exact measurement, all
/// series); `θ` next to the small-angle switch `θ² = 1e-6` and `σ` tiny;
/// `σ² + θ²` next to `W`'s series switch `0.04`; or up to 0.3 rad and 0.2.
fn error(sampler: &mut Sampler, i: usize) -> Sim3<f64> {
    let side = if (i / 5).is_multiple_of(2) { 1.0 } else { -1.0 };
    let (theta, sigma) = match i % 5 {
        0 => (0.0, 0.0),
        1 => (
            SMALL_ANGLE_SQUARED.sqrt() * (1.0 + side * 1e-9),
            side * 1e-9,
        ),
        2 => {
            let theta = sampler.uniform(0.0, 0.19);
            let r2 = SERIES_RADIUS_SQUARED * (1.0 + side * 1e-9);
            (theta, side * (r2 - theta * theta).sqrt())
        }
        _ => (sampler.uniform(0.0, 0.3), sampler.uniform(-0.2, 0.2)),
    };
    let axis = uniform_direction(sampler);
    let translation = if i.is_multiple_of(5) {
        Vector3::zeros()
    } else {
        sampler.vector3(0.2)
    };
    Sim3::new(So3::exp(&(axis * theta)), translation, sigma)
}

pub(crate) fn relative_sim3(sampler: &mut Sampler, i: usize) -> RelativeSim3 {
    let sim_i = similarity(sampler);
    let sim_j = similarity(sampler);
    let truth = sim_i.inverse().compose(&sim_j);
    RelativeSim3 {
        measured: truth.compose(&error(sampler, i).inverse()),
        sim_i,
        sim_j,
    }
}

#[test]
fn direction_dual_jacobians_match_central_differences() {
    let mut sampler = Sampler::new(11);
    for i in 0..CONFIGURATIONS {
        assert_correct_jacobians(&direction(&mut sampler, i), DEFAULT_TOLERANCE);
    }
}

#[test]
fn relative_sim3_dual_jacobians_match_central_differences() {
    let mut sampler = Sampler::new(12);
    for i in 0..CONFIGURATIONS {
        assert_correct_jacobians(&relative_sim3(&mut sampler, i), DEFAULT_TOLERANCE);
    }
}

/// The Sim(3) error a [`RelativeSim3`] sample was built with is its
/// residual's `Log`: the samples do reach the branches they are meant to.
#[test]
fn relative_sim3_samples_reach_their_branches() {
    let mut sampler = Sampler::new(12);
    for i in 0..CONFIGURATIONS {
        let r = relative_sim3(&mut sampler, i).residual().expect("finite");
        let theta2 = r.fixed_rows::<3>(0).norm_squared();
        let sigma = r[6];
        match i % 5 {
            0 => assert!(r.amax() < 1e-14, "{r}"),
            1 => assert!(
                (theta2 / SMALL_ANGLE_SQUARED - 1.0).abs() < 1e-7,
                "{theta2:e}"
            ),
            2 => {
                let r2 = theta2 + sigma * sigma;
                assert!((r2 / SERIES_RADIUS_SQUARED - 1.0).abs() < 1e-7, "{r2:e}");
            }
            _ => {}
        }
    }
}

/// At a direction on the equator `z = 0` the two branches' Jacobians (of
/// the same factor, with the direction just above and just below) are the
/// same derivative in two bases: they differ column-wise, but agree once
/// mapped back to R³ by `Bᵀ`, and are related by the rotation `B₊ᵀ B₋`.
#[test]
fn jacobians_across_the_branch_boundary_differ_by_the_basis_rotation() {
    let mut sampler = Sampler::new(13);
    let mut f = direction(&mut sampler, 1);
    let d = f.direction.vector();
    let at = |z: f64| UnitVector3::from_direction(&Vector3::new(d.x, d.y, z));
    f.direction = at(1e-300);
    let (above, basis_above) = (f.linearize_dual().unwrap().direction, f.direction.basis());
    f.direction = at(-1e-300);
    let (below, basis_below) = (f.linearize_dual().unwrap().direction, f.direction.basis());
    assert!((above - below).amax() > 0.1, "the bases differ");
    let in_r3 = (above * basis_above.transpose() - below * basis_below.transpose()).amax();
    assert!(in_r3 < 1e-15, "{in_r3:e}");
    let rotation: Matrix2<f64> = basis_above.transpose() * basis_below;
    assert!((above * rotation - below).amax() < 1e-15);
    assert!((rotation.determinant() - 1.0).abs() < 1e-15);
}

#[cfg(feature = "kernels")]
mod generated {
    use super::*;
    use factor_core::Factor;
    use factor_testing::{GENERATED_TOLERANCE, assert_generated_matches_dual};

    #[test]
    fn direction_generated_matches_dual() {
        let mut sampler = Sampler::new(21);
        for i in 0..CONFIGURATIONS {
            assert_generated_matches_dual(&direction(&mut sampler, i), GENERATED_TOLERANCE);
        }
    }

    #[test]
    fn relative_sim3_generated_matches_dual() {
        let mut sampler = Sampler::new(22);
        for i in 0..CONFIGURATIONS {
            assert_generated_matches_dual(&relative_sim3(&mut sampler, i), GENERATED_TOLERANCE);
        }
    }

    /// `linearize()` is the generated kernel's result, bit for bit.
    #[test]
    fn linearize_goes_through_the_generated_kernels() {
        assert_eq!(
            <Direction as Factor>::KERNEL,
            Some("user_kernels::direction::direction")
        );
        assert_eq!(
            <RelativeSim3 as Factor>::KERNEL,
            Some("user_kernels::relative_sim3::relative_sim3")
        );
        let mut sampler = Sampler::new(23);
        let f = direction(&mut sampler, 2);
        assert_eq!(f.linearize(), f.linearize_generated());
        let g = relative_sim3(&mut sampler, 3);
        assert_eq!(g.linearize(), g.linearize_generated());
    }
}
