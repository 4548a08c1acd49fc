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
//! the file written back with the solution. The command line
//! (`slamjac::solve`) builds the file here ([`build`]) and solves it.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use serde_json::Value;
use slam_problems::{Kernels, Robust};
use slamjac_problem::checks::{self, read_json};
use slamjac_problem::document::Document;
use slamjac_problem::file_truth::Truth;
use slamjac_problem::observability::{Deficiency, Normal, Plan, Variable};
use slamjac_registry::registry::Registry;
use slamjac_registry::schur_assembly::{SchurAssembly, blocks_of};

use crate::error::SolveError;
use crate::problem_file::{
    add_at, shape, something_to_solve, unobservable, value_json, variables_of,
};

/// A problem file assembled for the Schur-complement solver, checked at
/// its initial values.
pub struct SchurFile {
    /// The file's JSON, written back with the solution's values.
    pub json: Document,
    /// The problem, its variables and what the observability check keeps.
    pub assembly: SchurAssembly,
    /// The names of the variables held fixed.
    pub fixed: HashSet<String>,
    /// The names of the variables eliminated by the Schur complement.
    pub eliminated: HashSet<String>,
    /// The observability check's elimination at the initial values, for
    /// the check at the solution ([`deficiency`]).
    pub plan: Plan,
    /// The ground truth the file carries.
    pub truth: Option<Truth>,
}

/// Reads the problem file `file` and assembles it for the Schur-complement
/// solver, its factors those `registry` registered for it, linearized as
/// `kernels` says, `robust` the loss of an entry without its own; or, when
/// that solver cannot take the file, why (nothing built).
///
/// # Errors
///
/// As [`crate::problem_file::read`].
pub fn build(
    file: &Path,
    registry: &Registry,
    kernels: Kernels,
    robust: Option<Robust>,
) -> Result<Result<SchurFile, String>, SolveError> {
    let json = read_json(file)?;
    let checked = checks::check(&json, |factor, path| shape(registry, factor, path))?;
    something_to_solve(file, &checked)?;
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
        kernels,
        ..SchurAssembly::default()
    };
    for (entry, add) in checked.entries.iter().zip(adders) {
        add_at(entry, robust, |added| add(&mut assembly, added))?;
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
        return Err(unobservable(file, &deficiency));
    }
    let truth = checked.truth.clone();
    drop(checked);
    Ok(Ok(SchurFile {
        json,
        assembly,
        fixed,
        eliminated,
        plan,
        truth,
    }))
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
pub fn solved_variables(json: &Document, assembly: &SchurAssembly) -> Value {
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
pub fn deficiency(
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
