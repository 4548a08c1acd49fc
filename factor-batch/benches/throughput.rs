//! Throughput of the batch API against the batch size: factors linearized
//! per second (residual and every Jacobian block) for the point and the
//! Plücker-line reprojection factors, at batch sizes from 10 to 10⁶, by
//!
//! - `scalar`: the batch loop with `f64`, one factor per kernel call (this
//!   project's scalar kernel on the same columns);
//! - `4×f64`, `8×f64`, `8×f32`: the lane types `F64x4`, `F64x8`, `F32x8`
//!   (the `f32` batch on the same configurations rounded to `f32`);
//! - `8×f64, 2 threads`: `F64x8` with `Threads::Rayon` in a pool of 2
//!   threads (the machine's cores), chunks of `factor_batch::CHUNK`.
//!
//! Inputs: 4096 sampled configurations (`Sampler`, seeds 1 and 2 as
//! `benches/linearize.rs`) repeated to the batch size, as structure-of-arrays
//! columns; outputs preallocated. One timed run is one whole batch through
//! `factor_batch::linearize` (the instruction set detected at run time).
//! Wall time, since threads are measured; each measurement is the mean of
//! enough back-to-back runs to make about 2²² factors, and in each of the
//! rounds every method is measured once, in rotating order (the machine is
//! shared). Printed: the median factors/s over the rounds, and the medians
//! over the rounds of the per-round ratios (lanes / scalar, 2 threads /
//! 1 thread), with the cores the 2-thread batch had (the process's CPU
//! time over the wall time: below 2 when another process held a core); the
//! load average before and after.
//!
//! ```sh
//! cargo bench -p factor-batch --bench throughput -- [--rounds 7] [--svg docs/throughput.svg]
//! ```

use std::hint::black_box;
use std::path::PathBuf;

use factor_batch::{Columns, JacobianColumns, Options, linearize};
use factor_core::WithKernel;
use factor_lanes::{F32x8, F64x4, F64x8, Kernel, Lanes};
use factor_testing::samples::Sampler;
use rayon::ThreadPool;
use slam_factors::{PluckerLineReprojection, PointReprojection};

#[path = "support/inputs.rs"]
mod inputs;
#[path = "support/plot.rs"]
mod plot;

use clap::Parser;
use factor_testing::rounds::{
    Method, alternate, fail, load_average, median, median_ratio, positive_count,
};
use inputs::tiled;

/// Distinct sampled configurations, repeated to the batch size.
const DISTINCT: usize = 4096;
/// Factors per measurement (about): back-to-back runs of small batches.
const WORK: usize = 1 << 22;
/// The batch sizes by default: 1 and 3 times the powers of 10 up to 10⁶.
/// None is a multiple of 512: a column of `n` `f64` is `8n` bytes long and
/// the columns lie end to end, so with `n` a multiple of 512 every column's
/// row `i` has the same address modulo 4 KiB, and the dozens of streams
/// collide in the same L1 sets (see `--sizes 1000,1024`).
const SIZES: [usize; 11] = [
    10, 30, 100, 300, 1000, 3000, 10_000, 30_000, 100_000, 300_000, 1_000_000,
];

/// The batch of `inputs` with lanes `L`, on `pool` when given.
fn lanes<'a, F, L>(inputs: &'a Columns<L::Scalar>, pool: Option<&'a ThreadPool>) -> Method<'a>
where
    F: WithKernel,
    L: Lanes,
    F::Kernel: Kernel<L> + Kernel<L::Scalar>,
{
    let mut out = JacobianColumns::new::<F>(inputs.len(), &[]);
    let options = if pool.is_some() {
        Options::rayon()
    } else {
        Options::default()
    };
    Box::new(move |reps| {
        let mut run = || {
            for _ in 0..reps {
                linearize::<F, L>(black_box(inputs), &mut out, options).expect("shapes fit");
            }
        };
        match pool {
            Some(pool) => pool.install(run),
            None => run(),
        }
    })
}

/// One factor's table rows and plot panel.
fn factor<F>(
    title: &str,
    base: &Columns<f64>,
    pool: &ThreadPool,
    sizes: &[usize],
    rounds: usize,
) -> plot::Panel
where
    F: WithKernel,
    F::Kernel: Kernel<f64> + Kernel<f32> + Kernel<F64x4> + Kernel<F64x8> + Kernel<F32x8>,
{
    let names = ["scalar", "4×f64", "8×f64", "8×f32", "8×f64, 2 threads"];
    let mut series: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    println!("\n### {title}: factors per second (median of {rounds} rounds)\n");
    println!(
        "| factors | {} | 4×f64 / scalar | 8×f64 / scalar | 8×f32 / scalar | 2 threads / 1 | cores the 2 threads had |",
        names.join(" | ")
    );
    println!("|{}", " --- |".repeat(names.len() + 6));
    for &n in sizes {
        let inputs = tiled(base, n);
        let inputs32 = inputs.map(|x| *x as f32);
        let mut methods = vec![
            lanes::<F, f64>(&inputs, None),
            lanes::<F, F64x4>(&inputs, None),
            lanes::<F, F64x8>(&inputs, None),
            lanes::<F, F32x8>(&inputs32, None),
            lanes::<F, F64x8>(&inputs, Some(pool)),
        ];
        let times = alternate(&mut methods, rounds, (WORK / n).max(1));
        let rates: Vec<f64> = times.wall.iter().map(|t| n as f64 / median(t)).collect();
        for (s, r) in series.iter_mut().zip(&rates) {
            s.push(*r);
        }
        let cells: Vec<String> = rates.iter().map(|r| format!("{:.3e}", r)).collect();
        // Ratios of throughputs: time of the reference / time of the method.
        println!(
            "| {n} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |",
            cells.join(" | "),
            median_ratio(&times.wall[0], &times.wall[1]),
            median_ratio(&times.wall[0], &times.wall[2]),
            median_ratio(&times.wall[0], &times.wall[3]),
            median_ratio(&times.wall[2], &times.wall[4]),
            times.cores(4),
        );
    }
    plot::Panel {
        title: format!("{title} (residual + all Jacobian blocks)"),
        sizes: sizes.to_vec(),
        series: names.iter().map(|s| s.to_string()).zip(series).collect(),
    }
}

/// The command line (`cargo bench` adds `--bench`).
#[derive(Parser)]
struct Args {
    /// Rounds: every method runs once per round, in rotating order.
    #[arg(long, default_value_t = 7, value_parser = positive_count)]
    rounds: usize,
    /// Write the plot of factors/s against the batch size here.
    #[arg(long)]
    svg: Option<PathBuf>,
    /// Batch sizes, comma-separated (default: 10 to 10⁶).
    #[arg(long, value_delimiter = ',', value_parser = positive_count)]
    sizes: Vec<usize>,
    #[arg(long, hide = true)]
    bench: bool,
}

fn main() {
    let Args {
        rounds, svg, sizes, ..
    } = Args::parse();
    let sizes = if sizes.is_empty() {
        SIZES.to_vec()
    } else {
        sizes
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("a pool of 2 threads");
    println!(
        "instruction set: {:?}; load average before: {}",
        factor_batch::detected(),
        load_average()
    );
    let mut s = Sampler::new(1);
    let points: Vec<PointReprojection> = (0..DISTINCT).map(|_| s.point_reprojection()).collect();
    let mut s = Sampler::new(2);
    let lines: Vec<PluckerLineReprojection> = (0..DISTINCT)
        .map(|_| s.plucker_line_reprojection())
        .collect();
    let panels = [
        factor::<PointReprojection>(
            "point reprojection",
            &Columns::from_factors(&points),
            &pool,
            &sizes,
            rounds,
        ),
        factor::<PluckerLineReprojection>(
            "Plücker line reprojection",
            &Columns::from_factors(&lines),
            &pool,
            &sizes,
            rounds,
        ),
    ];
    println!("\nload average after: {}", load_average());
    if let Some(path) = svg {
        plot::write(&path, &panels).unwrap_or_else(|e| fail(&e));
        println!("wrote {}", path.display());
    }
}
