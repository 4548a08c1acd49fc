//! The memory limit: 10⁷ point-reprojection factors (`f64`; inputs and
//! outputs 2.9 GB, far larger than the caches) through
//! `factor_batch::linearize`, against a streaming-copy loop over the same
//! bytes in the same run.
//!
//! Bytes per factor: the 16 input columns read (128 B) and the 20 output
//! columns written (residual 2, pose block 12, point block 6: 160 B), 288 B.
//! The copy loop moves exactly those bytes with no arithmetic: output
//! column `k` is copied from input column `k mod 16` (the last four from
//! inputs just read, in cache), in chunks of `factor_batch::CHUNK` rows,
//! column by column in each (`memcpy`s of 16 KiB: one stream at a time,
//! the memory's best case). Both write with ordinary stores, so both also
//! pay the write-allocate read of each output line. Achieved GB/s =
//! 288 B × 10⁷ / time; the kernel's fraction is its GB/s over the copy's on as many
//! threads.
//!
//! Methods, each on 1 thread and on 2 (rayon's pool of 2 for the batch;
//! the rows split in two halves for the copy): the batch with `F64x4` and
//! `F64x8`, and the copy. Inputs: 4096 sampled configurations repeated to
//! 10⁷ rows. Wall time of one pass over the 10⁷ factors; in each round every
//! method once, in rotating order (the machine is shared); medians over the
//! rounds, the median per-round ratio to the copy, and the cores each
//! method had (the process's CPU time over the wall time: below 2 on 2
//! threads when another process held a core).
//!
//! ```sh
//! cargo bench -p factor-batch --bench stream -- [--rounds 7] [--factors 10000000]
//! ```

use std::cell::RefCell;
use std::hint::black_box;

use factor_batch::{CHUNK, Columns, JacobianColumns, Options, linearize};
use factor_lanes::{F64x4, F64x8, Lanes};
use factor_testing::samples::Sampler;
use rayon::ThreadPool;
use slam_factors::PointReprojection;

#[path = "support/inputs.rs"]
mod inputs;

use clap::Parser;
use factor_testing::rounds::{
    Method, alternate, load_average, median, median_ratio, positive_count,
};
use inputs::tiled;

/// Input and output columns of the point factor.
const INPUTS: usize = 16;
const OUTPUTS: usize = 20;
/// Bytes moved per factor: inputs read and outputs written, `f64`.
const BYTES: usize = (INPUTS + OUTPUTS) * 8;

/// The copy loop over one range of rows: output column `k` from input
/// column `k mod 16`, chunk by chunk, column by column in each chunk.
fn copy_rows(inputs: &[&[f64]], outputs: &mut [&mut [f64]]) {
    let len = inputs[0].len();
    for start in (0..len).step_by(CHUNK) {
        let rows = start..(start + CHUNK).min(len);
        for (k, output) in outputs.iter_mut().enumerate() {
            output[rows.clone()].copy_from_slice(&inputs[k % INPUTS][rows.clone()]);
        }
    }
}

/// One thread's rows: the input and the output columns.
type Piece<'a> = (Vec<&'a [f64]>, Vec<&'a mut [f64]>);

/// The copy loop over all rows, split into `threads` ranges of rows, one
/// per thread.
fn copy(inputs: &Columns<f64>, outputs: &mut JacobianColumns<f64>, threads: usize) {
    let part = inputs.len().div_ceil(threads);
    let mut pieces: Vec<Piece<'_>> = (0..threads).map(|_| (Vec::new(), Vec::new())).collect();
    for column in inputs.columns() {
        for (piece, rows) in pieces.iter_mut().zip(column.chunks(part)) {
            piece.0.push(rows);
        }
    }
    let columns = outputs.residual.columns_mut().chain(
        outputs
            .blocks
            .iter_mut()
            .flatten()
            .flat_map(Columns::columns_mut),
    );
    for column in columns {
        for (piece, rows) in pieces.iter_mut().zip(column.chunks_mut(part)) {
            piece.1.push(rows);
        }
    }
    std::thread::scope(|scope| {
        for (ins, mut outs) in pieces {
            scope.spawn(move || copy_rows(&ins, &mut outs));
        }
    });
}

/// The batch with lanes `L` into the shared outputs, on `pool` when given.
fn batch<'a, L>(
    inputs: &'a Columns<f64>,
    outputs: &'a RefCell<JacobianColumns<f64>>,
    pool: Option<&'a ThreadPool>,
) -> Method<'a>
where
    L: Lanes<Scalar = f64>,
    <PointReprojection as factor_core::WithKernel>::Kernel: factor_lanes::Kernel<L>,
{
    let options = if pool.is_some() {
        Options::rayon()
    } else {
        Options::default()
    };
    Box::new(move |reps| {
        let mut guard = outputs.borrow_mut();
        let out: &mut JacobianColumns<f64> = &mut guard;
        let mut run = || {
            for _ in 0..reps {
                linearize::<PointReprojection, L>(black_box(inputs), out, options)
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
    /// Rounds: every method runs once per round, in rotating order.
    #[arg(long, default_value_t = 7, value_parser = positive_count)]
    rounds: usize,
    /// Point factors per pass.
    #[arg(long, default_value_t = 10_000_000, value_parser = positive_count)]
    factors: usize,
    #[arg(long, hide = true)]
    bench: bool,
}

fn main() {
    let Args {
        rounds, factors, ..
    } = Args::parse();
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
    let sampled: Vec<PointReprojection> = (0..4096).map(|_| s.point_reprojection()).collect();
    let inputs = tiled(&Columns::from_factors(&sampled), factors);
    let outputs = RefCell::new(JacobianColumns::new::<PointReprojection>(factors, &[]));
    let names = [
        "copy loop, 1 thread",
        "batch 4×f64, 1 thread",
        "batch 8×f64, 1 thread",
        "copy loop, 2 threads",
        "batch 4×f64, 2 threads",
        "batch 8×f64, 2 threads",
    ];
    let copy_on = |threads: usize| -> Method<'_> {
        let (inputs, outputs) = (&inputs, &outputs);
        Box::new(move |reps| {
            for _ in 0..reps {
                copy(black_box(inputs), &mut outputs.borrow_mut(), threads);
            }
        })
    };
    let mut methods = vec![
        copy_on(1),
        batch::<F64x4>(&inputs, &outputs, None),
        batch::<F64x8>(&inputs, &outputs, None),
        copy_on(2),
        batch::<F64x4>(&inputs, &outputs, Some(&pool)),
        batch::<F64x8>(&inputs, &outputs, Some(&pool)),
    ];
    let times = alternate(&mut methods, rounds, 1);
    let gigabytes = (BYTES * factors) as f64 / 1e9;
    println!(
        "\n{factors} point factors, {BYTES} B each (inputs {} B read, outputs {} B written): \
         {gigabytes:.2} GB per pass; median of {rounds} rounds\n",
        INPUTS * 8,
        OUTPUTS * 8
    );
    println!(
        "| method | time per pass | ns per factor | GB/s | fraction of the copy loop's GB/s | cores it had |"
    );
    println!("| --- | --- | --- | --- | --- | --- |");
    for (k, name) in names.iter().enumerate() {
        let t = median(&times.wall[k]);
        // The copy on as many threads: method 0 (1 thread) or 3.
        let copy = if k < 3 { 0 } else { 3 };
        println!(
            "| {name} | {:.1} ms | {:.2} | {:.1} | {:.2} | {:.2} |",
            t * 1e3,
            t / factors as f64 * 1e9,
            gigabytes / t,
            median_ratio(&times.wall[copy], &times.wall[k]),
            times.cores(k),
        );
    }
    println!("\nload average after: {}", load_average());
}
