//! The hand-written analytic Jacobians of `slam_factors::analytic` against
//! dual numbers (`linearize_dual()`, exact by construction) at 200 sampled
//! configurations per factor: the independent confirmation that the
//! corrected document formulas they implement are right.
//!
//! Errors are relative Frobenius norms: each Jacobian block relative to the
//! dual block's norm (floor 1e-9), the residual relative to `max(‖r‖, 1)`.

use factor_core::factor::relative_frobenius_error;
use factor_core::{DynLinearization, Factor};
use factor_testing::samples::Sampler;
use slam_factors::analytic;

const CONFIGURATIONS: usize = 200;
const TOLERANCE: f64 = 1e-9;

/// Relative errors of the residual and of each block of `a` w.r.t. `b`.
fn errors(a: &DynLinearization, b: &DynLinearization) -> Vec<f64> {
    let residual = (&a.residual - &b.residual).norm() / b.residual.norm().max(1.0);
    let blocks = a
        .jacobians
        .iter()
        .zip(&b.jacobians)
        .map(|(x, y)| relative_frobenius_error(x, y, 1e-9));
    std::iter::once(residual).chain(blocks).collect()
}

/// Compares `hand` with `linearize_dual_dyn()` at `CONFIGURATIONS` valid
/// samples; returns the worst error of the residual and of each block.
fn check<F: Factor>(
    seed: u64,
    mut sample: impl FnMut(&mut Sampler) -> F,
    hand: impl Fn(&F) -> DynLinearization,
) -> Vec<f64> {
    let mut sampler = Sampler::new(seed);
    let mut worst = vec![0.0_f64; 1 + F::variables().len()];
    for i in 0..CONFIGURATIONS {
        let factor = sample(&mut sampler);
        factor
            .validate()
            .unwrap_or_else(|e| panic!("{} configuration {i}: {e}", F::NAME));
        let dual = factor.linearize_dual_dyn().expect("valid");
        let analytic = hand(&factor);
        for (k, e) in errors(&analytic, &dual).into_iter().enumerate() {
            assert!(
                e <= TOLERANCE,
                "{} configuration {i}, output {k} (0 = residual): analytic vs dual {e:e}\n\
                 analytic {analytic:?}\ndual {dual:?}",
                F::NAME
            );
            worst[k] = worst[k].max(e);
        }
    }
    let names: Vec<&str> = std::iter::once("residual")
        .chain(F::variables().iter().map(|v| v.name))
        .collect();
    let report: Vec<String> = names
        .iter()
        .zip(&worst)
        .map(|(n, e)| format!("{n} {e:.1e}"))
        .collect();
    println!("{}: worst analytic vs dual: {}", F::NAME, report.join(", "));
    worst
}

#[test]
fn point_reprojection_matches_dual() {
    check(101, Sampler::point_reprojection, |f| {
        analytic::point_reprojection(f).to_dyn()
    });
}

#[test]
fn line_reprojection_matches_dual() {
    check(102, Sampler::line_reprojection, |f| {
        analytic::line_reprojection(f).to_dyn()
    });
}

#[test]
fn plucker_line_reprojection_matches_dual() {
    check(103, Sampler::plucker_line_reprojection, |f| {
        analytic::plucker_line_reprojection(f).to_dyn()
    });
}

#[test]
fn plane_matches_dual() {
    check(104, Sampler::plane, |f| analytic::plane(f).to_dyn());
}

/// Document 000 (13) evaluated link by link with its corrections (`∂E/∂u =
/// Jl(E)⁻¹ Jl(u)`, exponent 3, the `∂u/∂φ₄` column, the `δρ` half of
/// `∂y/∂ξ`) gives the same pose block.
#[test]
fn plane_document_chain_matches_dual() {
    check(104, Sampler::plane, |f| {
        analytic::plane_document_chain(f).to_dyn()
    });
}

/// Errors up to π and beyond (the error quaternion's `w < 0`), where `Jl(E)⁻¹`
/// and the full-sphere logarithm are far from their small-angle forms.
#[test]
fn plane_with_large_errors_matches_dual() {
    let beyond_pi = std::cell::Cell::new(0);
    check(
        105,
        |s| s.plane_with_error(5.5),
        |f| {
            let lin = analytic::plane(f);
            if lin.residual.norm() > std::f64::consts::PI {
                beyond_pi.set(beyond_pi.get() + 1);
            }
            lin.to_dyn()
        },
    );
    assert!(beyond_pi.get() > 20, "{} errors beyond π", beyond_pi.get());
}

/// Errors below the small-angle threshold, where the logarithm and `Jl(E)⁻¹`
/// take their series.
#[test]
fn plane_with_tiny_errors_matches_dual() {
    check(
        106,
        |s| s.plane_with_error(1e-4),
        |f| analytic::plane(f).to_dyn(),
    );
}

#[test]
fn free_line_matches_dual() {
    check(107, Sampler::free_line, |f| analytic::free_line(f).to_dyn());
}

/// The bench's configurations (seeds 1–4 as in `benches/linearize.rs`) too.
#[test]
fn benchmark_configurations_match_dual() {
    check(1, Sampler::point_reprojection, |f| {
        analytic::point_reprojection(f).to_dyn()
    });
    check(2, Sampler::line_reprojection, |f| {
        analytic::line_reprojection(f).to_dyn()
    });
    check(2, Sampler::plucker_line_reprojection, |f| {
        analytic::plucker_line_reprojection(f).to_dyn()
    });
    check(3, Sampler::plane, |f| analytic::plane(f).to_dyn());
    check(4, Sampler::free_line, |f| analytic::free_line(f).to_dyn());
}
