//! Peak memory of reading, building and solving one problem, with this
//! project's factors or apex-solver's own: the figures of
//! `docs/guide/hostile-input.md` (bytes per observation, the adapter's
//! share of the peak).
//!
//! ```sh
//! cargo run --release --manifest-path integrations/apex/Cargo.toml --example memory -- \
//!     FILE [--factors generated|dual|apex] [--max-iterations N]
//! ```
//!
//! Prints the process's peak resident memory (Linux `VmHWM`) after reading
//! the file, after building the problem and after solving it (at most
//! `--max-iterations`, default 1; 0 builds only), each also per residual
//! block. A peak is the process's own, so measure one factor choice per run
//! and compare runs side by side. Not a test.

use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, ValueEnum};

use factor_apex::Kernels;
use factor_apex::problems::{BuildOptions, FactorChoice, build};
use factor_apex::solve::{SolveOptions, solve};

/// What to measure.
#[derive(Parser)]
#[command(about = "Peak memory of reading, building and solving one problem")]
struct Args {
    /// The data file (any format `slamjac solve` reads).
    file: String,
    /// Whose factors: this project's generated kernels or dual numbers, or
    /// apex-solver's own.
    #[arg(long, value_enum, default_value_t = Factors::Generated)]
    factors: Factors,
    /// Iterations of the solve (0: build only).
    #[arg(long, default_value_t = 1)]
    max_iterations: usize,
}

/// `--factors`.
#[derive(Clone, Copy, ValueEnum)]
enum Factors {
    Generated,
    Dual,
    Apex,
}

impl Factors {
    fn choice(self) -> FactorChoice {
        match self {
            Factors::Generated => FactorChoice::Ours(Kernels::Generated),
            Factors::Dual => FactorChoice::Ours(Kernels::Dual),
            Factors::Apex => FactorChoice::Apex,
        }
    }
}

/// The peak resident memory so far, bytes (Linux `VmHWM`).
fn peak() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

fn report(stage: &str, blocks: usize, start: Instant) {
    match peak() {
        Some(bytes) => println!(
            "{stage:<8} peak {:>9.1} MiB  {:>7.0} bytes per block  ({:.2} s)",
            bytes as f64 / 1048576.0,
            bytes as f64 / blocks.max(1) as f64,
            start.elapsed().as_secs_f64()
        ),
        None => println!("{stage:<8} peak memory unknown (no /proc/self/status)"),
    }
}

fn run(args: &Args) -> Result<(), String> {
    let start = Instant::now();
    println!("{}: factors {}", args.file, args.factors.choice().name());
    let data = slam_data::Problem::read(&args.file, None).map_err(|e| e.to_string())?;
    let blocks = data.measurements();
    report("read", blocks, start);
    let options = BuildOptions {
        factors: args.factors.choice(),
        robust: None,
        keep_blocks: false,
    };
    let mut built = build(&data, &options).map_err(|e| e.to_string())?;
    report("build", blocks, start);
    if args.max_iterations > 0 {
        let options = SolveOptions {
            max_iterations: args.max_iterations,
            ..SolveOptions::default()
        };
        let outcome = solve(&mut built, &options, |_| {}).map_err(|e| e.to_string())?;
        report("solve", blocks, start);
        println!(
            "{blocks} blocks, {} iterations, cost {:.10e} → {:.10e}",
            outcome.iterations, outcome.initial_cost, outcome.final_cost
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
