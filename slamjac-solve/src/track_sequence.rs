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
use factor_core::noise::Noise;
use factor_core::{Factor, Storage};
use factor_tracking::{PoseError, PoseProblem};
use slam_factors::{
    LineObservation, LineReprojection, PlaneFactor, PluckerLineReprojection, PointReprojection,
};
use slamjac_problem::InputError;
use slamjac_problem::decode::decode;
use slamjac_problem::document::{Document, Json};
use slamjac_problem::field_path::{join, quoted};
use slamjac_problem::input::Object;

use slamjac_problem::checks::{self, Shape, at_value, read_json};

use slamjac_problem::synthetic_room::Kinds;

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
    pub json: Document,
    /// The frames, in file order.
    pub frames: Vec<Frame>,
    /// The landmarks the observations hold fixed: points, lines, planes.
    pub map: [usize; 3],
}

/// A tracked factor type: its name, what it measures and how to read it.
struct Tracked {
    name: &'static str,
    kind: Kind,
    shape: fn() -> Shape,
    read: fn(&Object, &Object, Noise) -> Result<Adder, InputError>,
}

fn tracked<F: Factor + 'static>(kind: Kind) -> Tracked {
    Tracked {
        name: F::NAME,
        kind,
        shape: Shape::of::<F>,
        read: |variables, constants, noise| {
            let factor: F = decode(variables, constants)?;
            Ok(Box::new(move |problem| problem.add(&factor, &noise)))
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
fn pose(value: Json<'_>, path: &str) -> Result<Se3<f64>, InputError> {
    let object = Object::new(value, path, &["rotation", "translation"])?;
    let mut input = object.quaternion("rotation")?;
    input.extend(object.numbers("translation", 3)?);
    let stored = <Se3<f64> as Storage<f64>>::from_input(&input)
        .map_err(|e| InputError::new(object.path_of("rotation"), e.message))?;
    Ok(Se3::from_scalars(&stored))
}

/// Reads the problem file `file` as a sequence, its map from `map`.
///
/// # Errors
///
/// As a solve of the same file (`slamjac_problem::checks`: the field at
/// fault, values checked by their types); and a factor that is not one
/// pose against one landmark, a robust loss, no truth for a pose (or, with
/// [`MapSource::Truth`], for a landmark): each an [`InputError`] at its
/// field path.
pub fn read(file: &Path, map: MapSource) -> Result<Sequence, InputError> {
    let json = read_json(file)?;
    let tracked = tracked_factors();
    let checked = checks::check(&json, |factor, path| {
        let entry = tracked.iter().find(|t| t.name == factor).ok_or_else(|| {
            let names: Vec<&str> = tracked.iter().map(|t| t.name).collect();
            InputError::new(
                path,
                format!(
                    "{} is not a factor of one pose against one landmark; track reads {}",
                    quoted(factor),
                    names.join(", ")
                ),
            )
        })?;
        Ok((entry.shape)())
    })?;
    let declared = checked.declared;
    let truth = json.root().get("truth").ok_or_else(|| {
        InputError::new(
            "truth",
            "missing: track starts frame 0 at its true pose and measures the errors against \
             the truth",
        )
    })?;
    let mut frames = Vec::new();
    fn type_of(spec: Json<'_>) -> Option<&str> {
        spec.get("type").and_then(Json::as_str)
    }
    fn value_of(spec: Json<'_>) -> Json<'_> {
        spec.get("value")
            .expect("checked: every variable has a value")
    }
    for (name, spec) in declared.iter().filter(|(_, s)| type_of(*s) == Some("Se3")) {
        let at = join("truth", name);
        let value = truth
            .get(name)
            .ok_or_else(|| InputError::new(&at, "missing: every pose needs its truth"))?;
        frames.push(Frame {
            name: name.to_owned(),
            truth: pose(value, &at)?,
            observations: Vec::new(),
        });
        pose(value_of(spec), &join(&join("variables", name), "value"))?;
    }
    if frames.is_empty() {
        return Err(InputError::new(
            "variables",
            "no Se3 variable: no frame to track",
        ));
    }
    let mut landmarks: HashMap<&str, Kind> = HashMap::new();
    for (k, entry) in checked.entries.iter().enumerate() {
        if entry.robust.is_some() {
            return Err(InputError::new(
                join(&entry.path, "robust"),
                "track solves least squares: no robust loss",
            ));
        }
        let tracked = tracked
            .iter()
            .find(|t| t.name == entry.factor)
            .expect("checked: a tracked factor");
        // The file's values, decoded as `solve` decodes them.
        let mut add = (tracked.read)(&entry.variables(), &entry.constants, entry.noise.clone())
            .map_err(|e| at_value(e, entry))?;
        let mut frame = None;
        let mut values = Vec::with_capacity(entry.names.len());
        for (field, variable) in &entry.names {
            let spec = declared
                .get(variable)
                .expect("checked: a declared variable");
            let value = if type_of(spec) == Some("Se3") {
                frame = frames.iter().position(|f| f.name == *variable);
                value_of(spec)
            } else {
                landmarks.insert(variable, tracked.kind);
                match map {
                    MapSource::Values => value_of(spec),
                    MapSource::Truth => truth.get(variable).ok_or_else(|| {
                        InputError::new(
                            join("truth", variable),
                            "missing: the map of the truth (--map truth) needs every \
                             landmark's",
                        )
                    })?,
                }
            };
            values.push((*field, value));
        }
        if map == MapSource::Truth {
            // The map at its truth (checked as values are by `checks`).
            let variables = Object::gathered(&join(&entry.path, "variables"), values);
            add = (tracked.read)(&variables, &entry.constants, entry.noise.clone())?;
        }
        let frame = frame.expect("every tracked factor has an `Se3` pose");
        frames[frame].observations.push(Observation {
            kind: tracked.kind,
            factor: k,
            add,
        });
    }
    let count = |kind| landmarks.values().filter(|k| **k == kind).count();
    let map = [count(Kind::Point), count(Kind::Line), count(Kind::Plane)];
    Ok(Sequence { json, frames, map })
}
