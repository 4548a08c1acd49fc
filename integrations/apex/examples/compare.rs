//! The agreement and speed comparison of `bench-peers/README.md`, in one run
//! on one machine: every shipped data set solved by apex-solver with this
//! project's factors (generated kernels, dual numbers) and with apex's own
//! hand-written factors, and GTSAM 4.3's costs read from the JSON of
//! `bench-peers/gtsam_solve.py`.
//!
//! ```sh
//! cargo run --release --manifest-path integrations/apex/Cargo.toml --example compare -- \
//!     [--data DIR] [--gtsam out/gtsam.json] [--rounds 15] [--max-iterations 1000]
//! ```
//!
//! - **Agreement**: each factor set from the same initial values, run to the
//!   optimum (tolerances 1e-12, at most `--max-iterations`): final cost and
//!   iterations (apex counts every step tried, accepted or rejected), the
//!   relative difference of this project's final cost from apex's own
//!   factors' and from GTSAM's.
//! - **Speed**: the linearization pass, every block's residual and Jacobian
//!   at the initial values, on one thread, through apex's `Factor` trait
//!   (apex's between factor also whitened by its noise model, as apex does
//!   per block), timed `--rounds` times with the three factor sets
//!   alternating; the median pass, the time per observation, and the median
//!   of the per-round ratios to apex's own factors. Then the whole solve
//!   (apex's default tolerances, 100 iterations; all threads), median of
//!   `--rounds / 3` alternating runs, and the linearization pass's wall time
//!   inside it.
//!
//! Not a test: speed ratios are measured side by side here and reported.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use clap::Parser;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use factor_apex::Kernels;
use factor_apex::problems::{BuildOptions, Built, FactorChoice, KeptBlock, build};
use factor_apex::solve::{SolveOptions, solve};

/// The shipped data sets, by the file that names each.
const DATA_SETS: [&str; 5] = [
    "dubrovnik-3-7-pre.txt",
    "Balbianello.out",
    "pose3example.txt",
    "sphere2500.txt",
    "VO_camera_poses_large.txt",
];

const CHOICES: [FactorChoice; 3] = [
    FactorChoice::Ours(Kernels::Generated),
    FactorChoice::Ours(Kernels::Dual),
    FactorChoice::Apex,
];

/// The comparison's options.
#[derive(Parser)]
#[command(about = "Agreement and speed of this project's factors against apex-solver's own")]
struct Args {
    /// The directory of the shipped data sets.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data"))]
    data: PathBuf,
    /// GTSAM 4.3's results, written by `bench-peers/gtsam_solve.py`.
    #[arg(long)]
    gtsam: Option<PathBuf>,
    /// Timed rounds of the linearization pass (a third as many whole solves).
    #[arg(long, default_value_t = 15)]
    rounds: usize,
    /// The most iterations of the agreement runs.
    #[arg(long, default_value_t = 1000)]
    max_iterations: usize,
}

/// GTSAM's `final_cost` and `iterations` per data set, from the script's
/// JSON (`{"<data set>": {"final_cost": …, "iterations": …, …}, …}`).
fn read_gtsam(path: &Path) -> Result<HashMap<String, (f64, u64)>, String> {
    let at = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let text = std::fs::read_to_string(path).map_err(|e| at(&e))?;
    let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| at(&e))?;
    let mut out = HashMap::new();
    for name in DATA_SETS {
        let entry = &json[name];
        if let (Some(cost), Some(iterations)) =
            (entry["final_cost"].as_f64(), entry["iterations"].as_u64())
        {
            out.insert(name.to_owned(), (cost, iterations));
        }
    }
    Ok(out)
}

fn build_for(data: &slam_data::Problem, factors: FactorChoice, keep: bool) -> Option<Built> {
    build(
        data,
        &BuildOptions {
            factors,
            robust: None,
            keep_blocks: keep,
        },
    )
    .ok()
}

/// One linearization pass over `blocks` on this thread.
fn linearization_pass(blocks: &[KeptBlock]) -> Duration {
    let mut residual = [0.0; 16];
    let mut jacobian = [0.0; 512];
    let start = Instant::now();
    for block in blocks {
        let (rows, cols) = block.factor.jacobian_shape();
        let params: Vec<&[f64]> = block.params.iter().map(Vec::as_slice).collect();
        let (r, j) = (&mut residual[..rows], &mut jacobian[..rows * cols]);
        block.factor.linearize(
            &params,
            r,
            Some(faer::mat::MatMut::from_column_major_slice_mut(
                j, rows, cols,
            )),
        );
        block.noise.whiten_residual(r);
        block.noise.whiten_jacobian(j, rows, cols);
    }
    std::hint::black_box(&jacobian);
    start.elapsed()
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(f64::NAN)
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn agreement(
    args: &Args,
    problems: &[(&str, slam_data::Problem)],
    gtsam: &HashMap<String, (f64, u64)>,
) {
    println!(
        "## Agreement: from the same initial values, to the optimum (tolerances 1e-12, at most {} iterations)\n",
        args.max_iterations
    );
    println!(
        "| data set | generated: final cost (iterations) | dual | apex's own factors | generated vs apex | GTSAM 4.3 (iterations) | generated vs GTSAM |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    for (name, data) in problems {
        let mut cells = Vec::new();
        let mut finals = Vec::new();
        for choice in CHOICES {
            match build_for(data, choice, false) {
                Some(mut built) => {
                    let options = SolveOptions::converged(args.max_iterations);
                    match solve(&mut built, &options, |_| {}) {
                        Ok(o) => {
                            let limit = if o.iterations >= args.max_iterations {
                                ", limit"
                            } else {
                                ""
                            };
                            cells.push(format!("{:.12e} ({}{limit})", o.final_cost, o.iterations));
                            finals.push(Some(o.final_cost));
                        }
                        Err(e) => {
                            cells.push(format!("failed: {e}"));
                            finals.push(None);
                        }
                    }
                }
                None => {
                    cells.push("—".to_owned());
                    finals.push(None);
                }
            }
        }
        let vs_apex = match (finals[0], finals[2]) {
            (Some(g), Some(a)) => format!("{:.1e}", relative(g, a)),
            _ => "—".to_owned(),
        };
        let (gtsam_cell, vs_gtsam) = match (gtsam.get(*name), finals[0]) {
            (Some((cost, iterations)), Some(g)) => (
                format!("{cost:.12e} ({iterations})"),
                format!("{:.1e}", relative(g, *cost)),
            ),
            _ => ("—".to_owned(), "—".to_owned()),
        };
        println!(
            "| {name} | {} | {} | {} | {vs_apex} | {gtsam_cell} | {vs_gtsam} |",
            cells[0], cells[1], cells[2]
        );
    }
    println!();
}

fn speed(args: &Args, problems: &[(&str, slam_data::Problem)]) {
    println!(
        "## Speed: one linearization pass at the initial values, one thread, median of {} alternating rounds\n",
        args.rounds
    );
    println!(
        "| data set | blocks | generated | dual | apex's own | generated / apex (median of rounds) | dual / apex |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    for (name, data) in problems {
        let built: Vec<Option<Built>> = CHOICES.iter().map(|c| build_for(data, *c, true)).collect();
        let blocks: Vec<Option<&[KeptBlock]>> = built
            .iter()
            .map(|b| b.as_ref().and_then(|b| b.kept.as_deref()))
            .collect();
        let count = blocks[0].map_or(0, <[KeptBlock]>::len);
        let mut times: Vec<Vec<f64>> = vec![Vec::new(); 3];
        for round in 0..args.rounds {
            for k in 0..3 {
                let which = (k + round) % 3;
                if let Some(b) = blocks[which] {
                    times[which].push(linearization_pass(b).as_secs_f64());
                }
            }
        }
        let cell = |t: &[f64]| {
            if t.is_empty() {
                "—".to_owned()
            } else {
                let m = median(t.to_vec());
                format!(
                    "{:.3} ms ({:.0} ns/obs)",
                    m * 1e3,
                    m / count.max(1) as f64 * 1e9
                )
            }
        };
        let ratio = |a: &[f64], b: &[f64]| {
            if a.is_empty() || b.is_empty() {
                "—".to_owned()
            } else {
                format!(
                    "{:.2}",
                    median(a.iter().zip(b).map(|(x, y)| x / y).collect())
                )
            }
        };
        println!(
            "| {name} | {count} | {} | {} | {} | {} | {} |",
            cell(&times[0]),
            cell(&times[1]),
            cell(&times[2]),
            ratio(&times[0], &times[2]),
            ratio(&times[1], &times[2])
        );
    }
    println!();
    let runs = (args.rounds / 3).max(1);
    println!(
        "## Speed: whole solves (apex's default tolerances, at most 100 iterations, all threads), median of {runs} alternating runs\n"
    );
    println!(
        "| data set | generated: solve (iterations; linearization per pass) | dual | apex's own | generated / apex (solve) |"
    );
    println!("| --- | --- | --- | --- | --- |");
    for (name, data) in problems {
        let mut totals: Vec<Vec<f64>> = vec![Vec::new(); 3];
        let mut detail: Vec<String> = vec!["—".to_owned(); 3];
        for round in 0..runs {
            for k in 0..3 {
                let which = (k + round) % 3;
                let Some(mut built) = build_for(data, CHOICES[which], false) else {
                    continue;
                };
                let Ok(outcome) = solve(&mut built, &SolveOptions::default(), |_| {}) else {
                    continue;
                };
                let passes = outcome.history.len().max(1) as f64;
                let linearization: f64 = outcome
                    .history
                    .iter()
                    .map(|it| it.linearization.as_secs_f64())
                    .sum();
                totals[which].push(outcome.elapsed.as_secs_f64());
                detail[which] = format!(
                    "({}; {:.3} ms)",
                    outcome.iterations,
                    linearization / passes * 1e3
                );
            }
        }
        let cell = |k: usize| {
            if totals[k].is_empty() {
                "—".to_owned()
            } else {
                format!("{:.4} s {}", median(totals[k].clone()), detail[k])
            }
        };
        let ratio = if totals[0].is_empty() || totals[2].is_empty() {
            "—".to_owned()
        } else {
            format!(
                "{:.2}",
                median(totals[0].clone()) / median(totals[2].clone())
            )
        };
        println!(
            "| {name} | {} | {} | {} | {ratio} |",
            cell(0),
            cell(1),
            cell(2)
        );
    }
}

fn main() -> ExitCode {
    let args = Args::parse();
    let gtsam = match &args.gtsam {
        Some(path) => match read_gtsam(path) {
            Ok(costs) => costs,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        },
        None => HashMap::new(),
    };
    let mut problems = Vec::new();
    for name in DATA_SETS {
        match slam_data::Problem::read(args.data.join(name), None) {
            Ok(p) => problems.push((name, p)),
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        }
    }
    println!(
        "apex-solver 1.5, {} threads; this project's factors served by factor-apex\n",
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    agreement(&args, &problems, &gtsam);
    speed(&args, &problems);
    ExitCode::SUCCESS
}
