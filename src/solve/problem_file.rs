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
//!   summary ([`super::file_truth`]).
//!
//! The factors are those a [`Registry`] registered for `solve`
//! ([`Registry::solve_with_kernel`]: its generated kernel in apex-solver's
//! chart; [`Registry::solve_with_dual`]: dual numbers in that chart);
//! `slamjac`'s own is [`crate::kernels::shipped`], a user's command line
//! has its own ([`crate::cli`]). Errors name the field path
//! (`error: factors[3].variables.pose: …`, exit 2).

use std::collections::HashMap;
use std::path::Path;

use factor_apex::Kernels;
use factor_apex::builder::{Noise, ProblemBuilder, Values};
use factor_apex::problems::{BuildOptions, Built, FactorChoice, Robust};
use factor_core::geometry::OrthonormalLine;
use factor_core::{FieldInfo, Layout, Storage};

use serde_json::{Map, Value};

use super::file_truth::Truth;
use crate::decode::record_keys;
use crate::error::{CliError, InputError};
use crate::field_path::{join, quoted};
use crate::input::{Object, numbers};
use crate::problem_assembly::{Assembly, Created, Entry, build_error};
use crate::registry::{Registry, SolvedBy};

/// The format version this build reads and writes.
pub const VERSION: u64 = crate::PROBLEM_FILE_VERSION;

/// A problem read from a file and built for apex.
pub struct FileProblem {
    /// The file's JSON, written back with the solution's values.
    json: Value,
    /// The apex problem.
    pub built: Built,
    variables: Vec<(String, Created)>,
    /// The ground truth the file carries.
    truth: Option<Truth>,
    /// How many factors go through generated kernels, how many through
    /// dual numbers.
    pub linearized_by: [usize; 2],
}

/// `Se3` for `Se3<S>`: a type as the file names it.
fn type_name(info: &str) -> &str {
    info.strip_suffix("<S>").unwrap_or(info)
}

/// An object at `path` with the fields `required` and any of `optional`.
pub(crate) fn open<'a>(
    value: &'a Value,
    path: &str,
    required: &[&str],
    optional: &[&str],
) -> Result<Object<'a>, InputError> {
    let present: Vec<&str> = match value.as_object() {
        Some(map) => {
            let allowed: Vec<&str> = required.iter().chain(optional).copied().collect();
            if let Some(unknown) = map.keys().find(|k| !allowed.contains(&k.as_str())) {
                return Err(InputError::new(
                    join(path, unknown),
                    format!("unknown field; expected only {}", allowed.join(", ")),
                ));
            }
            required
                .iter()
                .copied()
                .chain(optional.iter().copied().filter(|k| map.contains_key(*k)))
                .collect()
        }
        None => required.to_vec(),
    };
    Object::new(value, path, &present)
}

/// The noise model at `path`.
pub(crate) fn noise(value: &Value, path: &str, dim: usize) -> Result<Noise, InputError> {
    let object = open(value, path, &[], &["sigma", "sigmas", "sqrt_information"])?;
    let keys: Vec<&String> = value
        .as_object()
        .map(|m| m.keys().collect())
        .unwrap_or_default();
    let [key] = keys.as_slice() else {
        return Err(InputError::new(
            path,
            "expected exactly one of sigma, sigmas, sqrt_information",
        ));
    };
    let at = object.path_of(key);
    let positive = |x: f64, at: &str| {
        if x > 0.0 {
            Ok(x)
        } else {
            Err(InputError::new(
                at,
                format!("a standard deviation must be above 0, found {x}"),
            ))
        }
    };
    match key.as_str() {
        "sigma" => Ok(Noise::Sigma(positive(object.number(key)?, &at)?)),
        "sigmas" => {
            let sigmas = object.numbers(key, dim)?;
            for (i, s) in sigmas.iter().enumerate() {
                positive(*s, &format!("{at}[{i}]"))?;
            }
            Ok(Noise::Sigmas(sigmas))
        }
        _ => {
            let rows = object
                .get(key)
                .as_array()
                .filter(|r| r.len() == dim)
                .ok_or_else(|| {
                    InputError::new(&at, format!("expected {dim} rows of {dim} numbers"))
                })?;
            let mut s = nalgebra::DMatrix::zeros(dim, dim);
            for (i, row) in rows.iter().enumerate() {
                for (j, x) in numbers(row, &format!("{at}[{i}]"), dim)?
                    .into_iter()
                    .enumerate()
                {
                    s[(i, j)] = x;
                }
            }
            Ok(Noise::SqrtInformation(s))
        }
    }
}

/// Reads the problem file `file`: its JSON, the top level checked (only
/// `slamjac_problem`, `variables`, `factors` and `truth`), the version
/// this build reads, `variables` an object ([`variables`]).
///
/// # Errors
///
/// [`CliError::Usage`] for a file that cannot be read, [`CliError::Input`]
/// at the field at fault.
pub(crate) fn read_json(file: &Path) -> Result<Value, CliError> {
    let name = file.display().to_string();
    let text = std::fs::read_to_string(file)
        .map_err(|e| CliError::Usage(format!("{name}: cannot read: {e}")))?;
    let json = crate::strict_json::parse_json(&text, &name)?;
    let top = open(
        &json,
        "",
        &["slamjac_problem", "variables", "factors"],
        &["truth"],
    )?;
    let version = top.number("slamjac_problem")?;
    if version != VERSION as f64 {
        return Err(InputError::new(
            "slamjac_problem",
            format!("version {version} is not the version this slamjac reads ({VERSION})"),
        )
        .into());
    }
    if !json["variables"].is_object() {
        return Err(InputError::new("variables", "expected an object of named variables").into());
    }
    Ok(json)
}

/// The `variables` of a problem file [`read_json`] accepted.
pub(crate) fn variables(json: &Value) -> &Map<String, Value> {
    json["variables"]
        .as_object()
        .expect("read_json checked `variables`")
}

/// Reads and builds the problem file `file`, its factors those `registry`
/// registered for `solve`.
///
/// # Errors
///
/// [`CliError::Input`] naming the field at fault (exit 2), a factor
/// degenerate at the initial values (exit 1), apex's refusal.
pub fn read(
    file: &Path,
    options: &BuildOptions,
    registry: &Registry,
) -> Result<FileProblem, CliError> {
    let json = read_json(file)?;
    let declared = variables(&json);
    let mut fixed = Vec::new();
    for (name, spec) in declared {
        let path = join("variables", name);
        let object = open(spec, &path, &["type", "value"], &["fixed"])?;
        object.string("type")?;
        if spec.get("fixed").is_some() {
            let is_fixed = spec["fixed"].as_bool().ok_or_else(|| {
                InputError::new(object.path_of("fixed"), "expected true or false")
            })?;
            if is_fixed {
                fixed.push(name.clone());
            }
        }
    }
    let truth = json
        .get("truth")
        .map(|truth| Truth::read(truth, declared))
        .transpose()?;
    let factors = json["factors"]
        .as_array()
        .ok_or_else(|| InputError::new("factors", "expected an array of factors"))?;
    let mut assembly = Assembly {
        builder: ProblemBuilder::with_options(options),
        declared,
        created: HashMap::new(),
        linearized_by: [0; 2],
        kernels: options.factors == FactorChoice::Ours(Kernels::Generated),
    };
    for (k, spec) in factors.iter().enumerate() {
        let path = format!("factors[{k}]");
        add_entry(&mut assembly, registry, spec, &path, options.robust)?;
    }
    for name in &fixed {
        let created = assembly.created.get(name).ok_or_else(|| {
            InputError::new(join("variables", name), "no factor uses this variable")
        })?;
        assembly
            .builder
            .fix_any(&created.variable)
            .map_err(build_error)?;
    }
    if let Some(unused) = declared.keys().find(|n| !assembly.created.contains_key(*n)) {
        return Err(
            InputError::new(join("variables", unused), "no factor uses this variable").into(),
        );
    }
    let linearized_by = assembly.linearized_by;
    let built = assembly.builder.build().map_err(build_error)?;
    let mut variables: Vec<(String, Created)> = assembly.created.into_iter().collect();
    variables.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(FileProblem {
        json,
        built,
        variables,
        truth,
        linearized_by,
    })
}

/// Adds the factor entry `spec` at `path`.
fn add_entry(
    assembly: &mut Assembly,
    registry: &Registry,
    spec: &Value,
    path: &str,
    default_loss: Option<Robust>,
) -> Result<(), CliError> {
    let object = open(
        spec,
        path,
        &["factor", "variables", "constants"],
        &["noise", "robust"],
    )?;
    let entry = registry.find(object.string("factor")?, &object.path_of("factor"))?;
    let add = entry.solve.ok_or_else(|| {
        InputError::new(
            object.path_of("factor"),
            format!(
                "the factor {} is not registered for solve (Registry::solve_with_kernel or \
                 solve_with_dual)",
                quoted(entry.name)
            ),
        )
    })?;
    let infos = (entry.variables)();
    let variable_fields: Vec<&str> = infos.iter().map(|v| v.name).collect();
    let named = object.object("variables", &variable_fields)?;
    let mut names = Vec::with_capacity(infos.len());
    let mut values = Map::new();
    for info in &infos {
        let at = named.path_of(info.name);
        let name = named.string(info.name)?;
        let declared = assembly.declared.get(name).ok_or_else(|| {
            InputError::new(&at, format!("no variable {} in variables", quoted(name)))
        })?;
        let declared_type = declared["type"].as_str().unwrap_or_default();
        if declared_type != type_name(info.type_name) {
            return Err(InputError::new(
                &at,
                format!(
                    "variable {} is a {declared_type}, the factor's {} is a {}",
                    quoted(name),
                    info.name,
                    type_name(info.type_name)
                ),
            )
            .into());
        }
        names.push((info.name.to_owned(), name.to_owned()));
        values.insert(info.name.to_owned(), declared["value"].clone());
    }
    let values = Value::Object(values);
    let variables = Object::new(&values, &object.path_of("variables"), &variable_fields)?;
    let constant_fields: Vec<&str> = entry
        .json_fields(false)
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    let constants = object.object("constants", &constant_fields)?;
    let noise = match spec.get("noise") {
        Some(value) => noise(value, &object.path_of("noise"), entry.residual_dim)?,
        None => Noise::Unit,
    };
    let loss = match spec.get("robust") {
        Some(_) => Some(
            object
                .string("robust")?
                .parse()
                .map_err(|e: String| InputError::new(object.path_of("robust"), e))?,
        ),
        None => default_loss,
    };
    let checked = Entry {
        variables: &variables,
        constants: &constants,
        names: &names,
        noise: &noise,
        loss,
    };
    let by_kernel = assembly.kernels && entry.solved_by == Some(SolvedBy::Kernel);
    assembly.linearized_by[usize::from(!by_kernel)] += 1;
    add(assembly, &checked).map_err(|e| match e {
        CliError::Solve(what) => CliError::Usage(format!("{path}: {what}")),
        // Degenerate at the initial values: which entry (exit 1).
        CliError::Factor(_) | CliError::Hinted { .. } => CliError::Solve(format!("{path}: {e}")),
        CliError::Input(error) => CliError::Input(at_value(error, &variables, &names)),
        other => other,
    })
}

/// `error` at the value it is about: a path into a factor entry's variable
/// field (`factors[0].variables.gravity[2]`), the values read from the
/// variable named there, becomes the path into that variable's value
/// (`variables.g.value[2]`).
fn at_value(error: InputError, variables: &Object, names: &[(String, String)]) -> InputError {
    for (field, name) in names {
        let prefix = variables.path_of(field);
        if let Some(rest) = error.path.strip_prefix(&prefix)
            && (rest.is_empty() || rest.starts_with(['[', '.']))
        {
            let value = join(&join("variables", name), "value");
            return InputError::new(format!("{value}{rest}"), error.message);
        }
    }
    error
}

/// The JSON of stored scalars `stored` of a value of field `field`, in the
/// form the file reads (its input layout).
fn value_json(field: &FieldInfo, stored: &[f64]) -> Value {
    let input = if field.input_layout == field.layout {
        stored.to_vec()
    } else {
        // The one type stored otherwise than written: the orthonormal
        // line, written as Plücker coordinates `[normal, direction]`.
        let line = OrthonormalLine::<f64>::from_scalars(stored).to_plucker();
        line.normal
            .iter()
            .chain(line.direction.iter())
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

impl FileProblem {
    /// The file's JSON with the variables' values of `values`.
    pub fn written(&self, values: &Values) -> Value {
        let mut json = self.json.clone();
        for (name, created) in &self.variables {
            let stored = (created.read_back)(values, &created.variable, created.index);
            json["variables"][name]["value"] = value_json(&created.field, &stored);
        }
        json
    }

    /// The errors of the initial values and of `values` against the file's
    /// truth, in words; `None` when it has none.
    pub fn truth_errors(&self, values: &Values) -> Option<String> {
        let truth = self.truth.as_ref()?;
        let solved = self.written(values);
        Some(truth.describe(&self.json["variables"], &solved["variables"]))
    }
}

#[cfg(test)]
mod tests {
    /// Every factor `slamjac` ships is registered for `solve`.
    #[test]
    fn every_shipped_factor_can_be_solved() {
        for entry in crate::kernels::shipped().factors() {
            assert!(entry.solve.is_some(), "{}", entry.name);
        }
    }
}
