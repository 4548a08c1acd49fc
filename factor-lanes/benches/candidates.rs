//! Which SIMD library the lane types are built on, measured on the generated
//! point-reprojection kernel itself (`factor_generated::point_reprojection`,
//! with the crate's `lanes` feature; the other candidates implement its
//! `Real` here).
//!
//! Each candidate runs the kernel with both Jacobian blocks over 4096 sampled
//! configurations held as structure-of-arrays columns (16 input and 20 output
//! columns), `LANES` configurations per call; criterion reports the time of
//! the whole batch (the thread's CPU time: the machine is shared), so
//! ns/factor is that time / 4096. Candidates:
//!
//! - `scalar`: `f64` and `f32`, the baseline;
//! - `wide`: `wide`'s `f64x4`, `f32x8`, `f64x8` as they are;
//! - `portable`: this crate's `F64x4`, `F32x8`, `F64x8`, aligned arrays with
//!   lane-loop operations;
//! - `pulp`: `V3` / `V4` vectors (only in the AVX2 / AVX-512 loops);
//!
//! each as the build compiles it (plain name) and, where the CPU has them,
//! inside a loop compiled with `#[target_feature]` for AVX2+FMA (`+avx2`) or
//! AVX-512 (`+avx512`), which is what a runtime-dispatched batch API would run.
//!
//! `cargo bench -p factor-lanes --bench candidates`, and again with
//! `RUSTFLAGS="-C target-cpu=native"`.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use factor_testing::samples::Sampler;

#[path = "candidates/batch.rs"]
mod batch;
// Only the point configurations are measured.
#[allow(dead_code)]
#[path = "../tests/support/configurations.rs"]
mod configurations;
// The crate's lane types as a candidate: `Batchable` impls only.
#[path = "candidates/portable.rs"]
mod portable;
#[path = "candidates/pulp_lanes.rs"]
mod pulp_lanes;
#[path = "candidates/wide_lanes.rs"]
mod wide_lanes;

use batch::{Batchable, INPUTS, OUTPUTS, point_batch, point_batch_avx2, point_batch_avx512};
use factor_testing::cpu_time::ThreadCpuTime;
// The candidates implement `crate::Real`: the generated crate's.
use factor_generated::Real;

const CONFIGURATIONS: usize = 4096;

/// The input columns of `CONFIGURATIONS` sampled point factors.
fn point_columns() -> Vec<Vec<f64>> {
    let mut sampler = Sampler::new(7);
    let mut columns: Vec<Vec<f64>> = (0..INPUTS)
        .map(|_| Vec::with_capacity(CONFIGURATIONS))
        .collect();
    for _ in 0..CONFIGURATIONS {
        for (column, s) in columns.iter_mut().zip(configurations::point(&mut sampler)) {
            column.push(s);
        }
    }
    columns
}

/// How a candidate's batch loop is compiled.
#[derive(Clone, Copy)]
enum Isa {
    /// As the build's target (`RUSTFLAGS`) has it.
    Build,
    /// `#[target_feature(enable = "avx2,fma")]`.
    Avx2,
    /// `#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2,fma")]`.
    Avx512,
}

impl Isa {
    fn suffix(self) -> &'static str {
        match self {
            Isa::Build => "",
            Isa::Avx2 => "+avx2",
            Isa::Avx512 => "+avx512",
        }
    }

    fn available(self) -> bool {
        match self {
            Isa::Build => true,
            Isa::Avx2 => is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
            Isa::Avx512 => {
                is_x86_feature_detected!("avx512f")
                    && is_x86_feature_detected!("avx512dq")
                    && is_x86_feature_detected!("avx512vl")
            }
        }
    }
}

/// Times the batch loop of lane type `L`, compiled as `isa` says.
fn bench_lanes<L: Batchable>(
    c: &mut criterion::BenchmarkGroup<'_, ThreadCpuTime>,
    name: &str,
    isa: Isa,
    input: &[Vec<L::Scalar>],
) {
    if !isa.available() {
        return;
    }
    let mut output = vec![vec![L::Scalar::default(); CONFIGURATIONS]; OUTPUTS];
    let id = BenchmarkId::from_parameter(format!("{name}{}", isa.suffix()));
    c.bench_function(id, |b| {
        b.iter(|| {
            let input = black_box(input);
            match isa {
                Isa::Build => point_batch::<L>(input, &mut output),
                // SAFETY: `isa.available()` checked the CPU above.
                Isa::Avx2 => unsafe { point_batch_avx2::<L>(input, &mut output) },
                // SAFETY: as above.
                Isa::Avx512 => unsafe { point_batch_avx512::<L>(input, &mut output) },
            }
            black_box(&mut output);
        })
    });
}

fn candidates(c: &mut Criterion<ThreadCpuTime>) {
    let f64_columns = point_columns();
    let f32_columns: Vec<Vec<f32>> = f64_columns
        .iter()
        .map(|column| column.iter().map(|&s| s as f32).collect())
        .collect();
    let mut group = c.benchmark_group("point_reprojection");
    group.throughput(Throughput::Elements(CONFIGURATIONS as u64));
    for isa in [Isa::Build, Isa::Avx2, Isa::Avx512] {
        bench_lanes::<f64>(&mut group, "scalar/f64", isa, &f64_columns);
        bench_lanes::<f32>(&mut group, "scalar/f32", isa, &f32_columns);
        bench_lanes::<wide_lanes::WideF64x4>(&mut group, "wide/f64x4", isa, &f64_columns);
        bench_lanes::<wide_lanes::WideF32x8>(&mut group, "wide/f32x8", isa, &f32_columns);
        bench_lanes::<wide_lanes::WideF64x8>(&mut group, "wide/f64x8", isa, &f64_columns);
        bench_lanes::<factor_lanes::F64x4>(&mut group, "portable/f64x4", isa, &f64_columns);
        bench_lanes::<factor_lanes::F32x8>(&mut group, "portable/f32x8", isa, &f32_columns);
        bench_lanes::<factor_lanes::F64x8>(&mut group, "portable/f64x8", isa, &f64_columns);
    }
    if Isa::Avx2.available() && pulp::x86::V3::try_new().is_some() {
        bench_lanes::<pulp_lanes::PulpF64<pulp::x86::V3>>(
            &mut group,
            "pulp/f64x4",
            Isa::Avx2,
            &f64_columns,
        );
        bench_lanes::<pulp_lanes::PulpF32<pulp::x86::V3>>(
            &mut group,
            "pulp/f32x8",
            Isa::Avx2,
            &f32_columns,
        );
    }
    if Isa::Avx512.available() && pulp::x86::V4::try_new().is_some() {
        bench_lanes::<pulp_lanes::PulpF64<pulp::x86::V4>>(
            &mut group,
            "pulp/f64x8",
            Isa::Avx512,
            &f64_columns,
        );
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .with_measurement(ThreadCpuTime)
        .sample_size(30)
        .warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(2));
    targets = candidates
}
criterion_main!(benches);
