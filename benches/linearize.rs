//! Per-factor linearization cost, in one run: the hand-written analytic
//! Jacobians (`slam_factors::analytic`), the generated kernel, dual numbers
//! (one pass over the whole tangent) and numerical differentiation, for the
//! point, line (orthonormal), Plücker-line, plane and free-line factors.
//!
//! `cargo bench --bench linearize`. Each factor is evaluated at 64 sampled
//! configurations in turn, so the figures are ns per call averaged over
//! realistic inputs rather than one cached point.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use factor_core::{Factor, NumericLinearize};
use factor_testing::samples::Sampler;
use slam_factors::analytic;

const CONFIGURATIONS: usize = 64;

fn samples<F>(seed: u64, make: impl Fn(&mut Sampler) -> F) -> Vec<F> {
    let mut sampler = Sampler::new(seed);
    (0..CONFIGURATIONS).map(|_| make(&mut sampler)).collect()
}

/// Benchmarks the five methods of one factor type: `hand_written` (the
/// factor's `slam_factors::analytic` function, between the same validation and
/// finiteness check as the typed methods, so it does the same work as
/// `generated`), `generated` (`linearize_generated()`, with the default
/// feature `kernels`),
/// `dual` (`linearize_dual()`), the derive-emitted typed methods, each
/// including the factor's validation and finiteness check, and `numeric`
/// (`Factor::linearize_numeric_dyn()`, Ridders' extrapolation of central
/// differences on the manifold).
macro_rules! bench_factor {
    ($c:expr, $name:literal, $factors:expr, $hand:path) => {{
        let factors = $factors;
        let mut group = $c.benchmark_group($name);
        let mut i = 0;
        group.bench_function("hand_written", |b| {
            b.iter(|| {
                i = (i + 1) % CONFIGURATIONS;
                let f = black_box(&factors[i]);
                black_box(f.validate().and_then(|()| $hand(f).ensure_finite()))
            })
        });
        #[cfg(feature = "kernels")]
        group.bench_function("generated", |b| {
            b.iter(|| {
                i = (i + 1) % CONFIGURATIONS;
                black_box(black_box(&factors[i]).linearize_generated())
            })
        });
        group.bench_function("dual", |b| {
            b.iter(|| {
                i = (i + 1) % CONFIGURATIONS;
                black_box(black_box(&factors[i]).linearize_dual())
            })
        });
        group.bench_function("numeric", |b| {
            b.iter(|| {
                i = (i + 1) % CONFIGURATIONS;
                black_box(black_box(&factors[i]).linearize_numeric_dyn())
            })
        });
        group.finish();
    }};
}

fn linearize(c: &mut Criterion) {
    bench_factor!(
        c,
        "point_reprojection",
        samples(1, Sampler::point_reprojection),
        analytic::point_reprojection
    );
    bench_factor!(
        c,
        "line_reprojection",
        samples(2, Sampler::line_reprojection),
        analytic::line_reprojection
    );
    // Seed 2 as for the orthonormal line: the configurations of
    // bench-peers/harness, so these figures compare with its wrenfold run.
    bench_factor!(
        c,
        "plucker_line_reprojection",
        samples(2, Sampler::plucker_line_reprojection),
        analytic::plucker_line_reprojection
    );
    bench_factor!(c, "plane", samples(3, Sampler::plane), analytic::plane);
    bench_factor!(
        c,
        "free_line",
        samples(4, Sampler::free_line),
        analytic::free_line
    );
}

criterion_group!(benches, linearize);
criterion_main!(benches);
