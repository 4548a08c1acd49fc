//! A problem file through the Schur-complement solver (crate
//! `factor-schur`), the default for a file it can take (`--solver auto`):
//! every factor registered for it, with [`Registry::solve_with_schur`] (a
//! fused normal-equation kernel, in lane batches) or
//! [`Registry::solve_with_schur_each`] (one factor at a time), and the
//! factors on each variable perturbing it the same way. Under `--kernels
//! dual` every factor is linearized one at a time by dual numbers.
//!
//! The variables eliminated are chosen greedily, the least connected first
//! (fewest factors, then the name): a free
//! variable is eliminated when none of its factors has an eliminated
//! variable yet, so no factor joins two, and the landmarks of a
//! reconstruction (seen by a few cameras) go before the cameras (which see
//! many landmarks).
//!
//! The checks are those of the apex path in a form that does not depend
//! on apex-solver: the observability check (at the initial values and at
//! the solution) over each factor's whitened Jacobian in its variables' own
//! tangents, by its generated kernel; the errors against the file's truth;
//! the file written back with the solution.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use factor_schur::Solver;
use serde_json::Value;
use slamjac_problem::document::Document;
use slamjac_problem::field_path::shown_path;
use slamjac_problem::observability::{Deficiency, Normal, Plan, Variable};

use super::problem_file::{
    add_at, nothing_to_solve, shape, solution_tolerance, truth_errors, unobservable, value_json,
    variables_of, with_variables,
};
use super::{SolveArgs, at, finish_file, progress};
use crate::error::CliError;
use crate::registry::Registry;
use slamjac_problem::checks::{self, read_json};
use slamjac_registry::schur_assembly::{SchurAssembly, blocks_of};

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
    let json = read_json(&args.file)?;
    let checked = checks::check(&json, |factor, path| shape(registry, factor, path))?;
    if let Some(why) = nothing_to_solve(&checked) {
        return Err(CliError::Usage(at(
            &args.file,
            format!("nothing to solve: {why}"),
        )));
    }
    let mut adders = Vec::with_capacity(checked.entries.len());
    for entry in &checked.entries {
        let factor = registry
            .find(entry.factor, &entry.path)
            .expect("checked: a registered factor");
        match factor.schur {
            Some((add, _)) => adders.push(add),
            None => {
                return Ok(Err(format!(
                    "the factor \"{}\" is not registered for the Schur-complement solver \
                     (Registry::solve_with_schur or solve_with_schur_each)",
                    factor.name
                )));
            }
        }
    }
    let eliminated = landmarks(&checked);
    let mut assembly = SchurAssembly {
        kernels: args.kernels,
        ..SchurAssembly::default()
    };
    for (entry, add) in checked.entries.iter().zip(adders) {
        add_at(entry, args.robust, |added| add(&mut assembly, added))?;
        if let Some(why) = assembly.unsupported.take() {
            return Ok(Err(why));
        }
    }
    for name in &checked.fixed {
        assembly.problem.fix(assembly.created[name].id);
    }
    for name in &eliminated {
        assembly.problem.eliminate(assembly.created[name].id);
    }
    let fixed: HashSet<String> = checked.fixed.iter().cloned().collect();
    let (found, plan) = deficiency(&mut assembly, &fixed, None, None);
    if let Some(deficiency) = found {
        return Err(unobservable(&args.file, &deficiency));
    }
    let blocks = assembly.problem.factor_count();
    let truth = checked.truth.clone();
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
    drop(checked);
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

/// The free variables to eliminate (see the module documentation).
fn landmarks(checked: &checks::Checked<'_>) -> HashSet<String> {
    let fixed: HashSet<&str> = checked.fixed.iter().map(String::as_str).collect();
    let mut factors_of: HashMap<&str, Vec<usize>> = HashMap::new();
    for (k, entry) in checked.entries.iter().enumerate() {
        for (_, name) in &entry.names {
            factors_of.entry(name).or_default().push(k);
        }
    }
    let mut order: Vec<&str> = factors_of
        .keys()
        .copied()
        .filter(|n| !fixed.contains(n))
        .collect();
    order.sort_by_key(|n| (factors_of[n].len(), *n));
    let mut touched = vec![false; checked.entries.len()];
    let mut eliminated = HashSet::new();
    for name in order {
        let factors = &factors_of[name];
        if factors.iter().all(|&k| !touched[k]) {
            for &k in factors {
                touched[k] = true;
            }
            eliminated.insert(name.to_owned());
        }
    }
    eliminated
}

/// The file's `variables` object with the solved values.
fn solved_variables(json: &Document, assembly: &SchurAssembly) -> Value {
    let mut variables = variables_of(json);
    for (name, created) in &assembly.created {
        variables[name]["value"] = value_json(&created.field, assembly.problem.value(created.id));
    }
    variables
}

/// The directions of the free variables the factors do not determine, at
/// the initial values (each factor's Jacobian there, kept by the build) or
/// (`solved`, with its tolerance) the problem's current ones
/// ([`slamjac_problem::observability`]), over each factor's whitened Jacobian in its
/// variables' own tangents; and the elimination's plan. With the `plan` of
/// the check at the initial values, the check at the solution eliminates
/// as it did, unless a factor is degenerate there (its pairs may then be
/// missing: the elimination is searched for anew).
fn deficiency(
    assembly: &mut SchurAssembly,
    fixed: &HashSet<String>,
    solved: Option<f64>,
    plan: Option<Plan>,
) -> (Option<Deficiency>, Plan) {
    let mut names: Vec<&String> = assembly
        .created
        .keys()
        .filter(|n| !fixed.contains(*n))
        .collect();
    names.sort();
    // Each problem variable's index among the free ones.
    let mut index = vec![None; assembly.problem.variable_count()];
    let mut variables = Vec::with_capacity(names.len());
    for (k, name) in names.into_iter().enumerate() {
        let created = &assembly.created[name];
        index[created.id.index()] = Some(k);
        variables.push(Variable {
            name: name.clone(),
            columns: created.columns.clone(),
        });
    }
    let planned = plan.is_some();
    let mut normal = match plan {
        Some(plan) => Normal::planned(variables, plan),
        None => Normal::new(variables),
    };
    let mut skipped = false;
    let (mut stored, mut residual, mut jacobian) = (Vec::new(), Vec::new(), Vec::new());
    let (mut free, mut whitened) = (Vec::new(), Vec::new());
    for kept in &mut assembly.kept {
        let s = &kept.sqrt_information;
        let rows = s.nrows();
        if solved.is_some() {
            stored.clone_from(&kept.stored);
            for (id, range, _) in &kept.variables {
                stored[range.clone()].copy_from_slice(assembly.problem.value(*id));
            }
            residual.resize(rows, 0.0);
            let dims: Vec<usize> = kept.variables.iter().map(|(_, _, d)| *d).collect();
            jacobian.resize(rows * dims.iter().sum::<usize>(), 0.0);
            let mut blocks = blocks_of(&mut jacobian, rows, &dims);
            // A factor degenerate here was refused by the solve already;
            // its measurements count for nothing.
            if (kept.linearize)(&stored, &mut residual, &mut blocks).is_err() {
                skipped = true;
                if planned {
                    break;
                }
                continue;
            }
        } else {
            jacobian = std::mem::take(&mut kept.initial);
        }
        // `S J` on the free variables.
        free.clear();
        whitened.clear();
        let mut start = 0;
        for (id, _, d) in &kept.variables {
            let block = &jacobian[start..start + rows * d];
            start += rows * d;
            let Some(k) = index[id.index()] else {
                continue;
            };
            free.push(k);
            for r in 0..rows {
                whitened.extend(
                    (0..*d).map(|c| (0..rows).map(|q| s[(r, q)] * block[q * d + c]).sum::<f64>()),
                );
            }
        }
        normal.add_rows(rows, &free, &mut whitened);
    }
    if skipped && planned {
        return deficiency(assembly, fixed, solved, None);
    }
    normal.deficiency_planned(solved.unwrap_or(slamjac_problem::observability::TOLERANCE))
}
