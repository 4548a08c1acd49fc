//! The problem file: any registered factors on named variables, in JSON,
//! solved by `slamjac solve FILE.json` and written back by `--output`.
//!
//! ```json
//! {
//!   "slamjac_problem": 1,
//!   "variables": {
//!     "x0": {"type": "Se3", "value": {"rotation": [0, 0, 0, 1], "translation": [0, 0, 0]}, "fixed": true},
//!     "p0": {"type": "Vector3", "value": [0.1, 0.2, 4.0]}
//!   },
//!   "factors": [
//!     {"factor": "point_reprojection",
//!      "variables": {"pose": "x0", "point": "p0"},
//!      "constants": {"intrinsics": [500, 500, 320, 240], "observed": [332.5, 265.0]},
//!      "noise": {"sigma": 1.0},
//!      "robust": "huber:2"}
//!   ]
//! }
//! ```
//!
//! - `slamjac_problem`: the format's version, 1.
//! - `variables`: by name, each with its `type` (the factor's variable type
//!   as `slamjac list` prints it, without `<S>`), its initial `value` in the
//!   JSON form `slamjac eval` reads for that type, and optionally `fixed`
//!   (`false` by default).
//! - `factors`: each with its registered `factor` name, `variables` naming
//!   a problem variable per variable field, `constants` as `eval` reads
//!   them, optionally a `noise` model in the factor's residual space —
//!   `{"sigma": σ}`, `{"sigmas": [σ₁, …]}` or `{"sqrt_information": [[…],
//!   …]}` (rows of `S`, the cost being `½ ‖S r‖²`; unit by default) — and a
//!   `robust` loss (`huber:δ` or `cauchy:δ`).
//!
//! - `truth` (optional): the true value of variables by name, in the form
//!   of their `value`; `solve` then reports the errors against it after the
//!   summary ([`slamjac_problem::file_truth`]).
//!
//! The factors are those a [`Registry`] registered for `solve`
//! ([`Registry::solve_with_kernel`]: its generated kernel in apex-solver's
//! chart; [`Registry::solve_with_dual`]: dual numbers in that chart);
//! `slamjac`'s own is `slamjac::kernels::shipped`, a user's command line
//! has its own (`slamjac::cli`). Errors name the field path
//! (`error: factors[3].variables.pose: …`, exit 2).

use std::collections::HashMap;
use std::path::Path;

use factor_apex::builder::{ProblemBuilder, Values};
use factor_apex::built::Built;
use factor_apex::problems::{BuildOptions, FactorChoice};
use factor_core::geometry::OrthonormalLine;
use factor_core::{FieldInfo, Layout, Storage};
use factor_minimizer::Verdict;
use slam_problems::{Kernels, Robust};

use nalgebra::DMatrix;
use serde_json::{Map, Value};
use slamjac_problem::InputError;
use slamjac_problem::decode::{FieldsCache, record_keys};
use slamjac_problem::document::{Document, Json};
use slamjac_problem::field_path::quoted;
use slamjac_problem::observability::{DRIFT_TOLERANCE, Deficiency, Normal, TOLERANCE, Variable};

use slamjac_problem::checks::{self, Shape, at_value, read_json};
use slamjac_problem::file_truth::Truth;

use crate::error::SolveError;
use slamjac_registry::RegistryError;
use slamjac_registry::problem_assembly::{Assembly, Created, Entry, build_error};
use slamjac_registry::registry::{Registry, SolvedBy};

/// A problem read from a file and built for apex.
pub struct FileProblem {
    /// The file's JSON, written back with the solution's values.
    json: Document,
    /// The apex problem.
    pub built: Built<()>,
    variables: Vec<(String, Created)>,
    /// The names of the variables held fixed.
    fixed: Vec<String>,
    /// The ground truth the file carries.
    truth: Option<Truth>,
    /// How many factors go through generated kernels, how many through
    /// dual numbers.
    pub linearized_by: [usize; 2],
}

/// What `solve` knows of the factor `factor` of `registry`: those
/// registered for `solve` (an error at `path` for any other).
pub fn shape(registry: &Registry, factor: &str, path: &str) -> Result<Shape, InputError> {
    let entry = registry.find(factor, path)?;
    if entry.solve.is_none() {
        return Err(InputError::new(
            path,
            format!(
                "the factor {} is not registered for solve (Registry::solve_with_kernel or \
                 solve_with_dual)",
                quoted(entry.name)
            ),
        ));
    }
    Ok(Shape::from_fields(
        (entry.variables)(),
        (entry.fields)(),
        entry.residual_dim,
    ))
}

/// Reads and builds the problem file `file`, its factors those `registry`
/// registered for `solve`.
///
/// # Errors
///
/// [`SolveError::Input`] naming the field at fault (exit 2; the checks of
/// `slamjac_problem::checks`, shared with `track`), nothing to solve (every variable
/// fixed, or no factor: [`SolveError::Usage`], exit 2), a factor
/// degenerate at the initial values (exit 1), apex's refusal.
pub fn read(
    file: &Path,
    options: &BuildOptions,
    registry: &Registry,
) -> Result<FileProblem, SolveError> {
    let json = read_json(file)?;
    let checked = checks::check(&json, |factor, path| shape(registry, factor, path))?;
    something_to_solve(file, &checked)?;
    // Every block kept, for the observability check.
    let options = BuildOptions {
        keep_blocks: true,
        ..*options
    };
    let mut assembly = Assembly {
        builder: ProblemBuilder::with_options(&options),
        created: HashMap::new(),
        linearized_by: [0; 2],
        kernels: options.factors == FactorChoice::Ours(Kernels::Generated),
        fields: FieldsCache::default(),
    };
    for entry in &checked.entries {
        add_entry(&mut assembly, registry, entry, options.robust)?;
    }
    for name in &checked.fixed {
        let created = &assembly.created[name];
        assembly
            .builder
            .fix_any(&created.variable)
            .map_err(build_error)?;
    }
    let linearized_by = assembly.linearized_by;
    let built = assembly.builder.build().map_err(build_error)?;
    if let Some(deficiency) = deficiency(&built, &assembly.created, &checked.fixed, None) {
        return Err(unobservable(file, &deficiency));
    }
    let mut variables: Vec<(String, Created)> = assembly.created.into_iter().collect();
    variables.sort_by(|a, b| a.0.cmp(&b.0));
    let (truth, fixed) = (checked.truth, checked.fixed);
    Ok(FileProblem {
        json,
        built,
        variables,
        fixed,
        truth,
        linearized_by,
    })
}

/// The refusal of a file whose free variables the factors do not
/// determine at the initial values (either solver path's check).
pub fn unobservable(file: &Path, deficiency: &Deficiency) -> SolveError {
    SolveError::Solve(format!(
        "{}: {deficiency}; nothing solved: hold more variables fixed (\"fixed\": true) or add \
         measurements",
        file.display()
    ))
}

/// Refuses the checked file `file` when it has nothing to solve: no
/// factor, or every variable held fixed (every variable is used by a
/// factor, so a factor on fixed variables only is among these).
///
/// # Errors
///
/// [`SolveError::Usage`] saying which.
pub fn something_to_solve(file: &Path, checked: &checks::Checked<'_>) -> Result<(), SolveError> {
    let why = if checked.entries.is_empty() {
        "the problem has no factors".to_owned()
    } else if checked.fixed.len() == checked.declared.len() {
        format!(
            "every variable is fixed ({} of {}): no value is left to estimate",
            checked.fixed.len(),
            checked.declared.len()
        )
    } else {
        return Ok(());
    };
    Err(SolveError::Usage(format!(
        "{}: nothing to solve: {why}",
        file.display()
    )))
}

/// The directions of the free variables the built problem's blocks do not
/// determine at the initial values, or at `solved` with its tolerance
/// ([`slamjac_problem::observability`]), in apex-solver's chart, through each block's
/// whitened Jacobian.
fn deficiency<'a>(
    built: &Built<()>,
    created: impl IntoIterator<Item = (&'a String, &'a Created)>,
    fixed: &[String],
    solved: Option<(&Values, f64)>,
) -> Option<Deficiency> {
    let created: HashMap<&String, &Created> = created.into_iter().collect();
    let mut names: Vec<&String> = created
        .keys()
        .copied()
        .filter(|n| !fixed.contains(n))
        .collect();
    names.sort();
    // Each free apex key: its variable, its first column there and which
    // of the variable's keys it is.
    let mut at = HashMap::new();
    let mut variables = Vec::with_capacity(names.len());
    // Per free variable: its width in apex's coordinates, its keys' count,
    // and how its own tangent sits in apex's coordinates where it is not
    // apex's (with the variable's index in its factor).
    let mut host = Vec::with_capacity(names.len());
    for (index, name) in names.into_iter().enumerate() {
        let created = created[name];
        let mut column = 0;
        let keys = created.variable.keys();
        for (part, (key, dof)) in keys.iter().zip(created.variable.dofs()).enumerate() {
            at.insert(*key, (index, column, part));
            column += dof;
        }
        variables.push(Variable {
            name: name.clone(),
            columns: created.columns.clone(),
        });
        let in_host = created.in_host.map(|f| (f, created.index));
        host.push((column, keys.len(), in_host));
    }
    let dofs: HashMap<_, usize> = created
        .values()
        .flat_map(|c| {
            c.variable
                .keys()
                .iter()
                .copied()
                .zip(c.variable.dofs().iter().copied())
        })
        .collect();
    // Each such variable's own tangent in apex's coordinates, at the point
    // linearized at (the same in every block).
    let mut bases: HashMap<usize, DMatrix<f64>> = HashMap::new();
    let mut normal = Normal::new(variables);
    for block in built.kept.as_deref().unwrap_or_default() {
        let params: Vec<&[f64]> = match solved {
            Some((values, _)) => block
                .keys
                .iter()
                .map(|k| values[*k].as_param_slice())
                .collect(),
            None => block.params.iter().map(Vec::as_slice).collect(),
        };
        let (rows, jacobian) = block.whitened_jacobian_at(&params);
        let mut blocks: Vec<HostBlock> = Vec::new();
        let mut first = 0;
        for (key, values) in block.keys.iter().zip(&params) {
            let dof = dofs[key];
            if let Some(&(index, column, part)) = at.get(key) {
                let position = match blocks.iter().position(|b| b.index == index) {
                    Some(position) => position,
                    None => {
                        let (width, keys, _) = host[index];
                        blocks.push(HostBlock {
                            index,
                            jacobian: DMatrix::zeros(rows, width),
                            parameters: vec![&[][..]; keys],
                        });
                        blocks.len() - 1
                    }
                };
                let HostBlock {
                    jacobian: whole,
                    parameters,
                    ..
                } = &mut blocks[position];
                whole
                    .columns_mut(column, dof)
                    .copy_from_slice(&jacobian[first * rows..(first + dof) * rows]);
                parameters[part] = values;
            }
            first += dof;
        }
        let blocks: Vec<(usize, DMatrix<f64>)> = blocks
            .into_iter()
            .map(|b| match host[b.index].2 {
                None => (b.index, b.jacobian),
                Some((in_host, variable)) => {
                    let basis = bases
                        .entry(b.index)
                        .or_insert_with(|| in_host(variable, &b.parameters.concat()));
                    (b.index, b.jacobian * &*basis)
                }
            })
            .collect();
        normal.add(blocks);
    }
    normal.deficiency_within(solved.map_or(TOLERANCE, |(_, tolerance)| tolerance))
}

/// The tolerance of the observability check at a solution: the strict one
/// after a converged solve, [`DRIFT_TOLERANCE`] after one that stopped
/// unconverged, whose weakly determined directions are where it drifted.
pub fn solution_tolerance(verdict: &Verdict) -> f64 {
    match verdict {
        Verdict::Converged(_) => TOLERANCE,
        _ => DRIFT_TOLERANCE,
    }
}

/// A block's whitened Jacobian on one free variable in apex's coordinates,
/// with the variable's parameters (one slice per apex key) it was taken at.
struct HostBlock<'a> {
    index: usize,
    jacobian: DMatrix<f64>,
    parameters: Vec<&'a [f64]>,
}

/// Adds the checked factor entry `entry`.
fn add_entry(
    assembly: &mut Assembly,
    registry: &Registry,
    entry: &checks::Entry<'_>,
    default_loss: Option<Robust>,
) -> Result<(), SolveError> {
    let factor = registry
        .find(entry.factor, &entry.path)
        .expect("checked: a registered factor");
    let add = factor.solve.expect("checked: registered for solve");
    let by_kernel = assembly.kernels && factor.solved_by == Some(SolvedBy::Kernel);
    assembly.linearized_by[usize::from(!by_kernel)] += 1;
    add_at(entry, default_loss, |checked| add(assembly, checked))
}

/// Runs `add` on the checked factor entry `entry` (its variables decoded,
/// its loss or else `default_loss`), its errors placed at the entry's
/// path: either solver path's adder.
pub fn add_at(
    entry: &checks::Entry<'_>,
    default_loss: Option<Robust>,
    add: impl FnOnce(&Entry) -> Result<(), RegistryError>,
) -> Result<(), SolveError> {
    let variables = entry.variables();
    let checked = Entry {
        variables: &variables,
        constants: &entry.constants,
        names: &entry.names,
        noise: &entry.noise,
        loss: entry.robust.or(default_loss),
    };
    let path = &entry.path;
    add(&checked).map_err(|e| match e {
        RegistryError::Solve(what) => SolveError::Usage(format!("{path}: {what}")),
        // Degenerate at the initial values: which entry (exit 1).
        RegistryError::Factor(_) | RegistryError::Hinted { .. } => {
            SolveError::Solve(format!("{path}: {e}"))
        }
        RegistryError::Input(error) => SolveError::Input(at_value(error, entry)),
        other => other.into(),
    })
}

/// The JSON of stored scalars `stored` of a value of field `field`, in the
/// form the file reads (its input layout).
pub fn value_json(field: &FieldInfo, stored: &[f64]) -> Value {
    let input = if field.input_layout == field.layout {
        stored.to_vec()
    } else {
        // The one type stored otherwise than written: the orthonormal
        // line, written as Plücker coordinates `[normal, direction]` scaled
        // to a unit direction (as the apex path writes a `PluckerLine`
        // solved in this chart), so that `|normal|` is its distance from
        // the origin.
        let line = OrthonormalLine::<f64>::from_scalars(stored);
        line.moment()
            .iter()
            .chain(line.direction().iter())
            .copied()
            .collect()
    };
    let mut rest = input.as_slice();
    layout_json(&field.input_layout, &mut rest)
}

fn layout_json(layout: &Layout, rest: &mut &[f64]) -> Value {
    match layout {
        Layout::Scalar => {
            let (x, tail) = rest.split_first().expect("a scalar per slot");
            *rest = tail;
            Value::from(*x)
        }
        Layout::Array(names) => {
            let (head, tail) = rest.split_at(names.len());
            *rest = tail;
            Value::from(head.to_vec())
        }
        Layout::Record(parts) => {
            let keys = record_keys(layout);
            let mut map = Map::new();
            for (key, (_, part)) in keys.iter().zip(parts) {
                map.insert((*key).to_owned(), layout_json(part, rest));
            }
            Value::Object(map)
        }
    }
}

/// The file's JSON `json` with its `variables` object replaced by
/// `variables` (the solved values): what `--output` writes.
pub fn with_variables(json: &Document, variables: &Value) -> Value {
    let top = json
        .root()
        .as_object()
        .expect("read_json checked the top level");
    let replaced = top.iter().map(|(key, value)| {
        let value = if key == "variables" {
            variables.clone()
        } else {
            value.to_value()
        };
        (key.to_owned(), value)
    });
    Value::Object(replaced.collect())
}

/// The file's `variables` object as written, to take the solved values.
pub fn variables_of(json: &Document) -> Value {
    json.root()
        .get("variables")
        .map_or(Value::Null, Json::to_value)
}

/// The errors against `truth` of the file's initial values and of the
/// `solved` variables ([`Truth::describe`]).
pub fn truth_errors(truth: &Truth, json: &Document, solved: &Value) -> Result<String, String> {
    let initial = json
        .root()
        .get("variables")
        .expect("read_json checked `variables`");
    truth.describe(initial, Document::from_value(solved).root())
}

impl FileProblem {
    /// The file's `variables` object with the values of `values`.
    pub fn solved_variables(&self, values: &Values) -> Value {
        let mut variables = variables_of(&self.json);
        for (name, created) in &self.variables {
            let stored = (created.read_back)(values, &created.variable, created.index);
            variables[name]["value"] = value_json(&created.field, &stored);
        }
        variables
    }

    /// The file's JSON with the solved `variables` ([`Self::solved_variables`]).
    pub fn written(&self, variables: &Value) -> Value {
        with_variables(&self.json, variables)
    }

    /// Refuses a solution whose free variables the measurements do not
    /// determine (the solve drifted to a configuration that leaves a
    /// direction free, as two planes rotated parallel: issue 28's
    /// `synth-plp --cameras 4`), naming the directions; after a solve that
    /// did not converge (`verdict`), one they determine only weakly too
    /// (`solution_tolerance`).
    ///
    /// # Errors
    ///
    /// The deficiency, in words.
    pub fn check_solution(&self, values: &Values, verdict: &Verdict) -> Result<(), String> {
        let created = self.variables.iter().map(|(name, c)| (name, c));
        let at = Some((values, solution_tolerance(verdict)));
        match deficiency(&self.built, created, &self.fixed, at) {
            Some(deficiency) => Err(deficiency.at("the solution").to_string()),
            None => Ok(()),
        }
    }

    /// The errors of the initial values and of the `solved` variables
    /// ([`Self::solved_variables`]) against the file's truth, in words;
    /// `None` when it has none.
    ///
    /// # Errors
    ///
    /// Errors that cannot be measured ([`Truth::describe`]), in words.
    pub fn truth_errors(&self, solved: &Value) -> Option<Result<String, String>> {
        let truth = self.truth.as_ref()?;
        Some(truth_errors(truth, &self.json, solved))
    }
}
