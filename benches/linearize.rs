//! Per-factor linearization cost: the generated kernel, dual numbers in one
//! pass over the whole tangent, dual numbers one pass per variable block, and
//! central differences.
//!
//! `cargo bench --bench linearize`. Each factor is evaluated at 64 sampled
//! configurations in turn, so the figures are ns per call averaged over
//! realistic inputs rather than one cached point.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use factor_core::Factor;
use factor_core::testing::samples::Sampler;

const CONFIGURATIONS: usize = 64;

fn samples<F>(seed: u64, make: impl Fn(&mut Sampler) -> F) -> Vec<F> {
    let mut sampler = Sampler::new(seed);
    (0..CONFIGURATIONS).map(|_| make(&mut sampler)).collect()
}

/// Benchmarks the three methods of one factor type; `one_pass` and
/// `per_block` are the macro-emitted typed methods.
macro_rules! bench_factor {
    ($c:expr, $name:literal, $factors:expr) => {{
        let factors = $factors;
        let mut group = $c.benchmark_group($name);
        let mut i = 0;
        #[cfg(feature = "kernels")]
        group.bench_function("generated", |b| {
            b.iter(|| {
                i = (i + 1) % CONFIGURATIONS;
                black_box(black_box(&factors[i]).linearize_generated())
            })
        });
        group.bench_function("dual_one_pass", |b| {
            b.iter(|| {
                i = (i + 1) % CONFIGURATIONS;
                black_box(black_box(&factors[i]).linearize_dual())
            })
        });
        group.bench_function("dual_per_block", |b| {
            b.iter(|| {
                i = (i + 1) % CONFIGURATIONS;
                black_box(black_box(&factors[i]).linearize_dual_per_block())
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
        samples(1, Sampler::point_reprojection)
    );
    bench_factor!(
        c,
        "line_reprojection",
        samples(2, Sampler::line_reprojection)
    );
    bench_factor!(c, "plane", samples(3, Sampler::plane));
    bench_factor!(c, "free_line", samples(4, Sampler::free_line));
}

criterion_group!(benches, linearize);
criterion_main!(benches);
