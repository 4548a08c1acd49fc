//! What every reader of a problem file checks before it builds anything:
//! `slamjac solve` and `slamjac track` read a file through [`read_json`]
//! and [`check`], so the same file gets the same exit status and the same
//! message from both.
//!
//! - The file: at most [`crate::source::MAX_PROBLEM_FILE_BYTES`]
//!   of UTF-8 JSON, parsed as it streams in (`/dev/zero` stops at its first byte);
//!   only `slamjac_problem`, `variables`, `factors` and `truth` at the top
//!   level, the version this build reads.
//! - Each variable: an object with `type`, `value` and optionally `fixed`
//!   (`true` or `false`); every variable named by some factor.
//! - The `truth`: checked as values are ([`crate::file_truth`]).
//! - Each factor entry: `factor`, `variables`, `constants`, optionally
//!   `noise` and `robust`; a `factor` the reader knows ([`Shape`]); each
//!   variable field naming a declared variable of the field's type, no
//!   variable named twice in one entry (a factor between a pose and itself
//!   is no measurement); the `constants` fields the factor has; a noise
//!   model whose standard deviations lie in `[1e-100, 1e100]` (the
//!   readers' range: their squares and inverses stay finite) and whose
//!   square-root information is invertible (every residual direction
//!   weighed); a loss `huber:δ` or `cauchy:δ`.
//!
//! Values themselves are checked by their types when the entries are
//! decoded, and their errors are moved to the value's path
//! ([`at_value`]).

use std::collections::HashMap;
use std::path::Path;

use crate::document::{Document, Json, Members};
use crate::field_path::{join, quoted};
use crate::input::{Object, numbers};
use crate::{InputError, PROBLEM_FILE_VERSION};
use factor_core::noise::Noise;
use factor_core::validation::number_text;
use factor_core::{Factor, FieldInfo, VariableInfo};
use slam_problems::Robust;

use crate::file_truth::Truth;

/// What a reader knows of a factor: its variable fields (with their
/// types), its constant fields and its residual's dimension.
pub struct Shape {
    /// The variable fields, in the factor's order, with their types.
    pub variables: Vec<VariableInfo>,
    /// The constant fields.
    pub constants: Vec<&'static str>,
    /// The residual's dimension.
    pub residual_dim: usize,
}

impl Shape {
    /// The shape of factor `F`.
    pub fn of<F: Factor>() -> Shape {
        Shape::from_fields(F::variables(), F::fields(), F::RESIDUAL_DIM)
    }

    /// The shape of a factor with these `variables`, `fields` (every
    /// field, [`Factor::fields`]: those that are no variable are its
    /// constants) and residual dimension.
    pub fn from_fields(
        variables: Vec<VariableInfo>,
        fields: Vec<FieldInfo>,
        residual_dim: usize,
    ) -> Shape {
        Shape {
            variables,
            constants: fields
                .into_iter()
                .filter(|field| field.variable.is_none())
                .map(|field| field.name)
                .collect(),
            residual_dim,
        }
    }
}

/// A factor entry that passed the checks.
pub struct Entry<'a> {
    /// `factors[k]`.
    pub path: String,
    /// Its `factor`.
    pub factor: &'a str,
    /// Per variable field, in the factor's order: the field and the
    /// problem variable it names.
    pub names: Vec<(&'static str, &'a str)>,
    /// Per variable field, in the factor's order: the value of the variable
    /// it names (read at the entry's `variables` path, for [`at_value`]).
    pub values: Vec<Json<'a>>,
    /// Its `constants` object.
    pub constants: Object<'a>,
    /// Its noise model (unit when absent).
    pub noise: Noise,
    /// Its own loss, if it has one.
    pub robust: Option<Robust>,
}

impl Entry<'_> {
    /// The entry's variable values as an object with exactly its fields.
    pub fn variables(&self) -> Object<'_> {
        let fields = self.names.iter().map(|(field, _)| *field);
        Object::gathered(
            &join(&self.path, "variables"),
            fields.zip(self.values.iter().copied()).collect(),
        )
    }
}

/// A problem file that passed the checks.
pub struct Checked<'a> {
    /// The declared variables, by name.
    pub declared: Members<'a>,
    /// The names of the variables marked `fixed`.
    pub fixed: Vec<String>,
    /// The truth, checked.
    pub truth: Option<Truth>,
    /// The factor entries, in file order.
    pub entries: Vec<Entry<'a>>,
}

/// Reads the problem file `file`: its JSON, the top level checked (only
/// `slamjac_problem`, `variables`, `factors` and `truth`), the version
/// this build reads, `variables` an object.
///
/// # Errors
///
/// The [`InputError`] naming the file (unreadable, over the cap, not UTF-8
/// or not JSON) or the field at fault.
pub fn read_json(file: &Path) -> Result<Document, InputError> {
    let name = file.display().to_string();
    let reader = crate::source::open_problem_file(file)?;
    let json = crate::strict_json::parse_json_from(reader, &name)?;
    let top = open(
        json.root(),
        "",
        &["slamjac_problem", "variables", "factors"],
        &["truth"],
    )?;
    let version = top.number("slamjac_problem")?;
    if version != PROBLEM_FILE_VERSION as f64 {
        return Err(InputError::new(
            "slamjac_problem",
            format!(
                "version {version} is not the version this slamjac reads ({PROBLEM_FILE_VERSION})"
            ),
        ));
    }
    if !json.root().get("variables").is_some_and(Json::is_object) {
        return Err(InputError::new(
            "variables",
            "expected an object of named variables",
        ));
    }
    if !json.root().get("factors").is_some_and(Json::is_array) {
        return Err(InputError::new("factors", "expected an array of factors"));
    }
    Ok(json)
}

/// Checks the problem file `json` ([`read_json`]) against the factors
/// `shape` knows (`shape(factor, path)`: the shape of `factor`, or the
/// error at `path` for a factor the reader does not take).
///
/// # Errors
///
/// The first fault, at its field path (see the module documentation).
pub fn check<'a>(
    json: &'a Document,
    shape: impl Fn(&str, &str) -> Result<Shape, InputError>,
) -> Result<Checked<'a>, InputError> {
    let root = json.root();
    let declared = root
        .get("variables")
        .and_then(Json::as_object)
        .expect("read_json checked `variables`");
    let mut fixed = Vec::new();
    for (name, spec) in declared.iter() {
        let object = open(
            spec,
            &join("variables", name),
            &["type", "value"],
            &["fixed"],
        )?;
        object.string("type")?;
        if let Some(value) = spec.get("fixed") {
            let is_fixed = value.as_bool().ok_or_else(|| {
                InputError::new(object.path_of("fixed"), "expected true or false")
            })?;
            if is_fixed {
                fixed.push(name.to_owned());
            }
        }
    }
    let truth = root
        .get("truth")
        .map(|truth| Truth::read(truth, declared))
        .transpose()?;
    let factors = root
        .get("factors")
        .and_then(Json::as_array)
        .expect("read_json checked `factors`");
    let mut entries = Vec::with_capacity(factors.len());
    // Each declared variable by name: its specification, and whether a
    // factor uses it.
    let mut variables: HashMap<&str, (Json<'a>, bool)> = declared
        .iter()
        .map(|(name, spec)| (name, (spec, false)))
        .collect();
    // Each factor's shape, asked once per factor name.
    let mut shapes = Vec::new();
    for (k, spec) in factors.iter().enumerate() {
        let at = format!("factors[{k}]");
        let entry = check_entry(spec, &at, &mut variables, &mut shapes, &shape)?;
        entries.push(entry);
    }
    if let Some(unused) = declared.keys().find(|n| !variables[n].1) {
        return Err(InputError::new(
            join("variables", unused),
            "no factor uses this variable",
        ));
    }
    Ok(Checked {
        declared,
        fixed,
        truth,
        entries,
    })
}

/// Checks the factor entry `spec` at `path`, the shape of its factor from
/// `shapes` or else `shape` (then kept in `shapes`).
fn check_entry<'a>(
    spec: Json<'a>,
    path: &str,
    declared: &mut HashMap<&str, (Json<'a>, bool)>,
    shapes: &mut Vec<(&'a str, Shape)>,
    shape: &impl Fn(&str, &str) -> Result<Shape, InputError>,
) -> Result<Entry<'a>, InputError> {
    let object = open(
        spec,
        path,
        &["factor", "variables", "constants"],
        &["noise", "robust"],
    )?;
    let factor = object.string("factor")?;
    let index = match shapes.iter().position(|(name, _)| *name == factor) {
        Some(index) => index,
        None => {
            shapes.push((factor, shape(factor, &object.path_of("factor"))?));
            shapes.len() - 1
        }
    };
    let shape = &shapes[index].1;
    let fields: Vec<&str> = shape.variables.iter().map(|v| v.name).collect();
    let named = object.object("variables", &fields)?;
    let mut names: Vec<(&'static str, &'a str)> = Vec::with_capacity(fields.len());
    let mut values = Vec::with_capacity(fields.len());
    for info in &shape.variables {
        let at = || named.path_of(info.name);
        let name = named.string(info.name)?;
        let (variable, used) = declared.get_mut(name).ok_or_else(|| {
            InputError::new(at(), format!("no variable {} in variables", quoted(name)))
        })?;
        *used = true;
        let variable = *variable;
        let declared_type = variable
            .get("type")
            .and_then(Json::as_str)
            .unwrap_or_default();
        let wanted = type_name(info.type_name);
        if declared_type != wanted {
            return Err(InputError::new(
                at(),
                format!(
                    "variable {} is a {declared_type}, the factor's {} is a {wanted}",
                    quoted(name),
                    info.name,
                ),
            ));
        }
        if let Some((other, _)) = names.iter().find(|(_, n)| *n == name) {
            return Err(InputError::new(
                at(),
                format!(
                    "names the variable {} that {other} names: a factor's variables must be \
                     distinct",
                    quoted(name)
                ),
            ));
        }
        names.push((info.name, name));
        values.push(
            variable
                .get("value")
                .expect("checked: every variable has a value"),
        );
    }
    let constants = object.object("constants", &shape.constants)?;
    let noise = match spec.get("noise") {
        Some(value) => noise(value, &object.path_of("noise"), shape.residual_dim)?,
        None => Noise::Unit,
    };
    let robust = match spec.get("robust") {
        Some(_) => Some(
            object
                .string("robust")?
                .parse()
                .map_err(|e: String| InputError::new(object.path_of("robust"), e))?,
        ),
        None => None,
    };
    Ok(Entry {
        path: path.to_owned(),
        factor,
        names,
        values,
        constants,
        noise,
        robust,
    })
}

/// `Se3` for `Se3<S>`: a type as the file names it.
pub fn type_name(info: &str) -> &str {
    info.strip_suffix("<S>").unwrap_or(info)
}

/// An object at `path` with the fields `required` and any of `optional`.
fn open<'a>(
    value: Json<'a>,
    path: &str,
    required: &[&str],
    optional: &[&str],
) -> Result<Object<'a>, InputError> {
    let present: Vec<&str> = match value.as_object() {
        Some(map) => {
            let present: Vec<&str> = required
                .iter()
                .copied()
                .chain(optional.iter().copied().filter(|k| map.contains_key(k)))
                .collect();
            // The required fields, and as many fields as present: none
            // unknown (the slow search for one runs only when not).
            if map.len() == present.len() && required.iter().all(|k| map.contains_key(k)) {
                return Object::new(value, path, &present);
            }
            let allowed: Vec<&str> = required.iter().chain(optional).copied().collect();
            if let Some(unknown) = map.keys().find(|k| !allowed.contains(k)) {
                return Err(InputError::new(
                    join(path, unknown),
                    format!("unknown field; expected only {}", allowed.join(", ")),
                ));
            }
            required
                .iter()
                .copied()
                .chain(optional.iter().copied().filter(|k| map.contains_key(k)))
                .collect()
        }
        // Not an object: what it should hold (every field it may hold
        // when none is required).
        None if required.is_empty() => optional.to_vec(),
        None => required.to_vec(),
    };
    Object::new(value, path, &present)
}

/// The range of a standard deviation, and of the magnitude of a
/// square-root information's entries: the readers' range of magnitudes,
/// so that squares and inverses stay finite.
const NOISE_RANGE: (f64, f64) = (1e-100, 1e100);

/// The noise model at `path`, for a residual of `dim` components.
fn noise(value: Json<'_>, path: &str, dim: usize) -> Result<Noise, InputError> {
    let object = open(value, path, &[], &["sigma", "sigmas", "sqrt_information"])?;
    let keys: Vec<&str> = value
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
    let (low, high) = NOISE_RANGE;
    let deviation = |x: f64, at: &str| {
        if (low..=high).contains(&x) {
            Ok(x)
        } else {
            Err(InputError::new(
                at,
                format!(
                    "a standard deviation must be from {low:e} to {high:e}, found {}",
                    number_text(x)
                ),
            ))
        }
    };
    match *key {
        "sigma" => Ok(Noise::Sigma(deviation(object.number(key)?, &at)?)),
        "sigmas" => {
            let sigmas = object.numbers(key, dim)?;
            for (i, s) in sigmas.iter().enumerate() {
                deviation(*s, &format!("{at}[{i}]"))?;
            }
            Ok(Noise::Sigmas(sigmas))
        }
        _ => sqrt_information(object.get(key), &at, dim).map(Noise::SqrtInformation),
    }
}

/// The square-root information `S` at `at`: `dim` rows of `dim` numbers of
/// magnitude at most 1e100, invertible to within rounding (its smallest
/// singular value above `dim · ε` times its largest).
fn sqrt_information(
    value: Json<'_>,
    at: &str,
    dim: usize,
) -> Result<nalgebra::DMatrix<f64>, InputError> {
    let rows = value
        .as_array()
        .filter(|r| r.len() == dim)
        .ok_or_else(|| InputError::new(at, format!("expected {dim} rows of {dim} numbers")))?;
    let mut s = nalgebra::DMatrix::zeros(dim, dim);
    for (i, row) in rows.iter().enumerate() {
        let row_at = format!("{at}[{i}]");
        for (j, x) in numbers(row, &row_at, dim)?.into_iter().enumerate() {
            if x.abs() > NOISE_RANGE.1 {
                return Err(InputError::new(
                    format!("{row_at}[{j}]"),
                    format!("magnitude over {:e}", NOISE_RANGE.1),
                ));
            }
            s[(i, j)] = x;
        }
    }
    let singular = s.clone().svd(false, false).singular_values;
    let (largest, smallest) = (singular.max(), singular.min());
    if smallest.is_nan() || smallest <= largest * dim as f64 * f64::EPSILON {
        let rank = singular
            .iter()
            .filter(|v| **v > largest * dim as f64 * f64::EPSILON)
            .count();
        return Err(InputError::new(
            at,
            format!(
                "not invertible (rank {rank} of {dim}): a square-root information must weigh \
                 every direction of the residual"
            ),
        ));
    }
    Ok(s)
}

/// `error` at the value it is about: a path into a factor entry's variable
/// field (`factors[0].variables.gravity[2]`), the values read from the
/// variable named there, becomes the path into that variable's value
/// (`variables.g.value[2]`).
pub fn at_value(error: InputError, entry: &Entry<'_>) -> InputError {
    let variables = join(&entry.path, "variables");
    for (field, name) in &entry.names {
        let prefix = join(&variables, field);
        if let Some(rest) = error.path.strip_prefix(&prefix)
            && (rest.is_empty() || rest.starts_with(['[', '.']))
        {
            let value = join(&join("variables", name), "value");
            return InputError::new(format!("{value}{rest}"), error.message);
        }
    }
    error
}
