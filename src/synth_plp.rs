//! `slamjac synth-plp`: a seeded point-line-plane room (crate `slam-data`'s
//! `plp_scene`) written as a problem file (`slamjac-solve/src/problem_file.rs`,
//! read by `slamjac solve FILE.json`) of the documents' factors, with its
//! ground truth.
//!
//! - Cameras `c0, c1, …` (`Se3`, world to camera); points `p0, …`
//!   (`Vector3`); lines `l0, …` (`OrthonormalLine`, the infinite lines of the
//!   scene's segments); planes `pi0, …` (`InfinitePlane`, the room's faces).
//!   Initial values are the scene's perturbed ones; `truth` holds the true
//!   value of every variable, in the same JSON form as `value`.
//! - `point_reprojection` per point observation, σ = the pixel noise;
//!   `line_reprojection` per segment observation (the distances of the two
//!   noisy endpoints to the projected line), σ = the pixel noise;
//!   `plane` per plane observation, its noise model the measurement's
//!   (normal turned by σ_θ per axis, offset moved by σ_d) moved into the
//!   residual space by the residual's Jacobian w.r.t. the measurement at the
//!   initial values (`slam_factors::g2o::plane_observation`, identity sensor
//!   offset): a square-root information linearised once, as a user who
//!   knows only the sensor's noise would compute it.
//! - Gauge: cameras `c0` and `c1` are fixed at their true poses. The first
//!   fixes the frame; the second fixes the scale, which points and lines
//!   seen in pixels leave free (planes' offsets would fix it, but every
//!   kind combination gets the same gauge so that their errors compare).
//! - Only measurements defined at the written initial values enter (a
//!   perturbed point can fall behind a camera that sees it: issue 28, where
//!   5 of seeds 1–20 of the guide's tracking configuration wrote one that
//!   `solve` then refused); only landmarks measured more often than their
//!   degrees of freedom demand (points seen at least twice, lines at least
//!   three times: two views fit a line exactly, however noisy; planes
//!   once), lines only from views whose interpretation planes span at least
//!   1° (`MIN_LINE_PARALLAX`), and only cameras with a measurement.
//! - A problem whose measurements do not determine its free variables (a
//!   camera that sees two walls and nothing else, a plane seen only by
//!   free cameras: [`slamjac_problem::observability`], at the true values
//!   and at the written initial values) is refused naming the directions nothing
//!   determines; nothing is written. A problem observable at both can still
//!   be drawn by the solve into a configuration that is not (`--cameras 4`:
//!   a wall seen only by free cameras rotated parallel to another); `solve`
//!   refuses that solution.
//!
//! The same seed writes the same file on every platform.

use std::path::Path;

use std::collections::{BTreeSet, HashMap};

use factor_core::Factor;
use factor_core::geometry::{InfinitePlane, Intrinsics, OrthonormalLine};
use factor_core::lie::{Quaternion, Se3, So3};
use nalgebra::{DMatrix, Isometry3, Matrix3, Vector3, Vector4};
use serde_json::{Map, Value, json};
use slam_data::plp_scene::{self, PlpConfig, PlpScene, PlpState, Segment};
use slam_factors::{LineReprojection, PlaneFactor, PointReprojection};
use slamjac_io::Role;
use slamjac_problem::field_path::shown_path;
use slamjac_problem::observability::{Normal, Variable};

use crate::error::CliError;
use crate::method::{Method, linearize};
use crate::outputs;

/// The measurement kinds a problem holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Kinds {
    /// Point reprojections.
    pub points: bool,
    /// Line reprojections.
    pub lines: bool,
    /// Plane measurements.
    pub planes: bool,
}

/// `points,lines,planes`, the kinds selected, as [`Kinds::from_str`](std::str::FromStr) reads them.
impl std::fmt::Display for Kinds {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names = [
            (self.points, "points"),
            (self.lines, "lines"),
            (self.planes, "planes"),
        ];
        let selected: Vec<&str> = names.iter().filter(|(s, _)| *s).map(|(_, n)| *n).collect();
        f.write_str(&selected.join(","))
    }
}

impl std::str::FromStr for Kinds {
    type Err = String;

    /// `points,lines,planes` or any non-empty part of it.
    fn from_str(text: &str) -> Result<Kinds, String> {
        let mut kinds = Kinds {
            points: false,
            lines: false,
            planes: false,
        };
        for kind in text.split(',') {
            match kind.trim() {
                "points" => kinds.points = true,
                "lines" => kinds.lines = true,
                "planes" => kinds.planes = true,
                other => {
                    return Err(format!(
                        "unknown kind {other:?}; expected points, lines or planes, comma-separated"
                    ));
                }
            }
        }
        Ok(kinds)
    }
}

/// What to generate, as the command line gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct SynthPlpArgs {
    /// Seed of the random generator.
    pub seed: u64,
    /// Cameras.
    pub cameras: usize,
    /// Points: two thirds on the planes, the rest in the volume.
    pub points: usize,
    /// Lines: the scene's first `lines` segments (the 12 box edges, then 2
    /// doors of 3 segments each, then wall segments).
    pub lines: usize,
    /// Which measurements enter.
    pub kinds: Kinds,
}

/// Segments of the room other than its wall segments: 12 edges, 2 doors.
const FIXED_SEGMENTS: usize = 12 + 3 * 2;

/// The gauge: cameras `c0` and `c1` fixed at their true poses.
const FIXED_CAMERAS: usize = 2;

/// The least angle (radians) between two of a line's interpretation planes
/// (each through a camera centre that sees it and the line itself, at the
/// truth) for the line to be written: 1°, about the parallax ORB-SLAM's
/// triangulation asks of a point (cosine below 0.9998, 1.1°). Views whose
/// planes all but coincide leave the line's depth to the noise; on the
/// default room such lines (0.08–0.22° in seeds 1, 11 and 19) drew the
/// solve, from the truth itself, toward the singular configuration of a
/// line through the cameras.
const MIN_LINE_PARALLAX: f64 = std::f64::consts::PI / 180.0;

/// Generates the scene and writes the problem file to `output`; describes
/// it in one line.
///
/// # Errors
///
/// Settings the generator refuses, a problem it would write that is not
/// observable, or an output that cannot be written ([`CliError::Usage`],
/// exit 2).
pub fn run(args: &SynthPlpArgs, output: &Path) -> Result<String, CliError> {
    outputs::check(&[], &[Role::new("--output", output)])?;
    let plane_points = args.points * 2 / 3;
    let config = PlpConfig {
        cameras: args.cameras,
        plane_points,
        volume_points: args.points - plane_points,
        wall_segments: args.lines.saturating_sub(FIXED_SEGMENTS),
        ..PlpConfig::room(args.seed)
    };
    let scene = plp_scene::generate(&config).map_err(|e| CliError::Usage(e.to_string()))?;
    let problem = Problem::of(&scene, args)?;
    if problem.factors.is_empty() {
        return Err(CliError::Usage(format!(
            "synth-plp: nothing measured with --cameras {} --kinds {} (seed {}): a point enters \
             when two cameras see it, a line when three do; use more cameras or other kinds",
            args.cameras, args.kinds, args.seed
        )));
    }
    let summary = format!(
        "wrote {}: {} cameras, {} points, {} lines, {} planes, {} factors, seed {}",
        shown_path(output),
        problem.counts[0],
        problem.counts[1],
        problem.counts[2],
        problem.counts[3],
        problem.factors.len(),
        args.seed
    );
    outputs::write(output, crate::pretty::to_string(&problem.json()) + "\n")?;
    Ok(summary)
}

/// The problem file being assembled.
struct Problem {
    variables: Map<String, Value>,
    truth: Map<String, Value>,
    factors: Vec<Value>,
    /// Cameras, points, lines, planes written.
    counts: [usize; 4],
}

/// The JSON of a world-to-camera pose.
fn pose_json(pose: &Isometry3<f64>) -> Value {
    let q = pose.rotation.coords;
    let t = pose.translation.vector;
    json!({"rotation": [q.x, q.y, q.z, q.w], "translation": [t.x, t.y, t.z]})
}

/// The JSON of the line through `p` and `q` (Plücker `[p × q, q − p]`).
fn line_json(p: &Vector3<f64>, q: &Vector3<f64>) -> Value {
    let (n, v) = (p.cross(q), q - p);
    json!({"normal": [n.x, n.y, n.z], "direction": [v.x, v.y, v.z]})
}

fn vector_json(v: &[f64]) -> Value {
    Value::from(v.to_vec())
}

/// `pose` as the factors' `Se3`.
fn se3(pose: &Isometry3<f64>) -> Se3<f64> {
    let q = pose.rotation.coords;
    Se3::new(
        So3::from_quaternion(Quaternion::new(q.x, q.y, q.z, q.w)),
        pose.translation.vector,
    )
}

/// A measurement the file keeps: its factor entry, the camera it is taken
/// from, the landmark variable it measures, and its whitened Jacobians
/// (camera, landmark) at the written initial values and at the truth.
struct Measurement {
    camera: usize,
    landmark: String,
    json: Value,
    jacobians: [[DMatrix<f64>; 2]; 2],
}

/// Which values the observability check linearizes at.
#[derive(Clone, Copy)]
enum At {
    Initial = 0,
    Truth = 1,
}

/// The whitened Jacobians (pose, landmark) of `factor` at its values,
/// `S J` for the square-root information `s`; `None` where the factor is
/// undefined (a point behind the camera, a line through its centre).
fn jacobians<F: Factor>(factor: &F, s: &DMatrix<f64>) -> Option<[DMatrix<f64>; 2]> {
    let (linearization, _) = linearize(factor, Method::Generated).ok()?;
    let [pose, landmark] = <[DMatrix<f64>; 2]>::try_from(linearization.jacobians).ok()?;
    Some([s * pose, s * landmark])
}

/// How many of `measurements` measure each landmark.
fn views(measurements: &[Measurement]) -> HashMap<&str, usize> {
    let mut views = HashMap::new();
    for m in measurements {
        *views.entry(m.landmark.as_str()).or_insert(0) += 1;
    }
    views
}

/// The normal of the interpretation plane of `segment` seen from a camera
/// whose world-to-camera pose is `camera`: the plane through the camera
/// centre and the segment.
fn interpretation_plane(segment: &Segment, camera: &Isometry3<f64>) -> Vector3<f64> {
    let centre = camera.inverse().translation.vector;
    (segment.start - centre)
        .cross(&(segment.end - centre))
        .normalize()
}

/// The largest angle between two of the planes of unit `normals`.
fn widest_angle(normals: &[Vector3<f64>]) -> f64 {
    let mut widest: f64 = 0.0;
    for (i, a) in normals.iter().enumerate() {
        for b in &normals[i + 1..] {
            widest = widest.max(a.dot(b).abs().min(1.0).acos());
        }
    }
    widest
}

impl Problem {
    /// The problem of `scene`: the measurements of `args.kinds` defined at
    /// the written initial values (any other is left out: the file must be
    /// solvable from its values), of the landmarks measured often enough.
    ///
    /// # Errors
    ///
    /// The problem would not be observable ([`CliError::Usage`], naming
    /// the directions nothing determines).
    fn of(scene: &PlpScene, args: &SynthPlpArgs) -> Result<Problem, CliError> {
        let config = &scene.config;
        let [fu, fv, cu, cv] = config.intrinsics;
        let intrinsics = Intrinsics::new(fu, fv, cu, cv);
        let sigma = json!({"sigma": config.pixel_sigma});
        let pixel = DMatrix::from_diagonal_element(2, 2, 1.0 / config.pixel_sigma);
        let (truth, initial) = (&scene.truth, &scene.initial);
        // The written initial pose: the gauge's cameras at their truth.
        let start = |i: usize| {
            if i < FIXED_CAMERAS {
                &truth.cameras[i]
            } else {
                &initial.cameras[i]
            }
        };
        let mut measurements: Vec<Measurement> = Vec::new();
        if args.kinds.points {
            let mut points = Vec::new();
            for o in &scene.point_observations {
                let at = |camera: &Isometry3<f64>, state: &PlpState| {
                    let factor = PointReprojection {
                        intrinsics,
                        observed: o.pixel,
                        pose: se3(camera),
                        point: state.points[o.point],
                    };
                    jacobians(&factor, &pixel)
                };
                if let (Some(initially), Some(truly)) = (
                    at(start(o.camera), initial),
                    at(&truth.cameras[o.camera], truth),
                ) {
                    points.push(Measurement {
                        camera: o.camera,
                        landmark: format!("p{}", o.point),
                        json: json!({
                            "factor": "point_reprojection",
                            "variables": {"pose": format!("c{}", o.camera), "point": format!("p{}", o.point)},
                            "constants": {"intrinsics": config.intrinsics, "observed": [o.pixel.x, o.pixel.y]},
                            "noise": sigma,
                        }),
                        jacobians: [initially, truly],
                    });
                }
            }
            let views = views(&points);
            let seen: Vec<bool> = points
                .iter()
                .map(|m| views[m.landmark.as_str()] >= 2)
                .collect();
            measurements.extend(
                points
                    .into_iter()
                    .zip(seen)
                    .filter(|(_, s)| *s)
                    .map(|(m, _)| m),
            );
        }
        if args.kinds.lines {
            let kept = args.lines.min(truth.segments.len());
            let mut lines = Vec::new();
            // Per line, the interpretation planes of its kept views, at the
            // truth.
            let mut planes: HashMap<usize, Vec<Vector3<f64>>> = HashMap::new();
            for o in scene
                .segment_observations
                .iter()
                .filter(|o| o.segment < kept)
            {
                let at = |camera: &Isometry3<f64>, state: &PlpState| {
                    let s = &state.segments[o.segment];
                    let line = OrthonormalLine::try_from_points(&s.start, &s.end).ok()?;
                    let factor = LineReprojection {
                        intrinsics,
                        start: o.start,
                        end: o.end,
                        pose: se3(camera),
                        line,
                    };
                    jacobians(&factor, &pixel)
                };
                if let (Some(initially), Some(truly)) = (
                    at(start(o.camera), initial),
                    at(&truth.cameras[o.camera], truth),
                ) {
                    planes
                        .entry(o.segment)
                        .or_default()
                        .push(interpretation_plane(
                            &truth.segments[o.segment],
                            &truth.cameras[o.camera],
                        ));
                    lines.push(Measurement {
                        camera: o.camera,
                        landmark: format!("l{}", o.segment),
                        json: json!({
                            "factor": "line_reprojection",
                            "variables": {"pose": format!("c{}", o.camera), "line": format!("l{}", o.segment)},
                            "constants": {"intrinsics": config.intrinsics, "start": [o.start.x, o.start.y], "end": [o.end.x, o.end.y]},
                            "noise": sigma,
                        }),
                        jacobians: [initially, truly],
                    });
                }
            }
            let views = views(&lines);
            let parallax: HashMap<String, f64> = planes
                .iter()
                .map(|(segment, normals)| (format!("l{segment}"), widest_angle(normals)))
                .collect();
            let seen: Vec<bool> = lines
                .iter()
                .map(|m| {
                    let name = m.landmark.as_str();
                    views[name] >= 3 && parallax[name] >= MIN_LINE_PARALLAX
                })
                .collect();
            measurements.extend(
                lines
                    .into_iter()
                    .zip(seen)
                    .filter(|(_, s)| *s)
                    .map(|(m, _)| m),
            );
        }
        if args.kinds.planes {
            // The measurement's noise in g2o's chart of it (azimuth and
            // elevation of the normal, unit-speed tangent directions at the
            // measured normal, and the offset).
            let information = Matrix3::from_diagonal(&Vector3::new(
                config.plane_angle_sigma.powi(-2),
                config.plane_angle_sigma.powi(-2),
                config.plane_offset_sigma.powi(-2),
            ));
            for o in &scene.plane_observations {
                // The factor and its square-root information, upper
                // triangular, at a camera and planes.
                let at = |camera: &Isometry3<f64>, state: &PlpState| {
                    let (factor, residual_information) = slam_factors::g2o::plane_observation(
                        &se3(&camera.inverse()),
                        &plane_of(&state.planes[o.plane]),
                        &Se3::identity(),
                        &o.measured,
                        &information,
                    )
                    .ok()?;
                    let upper = residual_information.cholesky()?.l().transpose();
                    let s = DMatrix::from_column_slice(3, 3, upper.as_slice());
                    Some((jacobians(&factor, &s)?, upper))
                };
                if let (Some((initially, upper)), Some((truly, _))) = (
                    at(start(o.camera), initial),
                    at(&truth.cameras[o.camera], truth),
                ) {
                    let rows: Vec<Value> = upper
                        .row_iter()
                        .map(|r| vector_json(&[r[0], r[1], r[2]]))
                        .collect();
                    measurements.push(Measurement {
                        camera: o.camera,
                        landmark: format!("pi{}", o.plane),
                        json: json!({
                            "factor": "plane",
                            "variables": {"pose": format!("c{}", o.camera), "plane": format!("pi{}", o.plane)},
                            "constants": {"measured": vector_json(o.measured.as_slice())},
                            "noise": {"sqrt_information": rows},
                        }),
                        jacobians: [initially, truly],
                    });
                }
            }
        }
        let mut problem = Problem {
            variables: Map::new(),
            truth: Map::new(),
            factors: measurements.iter().map(|m| m.json.clone()).collect(),
            counts: [0; 4],
        };
        // Points, lines, planes, each by index, as the scene lists them.
        let landmarks: BTreeSet<(u8, usize, &str)> = measurements
            .iter()
            .map(|m| {
                let name = m.landmark.as_str();
                let at = name.find(|c: char| c.is_ascii_digit()).expect("an index");
                let kind = match &name[..at] {
                    "p" => 0,
                    "l" => 1,
                    _ => 2,
                };
                (kind, name[at..].parse().expect("an index"), name)
            })
            .collect();
        let landmarks: Vec<&str> = landmarks.into_iter().map(|(_, _, name)| name).collect();
        let mut cameras: Vec<usize> = measurements.iter().map(|m| m.camera).collect();
        cameras.sort_unstable();
        cameras.dedup();
        // Refused where the truth is not observable (parallel walls seen by
        // a free camera: a perturbation at the initial values hides it) or
        // the written values are not.
        observable(&measurements, &cameras, &landmarks, args, At::Truth)?;
        observable(&measurements, &cameras, &landmarks, args, At::Initial)?;
        for name in &landmarks {
            problem.add_landmark(name, truth, initial);
        }
        for i in cameras {
            let fixed = i < FIXED_CAMERAS;
            problem.add(
                format!("c{i}"),
                "Se3",
                pose_json(start(i)),
                pose_json(&truth.cameras[i]),
                fixed,
            );
            problem.counts[0] += 1;
        }
        Ok(problem)
    }

    /// Adds the landmark `name` (`p3`, `l0`, `pi2`) with its initial value
    /// and its truth.
    fn add_landmark(&mut self, name: &str, truth: &PlpState, initial: &PlpState) {
        let (kind, index) = name
            .find(|c: char| c.is_ascii_digit())
            .map(|at| name.split_at(at))
            .expect("a landmark name ends in its index");
        let i: usize = index.parse().expect("an index");
        let (type_name, value, true_value, count) = match kind {
            "p" => (
                "Vector3",
                vector_json(initial.points[i].as_slice()),
                vector_json(truth.points[i].as_slice()),
                1,
            ),
            "l" => {
                let (s0, s) = (&initial.segments[i], &truth.segments[i]);
                (
                    "OrthonormalLine",
                    line_json(&s0.start, &s0.end),
                    line_json(&s.start, &s.end),
                    2,
                )
            }
            _ => (
                "InfinitePlane",
                vector_json(initial.planes[i].as_slice()),
                vector_json(truth.planes[i].as_slice()),
                3,
            ),
        };
        self.add(name.to_owned(), type_name, value, true_value, false);
        self.counts[count] += 1;
    }

    fn add(&mut self, name: String, kind: &str, value: Value, truth: Value, fixed: bool) {
        let mut variable = json!({"type": kind, "value": value});
        if fixed {
            variable["fixed"] = Value::Bool(true);
        }
        self.variables.insert(name.clone(), variable);
        self.truth.insert(name, truth);
    }

    fn json(&self) -> Value {
        json!({
            "slamjac_problem": slamjac_problem::PROBLEM_FILE_VERSION,
            "variables": self.variables,
            "factors": self.factors,
            "truth": self.truth,
        })
    }
}

/// Refuses a problem whose free variables its measurements do not
/// determine ([`slamjac_problem::observability`]): the gauge's two
/// cameras are fixed, every other camera and every landmark is free.
fn observable(
    measurements: &[Measurement],
    cameras: &[usize],
    landmarks: &[&str],
    args: &SynthPlpArgs,
    at: At,
) -> Result<(), CliError> {
    let tangent = |info: &factor_core::VariableInfo| info.tangent;
    let pose = tangent(&PointReprojection::<f64>::variables()[0]);
    let mut variables = Vec::new();
    let mut index: HashMap<String, usize> = HashMap::new();
    for i in cameras.iter().filter(|i| **i >= FIXED_CAMERAS) {
        index.insert(format!("c{i}"), variables.len());
        variables.push(Variable::new(format!("c{i}"), pose, 6));
    }
    for name in landmarks {
        let info = match name.trim_end_matches(|c: char| c.is_ascii_digit()) {
            "p" => PointReprojection::<f64>::variables()[1].clone(),
            "l" => LineReprojection::<f64>::variables()[1].clone(),
            _ => PlaneFactor::<f64>::variables()[1].clone(),
        };
        index.insert((*name).to_owned(), variables.len());
        variables.push(Variable::new(*name, info.tangent, info.tangent_dim));
    }
    let mut normal = Normal::new(variables);
    for m in measurements {
        let [camera, landmark] = &m.jacobians[at as usize];
        let mut blocks = vec![(index[m.landmark.as_str()], landmark.clone())];
        if let Some(free) = index.get(&format!("c{}", m.camera)) {
            blocks.push((*free, camera.clone()));
        }
        normal.add(blocks);
    }
    match normal.deficiency() {
        None => Ok(()),
        Some(deficiency) => Err(CliError::Usage(format!(
            "synth-plp: --cameras {} --points {} --lines {} --kinds {} (seed {}) is {}; \
             nothing written: use more cameras, points or lines, or other kinds",
            args.cameras,
            args.points,
            args.lines,
            args.kinds,
            args.seed,
            deficiency.at(match at {
                At::Initial => "the written initial values",
                At::Truth => "the true values",
            })
        ))),
    }
}

/// The factors' plane of `[n, d]`.
fn plane_of(plane: &Vector4<f64>) -> InfinitePlane<f64> {
    InfinitePlane::from_normal_offset(&plane.xyz(), plane.w)
}
