//! What apex-solver offers for bundle adjustment, one configuration per
//! process (so that `/usr/bin/time -v` gives each its peak memory): the BAL
//! or Bundler file built as `slamjac solve` builds it (this project's
//! generated kernels, camera 0's pose fixed), then solved with apex's
//! Levenberg–Marquardt or dog-leg and the linear solver named.
//!
//! ```sh
//! cargo bench --manifest-path integrations/schur/Cargo.toml --bench apex_options -- \
//!     --config lm-sparse FILE                      # RAYON_NUM_THREADS=1 for one thread
//! ```
//!
//! Configurations (`--config`): `lm-sparse` (apex's `ExplicitSparseSchur`,
//! variant `Sparse`: what `slamjac solve` used), `lm-iterative`
//! (`ExplicitSparseSchur`, variant `Iterative`, Schur–Jacobi PCG),
//! `lm-chunked` (variant `Chunked`), `lm-implicit-none`,
//! `lm-implicit-block`, `lm-implicit-schur-jacobi` (`ImplicitSparseSchur`
//! with each preconditioner), `lm-cholesky` (no Schur complement: sparse
//! Cholesky of the whole system) and `dogleg-sparse` (dog-leg with the
//! explicit sparse Schur). apex's default tolerances (Ceres'), at most
//! `--max-iterations` (100). Prints one JSON line.

use std::path::PathBuf;
use std::time::Instant;

use apex_solver::linalg::{ExplicitSchurVariant, LinearSolverType, SchurPreconditioner};
use apex_solver::optimizer::dog_leg::{DogLeg, DogLegConfig};
use apex_solver::optimizer::levenberg_marquardt::{LevenbergMarquardt, LevenbergMarquardtConfig};
use clap::Parser;
use factor_apex::Kernels;
use factor_apex::problems::{BuildOptions, FactorChoice, build};
use factor_testing::rounds::fail;

/// The command line (`cargo bench` adds `--bench`).
#[derive(Parser)]
struct Args {
    /// The BAL or Bundler file.
    file: PathBuf,
    /// The configuration (see the module documentation).
    #[arg(long)]
    config: String,
    /// The most iterations.
    #[arg(long, default_value_t = 100)]
    max_iterations: usize,
    #[arg(long, hide = true)]
    bench: bool,
}

/// apex's linear solver and explicit-Schur variant and preconditioner for
/// a configuration name.
fn linear_solver(
    config: &str,
) -> Option<(LinearSolverType, ExplicitSchurVariant, SchurPreconditioner)> {
    use ExplicitSchurVariant as V;
    use LinearSolverType as L;
    use SchurPreconditioner as P;
    Some(match config {
        "lm-sparse" | "dogleg-sparse" => (L::ExplicitSparseSchur, V::Sparse, P::SchurJacobi),
        "lm-iterative" => (L::ExplicitSparseSchur, V::Iterative, P::SchurJacobi),
        "lm-chunked" => (L::ExplicitSparseSchur, V::Chunked, P::SchurJacobi),
        "lm-implicit-none" => (L::ImplicitSparseSchur, V::Sparse, P::None),
        "lm-implicit-block" => (L::ImplicitSparseSchur, V::Sparse, P::BlockDiagonal),
        "lm-implicit-schur-jacobi" => (L::ImplicitSparseSchur, V::Sparse, P::SchurJacobi),
        "lm-cholesky" => (L::SparseCholesky, V::Sparse, P::SchurJacobi),
        _ => return None,
    })
}

fn main() {
    let args = Args::parse();
    let start = Instant::now();
    let data = slam_data::Problem::read(&args.file, None).unwrap_or_else(|e| fail(&e.to_string()));
    let options = BuildOptions {
        factors: FactorChoice::Ours(Kernels::Generated),
        robust: None,
        keep_blocks: false,
    };
    let mut built = build(&data, &options).unwrap_or_else(|e| fail(&e.to_string()));
    let built_at = start.elapsed().as_secs_f64();
    let (solver, variant, preconditioner) = linear_solver(&args.config)
        .unwrap_or_else(|| fail(&format!("unknown configuration `{}`", args.config)));
    // apex stops after the iteration whose 0-based index reaches its limit.
    let limit = args.max_iterations.saturating_sub(1);
    let solve_start = Instant::now();
    let result = if args.config.starts_with("dogleg") {
        let config = DogLegConfig::new()
            .with_linear_solver_type(solver)
            .with_schur_variant(variant)
            .with_schur_preconditioner(preconditioner)
            .with_max_iterations(limit);
        DogLeg::with_config(config).optimize(&mut built.problem)
    } else {
        let config = LevenbergMarquardtConfig::new()
            .with_linear_solver_type(solver)
            .with_schur_variant(variant)
            .with_schur_preconditioner(preconditioner)
            .with_max_iterations(limit);
        LevenbergMarquardt::with_config(config).optimize(&mut built.problem)
    };
    let solve = solve_start.elapsed().as_secs_f64();
    match result {
        Ok(result) => println!(
            "{{\"file\": \"{}\", \"config\": \"{}\", \"threads\": {}, \"initial_cost\": {:.15e}, \
             \"final_cost\": {:.15e}, \"iterations\": {}, \"status\": \"{}\", \"build_s\": {built_at:.3}, \
             \"solve_s\": {solve:.3}}}",
            args.file.display(),
            args.config,
            rayon_threads(),
            result.initial_cost,
            result.final_cost,
            result.iterations,
            result.status
        ),
        Err(e) => fail(&format!("{}: apex-solver: {e}", args.config)),
    }
}

/// The threads of rayon's global pool (apex's parallel passes).
fn rayon_threads() -> usize {
    std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}
