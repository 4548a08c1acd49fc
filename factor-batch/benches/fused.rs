//! The fused normal-equation kernel of the point factor against what it
//! replaces, in one run, 1000 sampled factors held in cache (the inputs and
//! outputs of every method fit in L2):
//!
//! - `scalar/fused`: `point_reprojection_normal` one factor at a time: the
//!   cost, the gradient (9) and the upper triangle of `JᵀwJ` (45);
//! - `scalar/jacobian+nalgebra`: the Jacobian kernel one factor at a time,
//!   then `nalgebra` on the 2 × 9 Jacobian: `Jᵀ (w J)` (the full 9 × 9),
//!   `Jᵀ (w r)` and `½ w rᵀr`;
//! - `scalar/jacobian`: the Jacobian kernel alone;
//! - `batch/<lanes>/normal` and `batch/<lanes>/jacobian`: the batch API's
//!   fused and Jacobian outputs in lanes (structure-of-arrays in and out).
//!
//! Time is the benchmark thread's CPU time (the machine is shared), per
//! batch of 1000; ns per factor is that / 1000. (Not 1024: structure-of-arrays
//! columns of a multiple of 512 `f64` rows, end to end, make every column's
//! row `i` collide in the same L1 sets, which slows the batch 2–4×; see
//! `benches/throughput.rs`.)
//!
//! `cargo bench -p factor-batch --bench fused`

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use factor_batch::{Columns, JacobianColumns, NormalColumns, Options, linearize, normal};
use factor_generated::point_reprojection::{point_reprojection, point_reprojection_normal};
use factor_lanes::{F32x8, F64x4, F64x8, Lanes, NormalKernel};
use factor_testing::samples::Sampler;
use nalgebra::{SMatrix, SVector};
use slam_factors::PointReprojection;

use factor_testing::cpu_time::ThreadCpuTime;

const FACTORS: usize = 1000;

/// One factor's inputs as the kernels take them.
struct Arrays {
    intrinsics: [f64; 4],
    observed: [f64; 2],
    pose: [f64; 7],
    point: [f64; 3],
    weight: f64,
}

fn arrays(factors: &[PointReprojection], weights: &[f64]) -> Vec<Arrays> {
    factors
        .iter()
        .zip(weights)
        .map(|(f, &weight)| {
            let s = factor_core::Storage::to_scalars(f);
            Arrays {
                intrinsics: core::array::from_fn(|k| s[k]),
                observed: core::array::from_fn(|k| s[4 + k]),
                pose: core::array::from_fn(|k| s[6 + k]),
                point: core::array::from_fn(|k| s[13 + k]),
                weight,
            }
        })
        .collect()
}

/// The normal equations of one factor: cost, gradient, upper triangle.
type Normal = (f64, [f64; 9], [f64; 45]);

fn fused(x: &Arrays) -> Normal {
    let mut cost = 0.0;
    let (mut g0, mut g1) = ([0.0; 6], [0.0; 3]);
    let (mut h00, mut h01, mut h11) = ([0.0; 21], [0.0; 18], [0.0; 6]);
    point_reprojection_normal(
        &x.intrinsics,
        &x.observed,
        &x.pose,
        &x.point,
        x.weight,
        &mut cost,
        Some(&mut g0),
        Some(&mut g1),
        Some(&mut h00),
        Some(&mut h01),
        Some(&mut h11),
    );
    let mut g = [0.0; 9];
    g[..6].copy_from_slice(&g0);
    g[6..].copy_from_slice(&g1);
    let mut h = [0.0; 45];
    h[..21].copy_from_slice(&h00);
    h[21..39].copy_from_slice(&h01);
    h[39..].copy_from_slice(&h11);
    (cost, g, h)
}

/// The Jacobian kernel: residual and the 2 × 9 Jacobian `[J_pose | J_point]`.
fn jacobian(x: &Arrays) -> (SVector<f64, 2>, SMatrix<f64, 2, 9>) {
    let (mut r, mut d_pose, mut d_point) = ([0.0; 2], [0.0; 12], [0.0; 6]);
    point_reprojection(
        &x.intrinsics,
        &x.observed,
        &x.pose,
        &x.point,
        &mut r,
        Some(&mut d_pose),
        Some(&mut d_point),
    );
    let j = SMatrix::<f64, 2, 9>::from_fn(|row, col| {
        if col < 6 {
            d_pose[row * 6 + col]
        } else {
            d_point[row * 3 + col - 6]
        }
    });
    (SVector::from(r), j)
}

/// The Jacobian kernel, then `nalgebra`: `Jᵀ (w J)`, `Jᵀ (w r)`, `½ w rᵀr`.
fn jacobian_then_nalgebra(x: &Arrays) -> (f64, SVector<f64, 9>, SMatrix<f64, 9, 9>) {
    let (r, j) = jacobian(x);
    let wr = r * x.weight;
    (0.5 * r.dot(&wr), j.tr_mul(&wr), j.tr_mul(&(j * x.weight)))
}

/// The two agree (so the benchmark compares equal work).
fn check(inputs: &[Arrays]) {
    for x in inputs {
        let (cost, g, h) = fused(x);
        let (c, gn, hn) = jacobian_then_nalgebra(x);
        let scale = hn.amax().max(1.0);
        assert!(
            (cost - c).abs() <= 1e-12 * c.abs().max(1.0),
            "{cost} vs {c}"
        );
        for a in 0..9 {
            assert!((g[a] - gn[a]).abs() <= 1e-12 * gn.amax().max(1.0));
        }
        let mut k = 0;
        for (i, j) in factor_batch::pairs(2) {
            let (ri, ci) = ([0..6, 6..9][i].clone(), [0..6, 6..9][j].clone());
            for a in ri.clone() {
                for b in ci.clone() {
                    if i == j && b < a {
                        continue;
                    }
                    assert!(
                        (h[k] - hn[(a, b)]).abs() <= 1e-12 * scale,
                        "entry ({a}, {b})"
                    );
                    k += 1;
                }
            }
        }
    }
}

fn batch<L: Lanes>(
    group: &mut criterion::BenchmarkGroup<'_, ThreadCpuTime>,
    name: &str,
    inputs: &Columns<L::Scalar>,
    weights: &[L::Scalar],
) where
    <PointReprojection as factor_core::WithKernel>::Kernel:
        NormalKernel<L> + NormalKernel<L::Scalar>,
{
    let n = inputs.len();
    let mut out = NormalColumns::new::<PointReprojection>(n, &[]);
    group.bench_function(BenchmarkId::new(format!("batch/{name}"), "normal"), |b| {
        b.iter(|| {
            normal::<PointReprojection, L>(
                black_box(inputs),
                Some(weights),
                &mut out,
                Options::default(),
            )
            .expect("shapes fit");
        })
    });
    let mut out = JacobianColumns::new::<PointReprojection>(n, &[]);
    group.bench_function(BenchmarkId::new(format!("batch/{name}"), "jacobian"), |b| {
        b.iter(|| {
            linearize::<PointReprojection, L>(black_box(inputs), &mut out, Options::default())
                .expect("shapes fit");
        })
    });
}

fn bench(c: &mut Criterion<ThreadCpuTime>) {
    let mut s = Sampler::new(41);
    let factors: Vec<PointReprojection> = (0..FACTORS).map(|_| s.point_reprojection()).collect();
    let weights: Vec<f64> = (0..FACTORS).map(|_| s.uniform(0.1, 10.0)).collect();
    let inputs = arrays(&factors, &weights);
    check(&inputs);

    let mut group = c.benchmark_group("fused_point");
    group.throughput(Throughput::Elements(FACTORS as u64));
    group.bench_function("scalar/fused", |b| {
        b.iter(|| {
            for x in black_box(&inputs) {
                black_box(fused(x));
            }
        })
    });
    group.bench_function("scalar/jacobian+nalgebra", |b| {
        b.iter(|| {
            for x in black_box(&inputs) {
                black_box(jacobian_then_nalgebra(x));
            }
        })
    });
    group.bench_function("scalar/jacobian", |b| {
        b.iter(|| {
            for x in black_box(&inputs) {
                black_box(jacobian(x));
            }
        })
    });
    let columns = Columns::from_factors(&factors);
    let columns32 = columns.map(|x| *x as f32);
    let weights32: Vec<f32> = weights.iter().map(|w| *w as f32).collect();
    batch::<f64>(&mut group, "f64", &columns, &weights);
    batch::<F64x4>(&mut group, "F64x4", &columns, &weights);
    batch::<F64x8>(&mut group, "F64x8", &columns, &weights);
    batch::<F32x8>(&mut group, "F32x8", &columns32, &weights32);
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .with_measurement(ThreadCpuTime)
        .sample_size(30)
        .warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(2));
    targets = bench
}
criterion_main!(benches);
