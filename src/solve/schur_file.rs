//! A problem file through the Schur-complement solver (crate
//! `factor-schur`), the default for a file it can take (`--solver auto`):
//! built by [`slamjac_solve::schur_file`] (which factors it takes, the
//! variables eliminated, the checks), solved and reported here.

use std::path::Path;

use factor_schur::Solver;
use slamjac_problem::field_path::shown_path;
use slamjac_solve::problem_file::{solution_tolerance, truth_errors, with_variables};
use slamjac_solve::schur_file::{self, SchurFile, deficiency, solved_variables};

use super::{SolveArgs, at, finish_file, progress};
use crate::error::CliError;
use crate::registry::Registry;

/// Solves the problem file of `args` with the Schur-complement solver and
/// returns the summary, or, when that solver cannot take it, why (nothing
/// solved, nothing printed).
///
/// # Errors
///
/// As [`super::run_problem_file`].
pub(super) fn run(
    args: &SolveArgs,
    registry: &Registry,
) -> Result<Result<String, String>, CliError> {
    let built = schur_file::build(&args.file, registry, args.kernels, args.robust)?;
    let SchurFile {
        json,
        mut assembly,
        fixed,
        eliminated,
        plan,
        truth,
    } = match built {
        Ok(built) => built,
        Err(why) => return Ok(Err(why)),
    };
    let blocks = assembly.problem.factor_count();
    let linearized = assembly.problem.linearized();
    let solver = Solver::new(&mut assembly.problem)
        .map_err(|e| CliError::Solve(at(&args.file, format!("the solve cannot start: {e}"))))?;
    // Which variables are eliminated, the header's count says: landmarks
    // in a reconstruction, possibly cameras where the landmarks are fixed.
    let words = super::schur::solver_words(
        eliminated.len(),
        assembly.created.len(),
        &linearized,
        &solver.linear_solver(),
    );
    progress::print(&header(
        &args.file,
        blocks,
        assembly.whitened,
        &words,
        solver.initial_cost(),
    ));
    let outcome = super::schur::iterate(args, solver, blocks);
    let finished = super::schur::finished(&outcome, blocks);
    let solved = solved_variables(&json, &assembly);
    let tolerance = solution_tolerance(&finished.verdict);
    let check = || match deficiency(&mut assembly, &fixed, Some(tolerance), Some(plan)).0 {
        Some(d) => Err(d.at("the solution").to_string()),
        None => Ok(()),
    };
    let errors = truth.map(|t| truth_errors(&t, &json, &solved));
    let summary = finish_file(args, &finished, check, errors, || {
        with_variables(&json, &solved)
    });
    super::drop_later((json, assembly, solved));
    summary.map(Ok)
}

/// The header: the file, its blocks, how many of them are `whitened` by a
/// full noise model, the solver, what it eliminates and how each factor
/// type is linearized (`words`).
fn header(file: &Path, blocks: usize, whitened: usize, words: &str, initial_cost: f64) -> String {
    format!(
        "{} (problem file): {blocks} blocks, {whitened} of them whitened by a full noise model; \
         Levenberg–Marquardt {words}; initial cost {initial_cost:.10e}",
        shown_path(file),
    )
}
