//! Peak memory of reading, building and solving one problem, with this
//! project's factors or apex-solver's own: the figures of
//! `docs/guide/hostile-input.md` (bytes per observation, the adapter's
//! share of the peak).
//!
//! ```sh
//! cargo run --release --manifest-path integrations/apex/Cargo.toml --bin memory -- \
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

use factor_apex::Kernels;
use factor_apex::problems::{BuildOptions, FactorChoice, build};
use factor_apex::solve::{SolveOptions, solve};

struct Args {
    file: String,
    factors: FactorChoice,
    max_iterations: usize,
}

fn parse_args() -> Result<Args, String> {
    let usage = "usage: memory FILE [--factors generated|dual|apex] [--max-iterations N]";
    let mut file = None;
    let mut factors = FactorChoice::Ours(Kernels::Generated);
    let mut max_iterations = 1;
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = || {
            it.next()
                .ok_or_else(|| format!("{arg} needs a value; {usage}"))
        };
        match arg.as_str() {
            "--factors" => {
                factors = match value()?.as_str() {
                    "generated" => FactorChoice::Ours(Kernels::Generated),
                    "dual" => FactorChoice::Ours(Kernels::Dual),
                    "apex" => FactorChoice::Apex,
                    other => return Err(format!("--factors: unknown `{other}`; {usage}")),
                }
            }
            "--max-iterations" => {
                max_iterations = value()?
                    .parse()
                    .map_err(|_| format!("--max-iterations: not a count; {usage}"))?
            }
            _ if file.is_none() && !arg.starts_with("--") => file = Some(arg),
            other => return Err(format!("unexpected argument `{other}`; {usage}")),
        }
    }
    Ok(Args {
        file: file.ok_or(usage)?,
        factors,
        max_iterations,
    })
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
    println!("{}: factors {}", args.file, args.factors.name());
    let data = slam_data::Problem::read(&args.file, None).map_err(|e| e.to_string())?;
    let blocks = data.measurements();
    report("read", blocks, start);
    let options = BuildOptions {
        factors: args.factors,
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
    match parse_args().and_then(|args| run(&args)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
