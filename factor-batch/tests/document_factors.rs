//! The five document factors' batches agree with their scalar kernels and
//! dual numbers in every lane type ([`check`]).

use factor_testing::branch_points;
use factor_testing::samples::Sampler;

use crate::agreement::{COUNT, check, sampled};

#[test]
fn point_reprojection_batches_agree() {
    check(&sampled(21, Sampler::point_reprojection), 1, false);
}

#[test]
fn line_reprojection_batches_agree() {
    check(&sampled(22, Sampler::line_reprojection), 2, false);
}

#[test]
fn plucker_line_reprojection_batches_agree() {
    check(&sampled(23, Sampler::plucker_line_reprojection), 3, false);
}

#[test]
fn plane_batches_agree_across_both_branch_points() {
    let mut sampler = Sampler::new(24);
    let factors = branch_points::plane_branch_configurations(&mut sampler, COUNT);
    check(&factors, 4, true);
}

#[test]
fn free_line_batches_agree() {
    check(&sampled(25, Sampler::free_line), 5, false);
}
