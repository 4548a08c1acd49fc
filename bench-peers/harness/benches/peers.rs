//! wrenfold's generated kernels beside this project's `linearize_dual()` and,
//! with the feature `generated` (on in `run.sh`), this project's generated
//! kernels, in one criterion run, on the same 64 sampled configurations per
//! factor (the seeds of `benches/linearize.rs`: 1 for the point, 2 for the
//! line).
//!
//! Before anything is timed, every wrenfold output is checked against
//! `linearize_dual()` to 1e-9 relative at all 64 configurations: this
//! validates both sides' conventions (quaternion order, active rotation, left
//! perturbation, `[δω, δρ]` column order). Then the generated kernels are
//! checked against wrenfold's outputs to the same tolerance. A mismatch aborts
//! the run.
//!
//! Inputs are prepared once per configuration in each method's own calling
//! convention (plain arrays for wrenfold and the generated kernels, the factor
//! struct for `linearize_dual()`, which includes its validation and finiteness
//! checks), and each iteration takes the next configuration in turn.

use std::hint::black_box;

use bench_peers_harness::{PluckerInputs, PointInputs, check_plucker, check_point};
use criterion::Criterion;
use factor_testing::samples::Sampler;

const CONFIGURATIONS: usize = 64;
const TOLERANCE: f64 = 1e-9;

fn samples<F>(seed: u64, make: impl Fn(&mut Sampler) -> F) -> Vec<F> {
    let mut sampler = Sampler::new(seed);
    (0..CONFIGURATIONS).map(|_| make(&mut sampler)).collect()
}

/// One criterion function cycling through the configurations.
macro_rules! bench_cycle {
    ($group:expr, $name:literal, $inputs:expr, |$x:ident| $call:expr) => {{
        let inputs = &$inputs;
        let mut i = 0;
        $group.bench_function($name, |b| {
            b.iter(|| {
                i = (i + 1) % CONFIGURATIONS;
                let $x = black_box(&inputs[i]);
                black_box($call)
            })
        });
    }};
}

fn main() {
    let points = samples(1, Sampler::point_reprojection);
    let lines = samples(2, Sampler::plucker_line_reprojection);

    // Conventions check: wrenfold == linearize_dual() everywhere, or no run.
    let point_agreement = check_point(&points, TOLERANCE).unwrap_or_else(|e| panic!("{e}"));
    let line_agreement = check_plucker(&lines, TOLERANCE).unwrap_or_else(|e| panic!("{e}"));
    println!(
        "conventions check: wrenfold == linearize_dual() at all {CONFIGURATIONS} configurations \
         to {TOLERANCE:e} relative"
    );
    println!(
        "  point_reprojection worst relative error: residual {:.2e}, pose {:.2e}, point {:.2e}",
        point_agreement.residual, point_agreement.pose, point_agreement.other
    );
    println!(
        "  plucker_line_reprojection worst relative error: residual {:.2e}, pose {:.2e}, line {:.2e}",
        line_agreement.residual, line_agreement.pose, line_agreement.other
    );
    #[cfg(feature = "generated")]
    generated::check(&points, &lines);

    let point_inputs: Vec<_> = points.iter().map(PointInputs::new).collect();
    let line_inputs: Vec<_> = lines.iter().map(PluckerInputs::new).collect();

    let mut c = Criterion::default().configure_from_args();
    {
        let mut group = c.benchmark_group("point_reprojection");
        bench_cycle!(group, "wrenfold", point_inputs, |x| x.wrenfold());
        bench_cycle!(group, "dual", points, |f| f.linearize_dual());
        #[cfg(feature = "generated")]
        generated::point(&mut group, &points);
        group.finish();
    }
    {
        let mut group = c.benchmark_group("plucker_line_reprojection");
        bench_cycle!(group, "wrenfold", line_inputs, |x| x.wrenfold());
        bench_cycle!(group, "dual", lines, |f| f.linearize_dual());
        #[cfg(feature = "generated")]
        generated::plucker(&mut group, &lines);
        group.finish();
    }
    #[cfg(feature = "generated")]
    {
        generated::batch(&mut c, "point_reprojection_batch", &points);
        generated::batch(&mut c, "plucker_line_reprojection_batch", &lines);
    }
    c.final_summary();
}

// ============================== GENERATED KERNELS ==============================
// This project's generated kernels (`factor-generated`), benchmarked beside
// wrenfold and the dual numbers under `--features generated` (`run.sh` enables
// it). Each is first checked against wrenfold's outputs to 1e-9 relative at all
// configurations (wrenfold itself having been checked against
// `linearize_dual()`), then timed as "generated": f64, every block requested
// (`Some`), inputs as plain arrays prepared once per configuration, outputs
// returned by value, exactly as the wrenfold side.
//
// Then the batch API (`factor_batch::linearize`, one thread) on the same
// configurations repeated to `BATCH` rows as structure-of-arrays columns,
// every block requested, in groups `<factor>_batch`: `f64` (the scalar
// kernel in the batch loop), `F64x4`, `F64x8` and `F32x8` (the inputs
// rounded to `f32`). One iteration is one batch; the group's throughput is
// `BATCH` elements, which `summarize.py` divides by for ns per factor.
#[cfg(feature = "generated")]
mod generated {
    use std::hint::black_box;

    use bench_peers_harness::ours::{self, PluckerArrays, PointArrays};
    use criterion::measurement::WallTime;
    use criterion::{BenchmarkGroup, Criterion, Throughput};
    use factor_batch::{Columns, JacobianColumns, Options, linearize};
    use factor_core::{Factor, WithKernel};
    use factor_lanes::{F32x8, F64x4, F64x8, Kernel, Lanes};
    use slam_factors::{PluckerLineReprojection, PointReprojection};

    use super::{CONFIGURATIONS, TOLERANCE};

    /// Rows of a batch: the configurations repeated; in cache (L2), and
    /// not a multiple of 512 (columns `8·BATCH` bytes long that are a
    /// multiple of 4 KiB collide in the L1 sets).
    const BATCH: usize = 1000;

    /// The batch with lanes `L` in `group`.
    fn lanes<F, L>(
        group: &mut BenchmarkGroup<'_, WallTime>,
        name: &str,
        inputs: &Columns<L::Scalar>,
    ) where
        F: WithKernel,
        L: Lanes,
        F::Kernel: Kernel<L> + Kernel<L::Scalar>,
    {
        let mut out = JacobianColumns::new::<F>(inputs.len(), &[]);
        group.bench_function(name, |b| {
            b.iter(|| {
                linearize::<F, L>(black_box(inputs), &mut out, Options::default())
                    .expect("shapes fit")
            })
        });
    }

    /// The batch API on `factors` repeated to `BATCH` rows, as group `name`.
    pub fn batch<F>(c: &mut Criterion, name: &str, factors: &[F])
    where
        F: Factor + WithKernel + Clone,
        F::Kernel: Kernel<f64> + Kernel<f32> + Kernel<F64x4> + Kernel<F64x8> + Kernel<F32x8>,
    {
        let rows: Vec<F> = factors.iter().cycle().take(BATCH).cloned().collect();
        let inputs = Columns::from_factors(&rows);
        let inputs32 = inputs.map(|x| *x as f32);
        let mut group = c.benchmark_group(name);
        group.throughput(Throughput::Elements(BATCH as u64));
        lanes::<F, f64>(&mut group, "f64", &inputs);
        lanes::<F, F64x4>(&mut group, "F64x4", &inputs);
        lanes::<F, F64x8>(&mut group, "F64x8", &inputs);
        lanes::<F, F32x8>(&mut group, "F32x8", &inputs32);
        group.finish();
    }

    /// Generated == wrenfold at every configuration of both factors, or no
    /// run.
    pub fn check(points: &[PointReprojection], lines: &[PluckerLineReprojection]) {
        let point = ours::check_point(points, TOLERANCE).unwrap_or_else(|e| panic!("{e}"));
        let line = ours::check_plucker(lines, TOLERANCE).unwrap_or_else(|e| panic!("{e}"));
        println!(
            "generated kernels check: generated == wrenfold at all {CONFIGURATIONS} \
             configurations to {TOLERANCE:e} relative"
        );
        println!(
            "  point_reprojection worst relative error: residual {:.2e}, pose {:.2e}, point {:.2e}",
            point.residual, point.pose, point.other
        );
        println!(
            "  plucker_line_reprojection worst relative error: residual {:.2e}, pose {:.2e}, line {:.2e}",
            line.residual, line.pose, line.other
        );
    }

    pub fn point(group: &mut BenchmarkGroup<'_, WallTime>, factors: &[PointReprojection]) {
        let inputs: Vec<_> = factors.iter().map(PointArrays::new).collect();
        bench_cycle!(group, "generated", inputs, |x| x.generated());
    }

    pub fn plucker(group: &mut BenchmarkGroup<'_, WallTime>, factors: &[PluckerLineReprojection]) {
        let inputs: Vec<_> = factors.iter().map(PluckerArrays::new).collect();
        bench_cycle!(group, "generated", inputs, |x| x.generated());
    }
}
