//! The chain rule through every candidate cut is exact: it gives the direct
//! columns' values on every document factor.

use std::collections::HashMap;

use factor_core::Factor;
use factor_symbolic::cut::minimum_cuts;
use factor_symbolic::evaluate::evaluate;
use factor_symbolic::jacobian::{chained_columns, direct_columns};
use factor_symbolic::trace::{Traced, trace_at_tangent};
use factor_symbolic::{Expr, Tracer};
use factor_testing::samples::Sampler;

/// At most this many cuts are tried (as the code generator does).
const CUTS_TRIED: usize = 4;

/// Every candidate cut of every document factor gives the direct
/// columns' values, at 20 sampled configurations each: the chain rule
/// through a cut is exact, whichever cut is chosen.
fn chained_equals_direct<F: Factor>(make: fn(&mut Sampler) -> F) {
    let mut sampler = Sampler::new(7);
    for _ in 0..20 {
        let factor = make(&mut sampler);
        let tracer = Tracer::new();
        let values = factor.to_scalars();
        let Traced {
            residual: traced,
            delta,
            input_len,
            at_zero,
        } = trace_at_tangent::<F>();
        let mut substituted = HashMap::new();
        let direct = direct_columns(&traced, &delta, &at_zero, &mut substituted);
        let cuts = minimum_cuts(&traced, &delta, CUTS_TRIED);
        assert!(!cuts.is_empty(), "{}: no cut found", F::NAME);
        let chained: Vec<Vec<Vec<Expr>>> = cuts
            .iter()
            .map(|cut| {
                let base = input_len + delta.len() as u32;
                chained_columns(&traced, &delta, &at_zero, &mut substituted, cut, base)
            })
            .collect();
        let graph = tracer.finish();
        let flat = |columns: &[Vec<Expr>]| -> Vec<f64> {
            let outputs: Vec<Expr> = columns.iter().flatten().copied().collect();
            evaluate(&graph, &values, &outputs)
        };
        let expected = flat(&direct);
        let scale = expected.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        for (cut, columns) in cuts.iter().zip(&chained) {
            for (a, b) in flat(columns).iter().zip(&expected) {
                assert!(
                    (a - b).abs() <= 1e-12 * scale,
                    "{} through a cut of {}: {a} vs {b}",
                    F::NAME,
                    cut.len()
                );
            }
        }
    }
}

#[test]
fn the_chain_rule_through_every_cut_is_exact() {
    chained_equals_direct(Sampler::point_reprojection);
    chained_equals_direct(Sampler::line_reprojection);
    chained_equals_direct(Sampler::plucker_line_reprojection);
    chained_equals_direct(Sampler::plane);
    chained_equals_direct(Sampler::free_line);
}
