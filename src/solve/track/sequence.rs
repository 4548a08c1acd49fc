//! A problem file read as a tracking sequence: its `Se3` variables are the
//! frames, in the order the file lists them, each with the observations
//! that name it and its true pose; every other variable is the map, held
//! fixed.
//!
//! - Observations: the factors of one pose against one landmark
//!   (`point_reprojection` measures points,
//!   `line_reprojection`, `plucker_line_reprojection` and
//!   `line_observation` lines, `plane` planes), each with the file's noise
//!   model; any other factor, or a `robust` loss (tracking solves least
//!   squares), is refused (exit 2).
//! - The map: each landmark at its `truth` ([`MapSource::Truth`], a map
//!   known exactly, so that the error is the tracker's alone) or at its
//!   `value` in `variables` ([`MapSource::Values`]: e.g. the map a `solve
//!   --output` estimated).
//! - The `truth` of every pose is required: frame 0 starts there, and the
//!   errors are measured against it. `fixed` flags are ignored: every pose
//!   is tracked, every landmark fixed.

use std::collections::HashMap;
use std::path::Path;

use factor_core::lie::Se3;
use factor_core::{Factor, Storage};
use factor_tracking::{PoseError, PoseProblem, Whitening};
use serde_json::{Map, Value};
use slam_factors::{
    LineObservation, LineReprojection, PlaneFactor, PluckerLineReprojection, PointReprojection,
};

use super::super::file_truth::Truth;
use super::super::problem_file::{noise, open, read_json, variables};
use crate::decode::decode;
use crate::error::{CliError, InputError};
use crate::field_path::{join, quoted};
use crate::input::Object;
use crate::synth_plp::Kinds;

/// Where the fixed map's values come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MapSource {
    /// Each landmark's `truth`.
    #[default]
    Truth,
    /// Each landmark's `value`.
    Values,
}

/// What an observation measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A point.
    Point,
    /// A line.
    Line,
    /// A plane.
    Plane,
}

impl Kind {
    /// Whether `kinds` selects it.
    pub fn in_kinds(self, kinds: &Kinds) -> bool {
        match self {
            Kind::Point => kinds.points,
            Kind::Line => kinds.lines,
            Kind::Plane => kinds.planes,
        }
    }
}

/// Adds an observation, with its map and noise model, to a pose problem.
type Adder = Box<dyn Fn(&mut PoseProblem) -> Result<usize, PoseError>>;

/// One observation of a frame.
pub struct Observation {
    /// What it measures.
    pub kind: Kind,
    /// Its index in the file's `factors`.
    pub factor: usize,
    add: Adder,
}

impl Observation {
    /// Adds it to `problem`.
    ///
    /// # Errors
    ///
    /// The problem's refusal ([`PoseProblem::add`]).
    pub fn add_to(&self, problem: &mut PoseProblem) -> Result<usize, PoseError> {
        (self.add)(problem)
    }
}

/// One frame: a pose variable.
pub struct Frame {
    /// The variable's name.
    pub name: String,
    /// Its true pose (world to camera).
    pub truth: Se3<f64>,
    /// The observations that name it, in file order.
    pub observations: Vec<Observation>,
}

/// The sequence of a problem file.
pub struct Sequence {
    /// The file's JSON.
    pub json: Value,
    /// The frames, in file order.
    pub frames: Vec<Frame>,
    /// The landmarks the observations hold fixed: points, lines, planes.
    pub map: [usize; 3],
}

/// A tracked factor type: its name, what it measures and how to read it.
struct Tracked {
    name: &'static str,
    kind: Kind,
    residual_dim: usize,
    variables: fn() -> Vec<factor_core::VariableInfo>,
    fields: fn() -> Vec<factor_core::FieldInfo>,
    read: fn(&Object, &Object, Whitening) -> Result<Adder, InputError>,
}

fn tracked<F: Factor + 'static>(kind: Kind) -> Tracked {
    Tracked {
        name: F::NAME,
        kind,
        residual_dim: F::RESIDUAL_DIM,
        variables: F::variables,
        fields: F::fields,
        read: |variables, constants, whitening| {
            let factor: F = decode(variables, constants)?;
            Ok(Box::new(move |problem| problem.add(&factor, &whitening)))
        },
    }
}

/// The factors `track` reads: one pose against one landmark.
fn tracked_factors() -> [Tracked; 5] {
    [
        tracked::<PointReprojection>(Kind::Point),
        tracked::<LineReprojection>(Kind::Line),
        tracked::<PluckerLineReprojection>(Kind::Line),
        tracked::<LineObservation>(Kind::Line),
        tracked::<PlaneFactor>(Kind::Plane),
    ]
}

/// A world-to-camera pose written `{"rotation": [qx, qy, qz, qw],
/// "translation": [x, y, z]}` at `path`.
fn pose(value: &Value, path: &str) -> Result<Se3<f64>, InputError> {
    let object = Object::new(value, path, &["rotation", "translation"])?;
    let mut input = object.quaternion("rotation")?;
    input.extend(object.numbers("translation", 3)?);
    let stored = <Se3<f64> as Storage<f64>>::from_input(&input)
        .map_err(|e| InputError::new(object.path_of("rotation"), e.message))?;
    Ok(Se3::from_scalars(&stored))
}

/// `Se3` for `Se3<S>`.
fn type_name(info: &str) -> &str {
    info.strip_suffix("<S>").unwrap_or(info)
}

/// Reads the problem file `file` as a sequence, its map from `map`.
///
/// # Errors
///
/// [`CliError::Usage`] for a file that cannot be read; [`CliError::Input`]
/// naming the field at fault (exit 2): malformed JSON or problem, no truth
/// for a pose (or, with [`MapSource::Truth`], for a landmark), a factor
/// that is not one pose against one landmark, a robust loss.
pub fn read(file: &Path, map: MapSource) -> Result<Sequence, CliError> {
    let json = read_json(file)?;
    let declared = variables(&json);
    for (name, spec) in declared {
        open(
            spec,
            &join("variables", name),
            &["type", "value"],
            &["fixed"],
        )?
        .string("type")?;
    }
    let truth = json.get("truth").ok_or_else(|| {
        InputError::new(
            "truth",
            "missing: track starts frame 0 at its true pose and measures the errors against \
             the truth",
        )
    })?;
    Truth::read(truth, declared)?;
    let mut frames = Vec::new();
    for (name, spec) in declared.iter().filter(|(_, s)| s["type"] == "Se3") {
        let at = join("truth", name);
        let value = truth
            .get(name)
            .ok_or_else(|| InputError::new(&at, "missing: every pose needs its truth"))?;
        frames.push(Frame {
            name: name.clone(),
            truth: pose(value, &at)?,
            observations: Vec::new(),
        });
        pose(&spec["value"], &join(&join("variables", name), "value"))?;
    }
    if frames.is_empty() {
        return Err(InputError::new("variables", "no Se3 variable: no frame to track").into());
    }
    let factors = json["factors"]
        .as_array()
        .ok_or_else(|| InputError::new("factors", "expected an array of factors"))?;
    let tracked = tracked_factors();
    let mut landmarks: HashMap<&str, Kind> = HashMap::new();
    for (k, spec) in factors.iter().enumerate() {
        let path = format!("factors[{k}]");
        let object = open(
            spec,
            &path,
            &["factor", "variables", "constants"],
            &["noise", "robust"],
        )?;
        if spec.get("robust").is_some() {
            return Err(InputError::new(
                object.path_of("robust"),
                "track solves least squares: no robust loss",
            )
            .into());
        }
        let factor = object.string("factor")?;
        let entry = tracked.iter().find(|t| t.name == factor).ok_or_else(|| {
            let names: Vec<&str> = tracked.iter().map(|t| t.name).collect();
            InputError::new(
                object.path_of("factor"),
                format!(
                    "{} is not a factor of one pose against one landmark; track reads {}",
                    quoted(factor),
                    names.join(", ")
                ),
            )
        })?;
        let infos = (entry.variables)();
        let fields: Vec<&str> = infos.iter().map(|v| v.name).collect();
        let named = object.object("variables", &fields)?;
        let mut values = Map::new();
        let mut frame = None;
        for info in &infos {
            let at = named.path_of(info.name);
            let variable = named.string(info.name)?;
            let spec = declared.get(variable).ok_or_else(|| {
                InputError::new(
                    &at,
                    format!("no variable {} in variables", quoted(variable)),
                )
            })?;
            let declared_type = spec["type"].as_str().unwrap_or_default();
            if declared_type != type_name(info.type_name) {
                return Err(InputError::new(
                    &at,
                    format!(
                        "variable {} is a {declared_type}, the factor's {} is a {}",
                        quoted(variable),
                        info.name,
                        type_name(info.type_name)
                    ),
                )
                .into());
            }
            let value = if declared_type == "Se3" {
                frame = frames.iter().position(|f| f.name == variable);
                &spec["value"]
            } else {
                landmarks.insert(variable, entry.kind);
                match map {
                    MapSource::Values => &spec["value"],
                    MapSource::Truth => truth.get(variable).ok_or_else(|| {
                        InputError::new(
                            join("truth", variable),
                            "missing: the map of the truth (--map truth) needs every \
                             landmark's",
                        )
                    })?,
                }
            };
            values.insert(info.name.to_owned(), value.clone());
        }
        let values = Value::Object(values);
        let variables = Object::new(&values, &object.path_of("variables"), &fields)?;
        let constant_fields: Vec<&str> = (entry.fields)()
            .into_iter()
            .filter(|f| f.variable.is_none())
            .map(|f| f.name)
            .collect();
        let constants = object.object("constants", &constant_fields)?;
        let whitening = match spec.get("noise") {
            Some(value) => {
                use factor_apex::builder::Noise;
                match noise(value, &object.path_of("noise"), entry.residual_dim)? {
                    Noise::Unit => Whitening::Unit,
                    Noise::Sigma(sigma) => Whitening::Sigma(sigma),
                    Noise::Sigmas(sigmas) => Whitening::SqrtInformation(
                        nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_iterator(
                            sigmas.len(),
                            sigmas.iter().map(|s| 1.0 / s),
                        )),
                    ),
                    Noise::SqrtInformation(s) => Whitening::SqrtInformation(s),
                }
            }
            None => Whitening::Unit,
        };
        let add = (entry.read)(&variables, &constants, whitening)?;
        let frame = frame.expect("every tracked factor has an `Se3` pose");
        frames[frame].observations.push(Observation {
            kind: entry.kind,
            factor: k,
            add,
        });
    }
    let count = |kind| landmarks.values().filter(|k| **k == kind).count();
    let map = [count(Kind::Point), count(Kind::Line), count(Kind::Plane)];
    Ok(Sequence { json, frames, map })
}
