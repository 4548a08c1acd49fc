//! Dual-number Jacobians of the four document factors against central
//! differences on their manifolds, at 200 random well-conditioned
//! configurations each, plus a check that the comparison is sensitive enough
//! to catch a wrong block.

use factor_core::factor::relative_frobenius_error;
use factor_core::{DynLinearization, Factor, NumericLinearize};
use factor_testing::check_jacobians;
use factor_testing::samples::Sampler;
use factor_testing::seeding::assert_seeding_matches_retraction;

const CONFIGURATIONS: usize = 200;
const TOLERANCE: f64 = 1e-6;

/// Checks every configuration and returns the worst relative error seen.
fn worst_error<F: Factor>(seed: u64, mut sample: impl FnMut(&mut Sampler) -> F) -> f64 {
    let mut sampler = Sampler::new(seed);
    let mut worst: f64 = 0.0;
    for i in 0..CONFIGURATIONS {
        let factor = sample(&mut sampler);
        let check = check_jacobians(&factor).unwrap_or_else(|e| panic!("configuration {i}: {e}"));
        assert!(
            check.max_error() <= TOLERANCE,
            "{} configuration {i}: {:?}",
            F::NAME,
            check
        );
        worst = worst.max(check.max_error());
    }
    worst
}

#[test]
fn point_reprojection_dual_matches_numeric() {
    let worst = worst_error(1, Sampler::point_reprojection);
    println!("point_reprojection: worst relative error {worst:e}");
}

#[test]
fn line_reprojection_dual_matches_numeric() {
    let worst = worst_error(2, Sampler::line_reprojection);
    println!("line_reprojection: worst relative error {worst:e}");
}

#[test]
fn plane_dual_matches_numeric() {
    let worst = worst_error(3, Sampler::plane);
    println!("plane: worst relative error {worst:e}");
}

#[test]
fn free_line_dual_matches_numeric() {
    let worst = worst_error(4, Sampler::free_line);
    println!("free_line: worst relative error {worst:e}");
}

/// The plane error at convergence (below the small-angle threshold of the
/// quaternion logarithm) and exactly zero: the branch a solver ends in.
#[test]
fn plane_jacobians_are_exact_near_and_at_zero_error() {
    let mut sampler = Sampler::new(5);
    for i in 0..CONFIGURATIONS {
        let max_error = if i % 2 == 0 { 1e-4 } else { 0.0 };
        let factor = sampler.plane_with_error(max_error);
        let check = check_jacobians(&factor).expect("well-conditioned");
        assert!(
            check.max_error() <= TOLERANCE,
            "configuration {i}: {check:?}"
        );
    }
}

/// Every way of damaging one block (a sign, a swapped pair of columns, one
/// entry off by 0.1%) is caught by the comparison used above, so those tests
/// would fail if a block were wrong.
#[test]
fn the_comparison_detects_a_wrong_block() {
    fn damaged_versions(lin: &DynLinearization, block: usize) -> Vec<nalgebra::DMatrix<f64>> {
        let j = &lin.jacobians[block];
        let mut sign = j.clone();
        sign.column_mut(0).neg_mut();
        let mut swapped = j.clone();
        swapped.swap_columns(0, 1);
        let mut scaled = j.clone();
        let (r, c) = j.iamax_full();
        scaled[(r, c)] *= 1.001;
        vec![sign, swapped, scaled]
    }
    fn check<F: Factor>(factor: &F) {
        let dual = factor.linearize_dual_dyn().expect("valid");
        let numeric = factor.linearize_numeric_dyn().expect("valid");
        for block in 0..dual.jacobians.len() {
            let good =
                relative_frobenius_error(&dual.jacobians[block], &numeric.jacobians[block], 1e-9);
            assert!(good <= TOLERANCE);
            for bad in damaged_versions(&dual, block) {
                if bad == dual.jacobians[block] {
                    continue; // e.g. two equal columns swapped: not a damage
                }
                let error = relative_frobenius_error(&bad, &numeric.jacobians[block], 1e-9);
                assert!(
                    error > TOLERANCE,
                    "{} block {block}: damage undetected ({error:e})",
                    F::NAME
                );
            }
        }
    }
    let mut sampler = Sampler::new(6);
    for _ in 0..20 {
        check(&sampler.point_reprojection());
        check(&sampler.line_reprojection());
        check(&sampler.plane());
        check(&sampler.free_line());
    }
}

/// The seeded one-pass dual numbers (each variable seeded through its
/// chart's closed form, `Manifold::seeded`) and the same derivative through
/// every variable's `retract_first_order`, one column at a time, agree to
/// rounding, for every shipped factor.
#[test]
fn seeded_dual_numbers_agree_with_the_retractions() {
    let mut sampler = Sampler::new(7);
    for _ in 0..CONFIGURATIONS {
        assert_seeding_matches_retraction(&sampler.point_reprojection(), 1e-13);
        assert_seeding_matches_retraction(&sampler.line_reprojection(), 1e-13);
        assert_seeding_matches_retraction(&sampler.plucker_line_reprojection(), 1e-13);
        assert_seeding_matches_retraction(&sampler.plane(), 1e-13);
        assert_seeding_matches_retraction(&sampler.free_line(), 1e-13);
        assert_seeding_matches_retraction(&sampler.snavely_reprojection(), 1e-13);
        assert_seeding_matches_retraction(&sampler.stereo_reprojection(), 1e-13);
        assert_seeding_matches_retraction(&sampler.between(), 1e-13);
    }
}

#[test]
fn plucker_line_reprojection_dual_matches_numeric() {
    let worst = worst_error(8, Sampler::plucker_line_reprojection);
    println!("plucker_line_reprojection: worst relative error {worst:e}");
}

#[test]
fn g2o_se3_dual_matches_numeric() {
    let worst = worst_error(9, Sampler::g2o_se3);
    println!("g2o_se3: worst relative error {worst:e}");
}

#[test]
fn g2o_line_dual_matches_numeric() {
    let worst = worst_error(10, Sampler::g2o_line);
    println!("g2o_se3_line3d: worst relative error {worst:e}");
}

#[test]
fn g2o_plane_dual_matches_numeric() {
    let worst = worst_error(11, Sampler::g2o_plane);
    println!("g2o_se3_plane_calib: worst relative error {worst:e}");
}

#[test]
fn g2o_prior_dual_matches_numeric() {
    let worst = worst_error(13, Sampler::g2o_prior);
    println!("g2o_se3_prior: worst relative error {worst:e}");
}

#[test]
fn g2o_point_dual_matches_numeric() {
    let worst = worst_error(14, Sampler::g2o_point);
    println!("g2o_se3_trackxyz: worst relative error {worst:e}");
}

/// g2o's errors near zero (a converged graph) and at zero.
#[test]
fn g2o_jacobians_are_exact_near_and_at_zero_error() {
    let mut sampler = Sampler::new(12);
    for i in 0..CONFIGURATIONS / 4 {
        let max_error = if i % 2 == 0 { 1e-5 } else { 0.0 };
        for check in [
            check_jacobians(&sampler.g2o_se3_with_error(max_error)),
            check_jacobians(&sampler.g2o_line_with_error(max_error)),
            check_jacobians(&sampler.g2o_plane_with_error(max_error)),
            check_jacobians(&sampler.g2o_prior_with_error(max_error)),
            check_jacobians(&sampler.g2o_point_with_error(max_error)),
        ] {
            let check = check.expect("well-conditioned");
            assert!(
                check.max_error() <= TOLERANCE,
                "configuration {i}: {check:?}"
            );
        }
    }
}

#[test]
fn line_observation_dual_matches_numeric() {
    let worst = worst_error(13, Sampler::line_observation);
    println!("line_observation: worst relative error {worst:e}");
}

/// The documents' line and plane factors on g2o's body-to-world pose
/// (`g2o::{LineObservationOnBody, PlaneFactorOnBody}`).
#[test]
fn documents_factors_on_body_dual_match_numeric() {
    use factor_core::lie::Se3RhoTheta;
    use slam_factors::g2o::{LineObservationOnBody, PlaneFactorOnBody};
    let worst = worst_error(31, |s| {
        let f = s.line_observation();
        LineObservationOnBody::new(&f, Se3RhoTheta::new(f.pose.inverse()))
    });
    println!("line_observation_on_body: worst relative error {worst:e}");
    let worst = worst_error(32, |s| {
        let f = s.plane();
        PlaneFactorOnBody::new(&f, Se3RhoTheta::new(f.pose.inverse()))
    });
    println!("plane_on_body: worst relative error {worst:e}");
}
