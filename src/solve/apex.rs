//! The general path: the problem built for apex-solver through the adapter
//! of crate `factor-apex`, solved by its Levenberg–Marquardt; g2o's line and
//! plane graphs and problem files ([`super::problem_file`]) take it always.

use factor_apex::built::Built;
use factor_apex::problems::g2o_addons;
use factor_apex::problems::{self, BuildError, BuildOptions, FactorChoice};
use factor_apex::solve::{Outcome, SolveOptions, solve};
use slam_problems::ProblemError;
use slamjac_problem::field_path::shown_path;

use super::{SolveArgs, at, finish, finish_file, problem_file, progress, report};
use crate::error::CliError;
use crate::registry::Registry;
use slamjac_problem::truth::Truth;

/// Builds, solves and reports `data` with apex-solver, against `truth`
/// where there is one.
pub(super) fn run(
    args: &SolveArgs,
    data: &slam_data::Problem,
    truth: Option<&Truth>,
) -> Result<String, CliError> {
    let options = build_options(args);
    let built = match data {
        slam_data::Problem::G2oAddons(graph) => {
            g2o_addons::build_with(graph, &options, args.landmarks)
                .map(|b| b.map_keys(problems::Keys::G2oAddons))
        }
        _ => problems::build(data, &options),
    };
    let mut built = built.map_err(|e| match e {
        BuildError::Problem(ProblemError::Data(_) | ProblemError::Unavailable(_)) => {
            CliError::Usage(at(&args.file, e))
        }
        // Degenerate geometry, the solver's or the adapter's refusal.
        _ => CliError::Solve(at(&args.file, e)),
    })?;
    let setup = report::Setup {
        blocks: built.blocks,
        solver: format!("(apex-solver), {:?}", built.linear_solver),
        initial_cost: built.initial_cost,
    };
    progress::print(&report::header(&args.file, data, &setup, args));
    let outcome = solve_built(args, &mut built)?;
    let solved = built.write_back(data, &outcome.values);
    finish(args, data, &solved, truth, &finished(&built, &outcome))
}

/// Reads, solves and reports a problem file, and writes it back with the
/// solution (`--output`).
pub(super) fn run_problem_file(args: &SolveArgs, registry: &Registry) -> Result<String, CliError> {
    let mut problem = problem_file::read(&args.file, &build_options(args), registry)?;
    let built = &mut problem.built;
    let [kernels, duals] = problem.linearized_by;
    progress::print(&format!(
        "{} (problem file): {} blocks, {kernels} through generated kernels and {duals} through \
         dual numbers in apex-solver's chart; Levenberg–Marquardt (apex-solver), {:?}; initial \
         cost {:.10e}",
        shown_path(&args.file),
        built.blocks,
        built.linear_solver,
        built.initial_cost
    ));
    let outcome = solve_built(args, built)?;
    let finished = finished(&problem.built, &outcome);
    let solved = problem.solved_variables(&outcome.values);
    let check = || problem.check_solution(&outcome.values, &finished.verdict);
    let truth = problem.truth_errors(&solved);
    finish_file(args, &finished, check, truth, || problem.written(&solved))
}

fn build_options(args: &SolveArgs) -> BuildOptions {
    BuildOptions {
        factors: FactorChoice::Ours(args.kernels),
        robust: args.robust,
        keep_blocks: false,
    }
}

/// Solves `built` with the iteration limit of `args`, with progress.
fn solve_built<K>(args: &SolveArgs, built: &mut Built<K>) -> Result<Outcome, CliError> {
    let options = SolveOptions {
        max_iterations: args.max_iterations,
        ..SolveOptions::default()
    };
    let mut progress = progress::Progress::new(args.max_iterations, built.blocks);
    let outcome = solve(built, &options, progress.callback())
        .map_err(|e| CliError::Solve(at(&args.file, format!("the solve stopped: {e}"))))?;
    progress.finish();
    Ok(outcome)
}

/// What the summary says of `outcome`, a solve of `built`.
fn finished<'a, K>(built: &'a Built<K>, outcome: &'a Outcome) -> report::Finished<'a> {
    report::Finished {
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
    }
}
