//! The path of every data set: crate `factor-schur` (Levenberg–Marquardt
//! with the landmarks, where there are any, eliminated by a Schur
//! complement formed straight from the fused normal-equation kernels in
//! lane batches or from each factor's Jacobians, the reduced system by
//! faer's Cholesky).

use factor_minimizer::SolveOptions;
use factor_schur::problems::BuildError;
use factor_schur::{Linearized, Outcome, Profile, Solver};
use slam_problems::ProblemError;

use super::progress::duration;
use super::{SolveArgs, at, finish, progress, report};
use crate::error::CliError;
use slamjac_problem::truth::Truth;

/// The solver in words, for the header: how many of the `variables` are
/// eliminated (none: a pose graph), how each factor type is linearized
/// (`Problem::linearized`), and the reduced system's factorization
/// (`Solver::linear_solver`).
pub(super) fn solver_words(
    eliminated: usize,
    variables: usize,
    linearized: &[(&str, usize, Linearized)],
    factorization: &str,
) -> String {
    // The factor types by how they are linearized, in order of first
    // appearance: a method alone when every type shares it.
    let mut by_method: Vec<(Linearized, Vec<&str>)> = Vec::new();
    for &(name, _, method) in linearized {
        match by_method.iter_mut().find(|(m, _)| *m == method) {
            Some((_, names)) => names.push(name),
            None => by_method.push((method, vec![name])),
        }
    }
    let how = match &by_method[..] {
        [(only, _)] => only.describe().to_owned(),
        _ => by_method
            .iter()
            .map(|(method, names)| format!("{} by {}", names.join(", "), method.describe()))
            .collect::<Vec<_>>()
            .join("; "),
    };
    if eliminated > 0 {
        format!(
            "(Schur complement: {eliminated} of {variables} variables eliminated, {how}, \
             {factorization})"
        )
    } else {
        format!("(factor-schur: nothing to eliminate, {how}, {factorization})")
    }
}

/// Builds, solves and reports `data` with the Schur-complement solver
/// (its ground truth, where it has one, is `truth`).
pub(super) fn run(
    args: &SolveArgs,
    data: &slam_data::Problem,
    truth: Option<&Truth>,
) -> Result<String, CliError> {
    let built = factor_schur::problems::build_with(data, args.robust, args.kernels, args.landmarks);
    let mut built = built.map_err(|e| match e {
        BuildError::Problem(ProblemError::Data(_) | ProblemError::Unavailable(_)) => {
            CliError::Usage(at(&args.file, e))
        }
        // Degenerate geometry, the solver's or the adapter's refusal.
        _ => CliError::Solve(at(&args.file, e)),
    })?;
    let blocks = built.blocks;
    let eliminated = built.problem.eliminated_count();
    let variables = built.problem.variable_count();
    let linearized = built.problem.linearized();
    let solver = Solver::new(&mut built.problem)
        .map_err(|e| CliError::Solve(at(&args.file, format!("the solve cannot start: {e}"))))?;
    let setup = report::Setup {
        blocks,
        solver: solver_words(eliminated, variables, &linearized, &solver.linear_solver()),
        initial_cost: solver.initial_cost(),
    };
    progress::print(&report::header(&args.file, data, &setup, args));
    let outcome = iterate(args, solver, blocks);
    let solved = built.write_back(data);
    let finished = finished(&outcome, blocks);
    finish(args, data, &solved, truth, &finished)
}

/// Runs `solver` with the command line's options (`args`), its progress
/// over `blocks` blocks shown.
pub(super) fn iterate(args: &SolveArgs, solver: Solver<'_>, blocks: usize) -> Outcome {
    let options = SolveOptions {
        max_iterations: args.max_iterations,
        ..SolveOptions::default()
    };
    let mut progress = progress::Progress::new(args.max_iterations, blocks);
    let outcome = solver.run(&options, progress.callback());
    progress.finish();
    outcome
}

/// What the report needs of `outcome`, a solve of `blocks` blocks.
pub(super) fn finished(outcome: &Outcome, blocks: usize) -> report::Finished<'_> {
    report::Finished {
        verdict: outcome.verdict.clone(),
        iterations: outcome.iterations,
        elapsed: outcome.elapsed,
        initial_cost: outcome.initial_cost,
        final_cost: outcome.final_cost,
        history: &outcome.history,
        blocks,
        rejected: outcome.rejected,
        first_rejection: outcome.first_rejection.as_deref(),
        extra: breakdown(&outcome.profile, outcome.elapsed),
    }
}

/// Where the solve's time went: the fused kernels' share, and each part.
fn breakdown(p: &Profile, elapsed: std::time::Duration) -> Vec<String> {
    let share = |d: std::time::Duration| 100.0 * d.as_secs_f64() / elapsed.as_secs_f64().max(1e-12);
    vec![
        format!(
            "  factor kernels (fused in 4×f64 lane batches, or per factor): {}{} ({:.1}% of the \
             solve), within linearization passes of {} in all",
            duration(p.kernels),
            if p.threads > 1 { " of thread time" } else { "" },
            share(p.kernels) / p.threads as f64,
            duration(p.linearization)
        ),
        format!(
            "  Schur complement: set-up {}, eliminating {}, reduced system ({} × {}, {} entries, \
             Cholesky factor {}) {}, back-substitution {}, retraction {}, cost evaluations {}; \
             {} thread{}",
            duration(p.setup),
            duration(p.eliminate),
            p.reduced_dim,
            p.reduced_dim,
            p.reduced_entries,
            p.factor_entries,
            duration(p.factorize),
            duration(p.back_substitute),
            duration(p.retract),
            duration(p.evaluation),
            p.threads,
            if p.threads == 1 { "" } else { "s" }
        ),
    ]
}
