//! The general path: the problem built for apex-solver through the adapter
//! of crate `factor-apex`, solved by its Levenberg–Marquardt.

use factor_apex::problems::{self, BuildError, BuildOptions, FactorChoice};
use factor_apex::solve::{SolveOptions, solve};

use super::{SolveArgs, at, finish, progress, report};
use crate::error::CliError;

/// Builds, solves and reports `data` with apex-solver.
pub(super) fn run(args: &SolveArgs, data: &slam_data::Problem) -> Result<String, CliError> {
    let options = BuildOptions {
        factors: FactorChoice::Ours(args.kernels),
        robust: args.robust,
        keep_blocks: false,
    };
    let mut built = problems::build(data, &options).map_err(|e| match e {
        BuildError::Data(_) | BuildError::Unavailable(_) => CliError::Usage(at(&args.file, e)),
        BuildError::Degenerate { .. } | BuildError::Solver(_) | BuildError::Adapter(_) => {
            CliError::Solve(at(&args.file, e))
        }
    })?;
    let before = problems::reprojection_errors(data);
    let setup = report::Setup {
        blocks: built.blocks,
        solver: format!("(apex-solver), {:?}", built.linear_solver),
        initial_cost: built.initial_cost,
    };
    progress::print(&report::header(&args.file, data, &setup, args));
    let options = SolveOptions {
        max_iterations: args.max_iterations,
        ..SolveOptions::default()
    };
    let mut progress = progress::Progress::new(args.max_iterations, built.blocks);
    let outcome = solve(&mut built, &options, progress.callback())
        .map_err(|e| CliError::Solve(at(&args.file, format!("the solve stopped: {e}"))))?;
    progress.finish();
    let solved = built.write_back(data, &outcome.values);
    let finished = report::Finished {
        verdict: outcome.verdict(),
        iterations: outcome.iterations,
        elapsed: outcome.elapsed,
        initial_cost: outcome.initial_cost,
        final_cost: outcome.final_cost,
        history: &outcome.history,
        blocks: built.blocks,
        rejected: built.rejections.count(),
        first_rejection: built.rejections.first(),
        extra: Vec::new(),
    };
    finish(args, &solved, before, &finished)
}
