//! Linearization of a whole synthetic bundle-adjustment problem: this
//! project's batch API against apex-solver's own per-block linearization of
//! the same problem, in one run.
//!
//! The problem: `slam_data::synthetic` (what `slamjac synth-bal` writes),
//! `SyntheticConfig::with_observations(10⁶, 1)`: 10⁶ observations, 2·10⁵
//! points, 1000 cameras. Each observation is a block on the camera's pose
//! (6), its `[f, k1, k2]` (3) and the point (3): a residual of 2 and a
//! Jacobian of 2 × 12.
//!
//! Timed, one pass over every observation at the initial values, each
//! writing its outputs to memory (nothing is summed or assembled):
//!
//! - `apex`: apex-solver's `ProjectionFactor<BALPinholeCameraStrict,
//!   SelfCalibration>` (how `factor_apex::problems` builds apex's own BAL
//!   problem), `Factor::linearize` block after block, residual and the
//!   column-major 2 × 12 Jacobian written to one preallocated array per
//!   pass; on 2 threads, rayon over chunks of blocks, as apex's own
//!   evaluation runs its blocks in parallel. The parameters are the kept
//!   per-block copies (`KeptBlock`), gathered before timing; BAL blocks
//!   have no noise model, so there is no whitening.
//! - `batch Jacobians`: `factor_batch::linearize` of `SnavelyReprojection`
//!   (kernel `snavely_reprojection`), the residual and the three blocks
//!   (26 columns), with `F64x4` and `F64x8`; inputs: the factors' stored
//!   scalars as columns (19), gathered before timing.
//! - `batch normal equations`: `factor_batch::normal` (the fused kernel,
//!   weights 1): per observation the cost, the gradient (12) and the upper
//!   triangle of `JᵀJ` by blocks (78), 91 columns.
//!
//! Each on 1 thread and on a rayon pool of 2. Wall time; in each round
//! every method once, in rotating order (the machine is shared,
//! `factor_testing::rounds`); medians over the rounds, the median
//! per-round ratio to apex on as many threads, and the cores each method
//! had (the process's CPU time over the wall time: below 2 on 2 threads
//! when another process held a core).
//!
//! ```sh
//! cargo bench --manifest-path integrations/apex/Cargo.toml --bench linearize_bal -- \
//!     [--observations 1000000] [--rounds 5]
//! ```

use std::hint::black_box;
use std::time::Instant;

use clap::Parser;
use factor_apex::problems::bundle::factor_of;
use factor_apex::problems::{BuildOptions, FactorChoice, KeptBlock, build};
use factor_batch::{Columns, JacobianColumns, NormalColumns, Options, linearize, normal};
use factor_lanes::{F64x4, F64x8, Kernel, Lanes, NormalKernel};
use factor_testing::rounds::{
    Method, alternate, fail, load_average, median, median_ratio, positive_count,
};
use rayon::ThreadPool;
use rayon::prelude::*;
use slam_data::synthetic::{SyntheticConfig, generate};
use slam_factors::SnavelyReprojection;

/// Residual and Jacobian entries of one block: 2 + 2 × 12.
const OUTPUTS: usize = 26;
/// Blocks per rayon task of the apex pass (as `factor_batch::CHUNK`).
const CHUNK: usize = factor_batch::CHUNK;

/// apex's linearization of `blocks`, residual and Jacobian of block `k`
/// written to `out[26 k..26 (k + 1)]`.
fn apex_pass(blocks: &[KeptBlock], out: &mut [f64]) {
    for (block, out) in blocks.iter().zip(out.chunks_exact_mut(OUTPUTS)) {
        let params: [&[f64]; 3] = [&block.params[0], &block.params[1], &block.params[2]];
        let (residual, jacobian) = out.split_at_mut(2);
        block.factor.linearize(
            &params,
            residual,
            Some(faer::mat::MatMut::from_column_major_slice_mut(
                jacobian, 2, 12,
            )),
        );
    }
}

/// The batch Jacobians with lanes `L`, on `pool` when given.
fn jacobians<'a, L>(inputs: &'a Columns<f64>, pool: Option<&'a ThreadPool>) -> Method<'a>
where
    L: Lanes<Scalar = f64>,
    <SnavelyReprojection as factor_core::WithKernel>::Kernel: Kernel<L>,
{
    let mut out = JacobianColumns::new::<SnavelyReprojection>(inputs.len(), &[]);
    let options = if pool.is_some() {
        Options::rayon()
    } else {
        Options::default()
    };
    Box::new(move |reps| {
        let mut run = || {
            for _ in 0..reps {
                linearize::<SnavelyReprojection, L>(black_box(inputs), &mut out, options)
                    .expect("shapes fit");
            }
        };
        match pool {
            Some(pool) => pool.install(run),
            None => run(),
        }
    })
}

/// The batch normal equations with lanes `L`, on `pool` when given.
fn normals<'a, L>(inputs: &'a Columns<f64>, pool: Option<&'a ThreadPool>) -> Method<'a>
where
    L: Lanes<Scalar = f64>,
    <SnavelyReprojection as factor_core::WithKernel>::Kernel: NormalKernel<L>,
{
    let mut out = NormalColumns::new::<SnavelyReprojection>(inputs.len(), &[]);
    let options = if pool.is_some() {
        Options::rayon()
    } else {
        Options::default()
    };
    Box::new(move |reps| {
        let mut run = || {
            for _ in 0..reps {
                normal::<SnavelyReprojection, L>(black_box(inputs), None, &mut out, options)
                    .expect("shapes fit");
            }
        };
        match pool {
            Some(pool) => pool.install(run),
            None => run(),
        }
    })
}

/// The command line (`cargo bench` adds `--bench`).
#[derive(Parser)]
struct Args {
    /// Observations of the synthetic problem.
    #[arg(long, default_value_t = 1_000_000, value_parser = positive_count)]
    observations: usize,
    /// Rounds: every method runs once per round, in rotating order.
    #[arg(long, default_value_t = 5, value_parser = positive_count)]
    rounds: usize,
    #[arg(long, hide = true)]
    bench: bool,
}

fn main() {
    let Args {
        observations,
        rounds,
        ..
    } = Args::parse();
    let load_before = load_average();
    let started = Instant::now();
    let bal = generate(&SyntheticConfig::with_observations(observations, 1))
        .unwrap_or_else(|e| fail(&e.to_string()))
        .problem;
    let n = bal.observations.len();
    eprintln!(
        "generated {n} observations, {} cameras, {} points ({:.1} s); building apex's problem…",
        bal.cameras.len(),
        bal.points.len(),
        started.elapsed().as_secs_f64()
    );
    let data = slam_data::Problem::Bal(bal);
    let options = BuildOptions {
        factors: FactorChoice::Apex,
        robust: None,
        keep_blocks: true,
    };
    let blocks = build(&data, &options)
        .unwrap_or_else(|e| fail(&e.to_string()))
        .kept
        .expect("blocks kept");
    let slam_data::Problem::Bal(bal) = &data else {
        unreachable!("built as BAL")
    };
    let factors: Vec<SnavelyReprojection> = (0..n).map(|k| factor_of(bal, k)).collect();
    let inputs = Columns::from_factors(&factors);
    drop(factors);
    eprintln!(
        "ready ({:.1} s); timing {rounds} rounds…",
        started.elapsed().as_secs_f64()
    );

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("a pool of 2 threads");
    let mut apex_out = vec![0.0; n * OUTPUTS];
    let mut apex_out2 = vec![0.0; n * OUTPUTS];
    let names = [
        "apex, per block",
        "batch Jacobians, 4×f64",
        "batch Jacobians, 8×f64",
        "batch normal equations, 8×f64",
    ];
    let blocks = &blocks;
    let mut methods: Vec<Method<'_>> = vec![
        Box::new(|reps| {
            for _ in 0..reps {
                apex_pass(black_box(blocks), &mut apex_out)
            }
        }),
        jacobians::<F64x4>(&inputs, None),
        jacobians::<F64x8>(&inputs, None),
        normals::<F64x8>(&inputs, None),
        Box::new(|reps| {
            pool.install(|| {
                for _ in 0..reps {
                    blocks
                        .par_chunks(CHUNK)
                        .zip(apex_out2.par_chunks_mut(CHUNK * OUTPUTS))
                        .for_each(|(blocks, out)| apex_pass(black_box(blocks), out))
                }
            })
        }),
        jacobians::<F64x4>(&inputs, Some(&pool)),
        jacobians::<F64x8>(&inputs, Some(&pool)),
        normals::<F64x8>(&inputs, Some(&pool)),
    ];
    let times = alternate(&mut methods, rounds, 1);
    println!(
        "\nlinearization of a synthetic BAL problem: {n} observations; wall time of one pass, median of {rounds} rounds\n"
    );
    println!(
        "| threads | method | time per pass | ns per observation | apex's time / the method's | cores it had |"
    );
    println!("| --- | --- | --- | --- | --- | --- |");
    for (k, time) in times.wall.iter().enumerate() {
        let (threads, apex) = if k < names.len() {
            (1, 0)
        } else {
            (2, names.len())
        };
        let t = median(time);
        println!(
            "| {threads} | {} | {:.1} ms | {:.1} | {:.2} | {:.2} |",
            names[k % names.len()],
            t * 1e3,
            t / n as f64 * 1e9,
            median_ratio(&times.wall[apex], time),
            times.cores(k),
        );
    }
    println!(
        "\nload average before: {load_before}; after: {}",
        load_average()
    );
}
