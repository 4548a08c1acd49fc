//! `slamjac synth-plp`: a seeded point-line-plane room (crate `slam-data`'s
//! `plp_scene`) written as a problem file (`src/solve/problem_file.rs`,
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
//! - Only landmarks measured more often than their degrees of freedom
//!   demand enter (points seen at least twice, lines at least three times:
//!   two views fit a line exactly, however noisy; planes once), and only
//!   cameras with a measurement.
//!
//! The same seed writes the same file on every platform.

use std::path::Path;

use factor_core::geometry::InfinitePlane;
use factor_core::lie::{Quaternion, Se3, So3};
use nalgebra::{Isometry3, Matrix3, Vector3, Vector4};
use serde_json::{Map, Value, json};
use slam_data::plp_scene::{self, PlpConfig, PlpScene};
use slamjac_io::Role;

use crate::error::CliError;
use crate::field_path::shown_path;
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

/// Generates the scene and writes the problem file to `output`; describes
/// it in one line.
///
/// # Errors
///
/// Settings the generator refuses or an output that cannot be written
/// ([`CliError::Usage`], exit 2); a plane measurement degenerate at the
/// initial values ([`CliError::Factor`], exit 1).
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

/// Counts per index, of the `indices` given.
fn seen(indices: impl Iterator<Item = usize>, len: usize) -> Vec<usize> {
    let mut counts = vec![0; len];
    for i in indices {
        counts[i] += 1;
    }
    counts
}

impl Problem {
    fn of(scene: &PlpScene, args: &SynthPlpArgs) -> Result<Problem, CliError> {
        let config = &scene.config;
        let intrinsics = vector_json(&config.intrinsics);
        let sigma = json!({"sigma": config.pixel_sigma});
        let mut problem = Problem {
            variables: Map::new(),
            truth: Map::new(),
            factors: Vec::new(),
            counts: [0; 4],
        };
        let (truth, initial) = (&scene.truth, &scene.initial);
        let mut cameras_used = vec![false; truth.cameras.len()];
        if args.kinds.points {
            let views = seen(
                scene.point_observations.iter().map(|o| o.point),
                truth.points.len(),
            );
            for o in scene
                .point_observations
                .iter()
                .filter(|o| views[o.point] >= 2)
            {
                cameras_used[o.camera] = true;
                problem.factors.push(json!({
                    "factor": "point_reprojection",
                    "variables": {"pose": format!("c{}", o.camera), "point": format!("p{}", o.point)},
                    "constants": {"intrinsics": intrinsics, "observed": [o.pixel.x, o.pixel.y]},
                    "noise": sigma,
                }));
            }
            for (i, _) in views.iter().enumerate().filter(|(_, v)| **v >= 2) {
                problem.add(
                    format!("p{i}"),
                    "Vector3",
                    vector_json(initial.points[i].as_slice()),
                    vector_json(truth.points[i].as_slice()),
                    false,
                );
                problem.counts[1] += 1;
            }
        }
        if args.kinds.lines {
            let kept = args.lines.min(truth.segments.len());
            let views = seen(
                scene
                    .segment_observations
                    .iter()
                    .map(|o| o.segment)
                    .filter(|s| *s < kept),
                kept,
            );
            for o in scene
                .segment_observations
                .iter()
                .filter(|o| o.segment < kept && views[o.segment] >= 3)
            {
                cameras_used[o.camera] = true;
                problem.factors.push(json!({
                    "factor": "line_reprojection",
                    "variables": {"pose": format!("c{}", o.camera), "line": format!("l{}", o.segment)},
                    "constants": {"intrinsics": intrinsics, "start": [o.start.x, o.start.y], "end": [o.end.x, o.end.y]},
                    "noise": sigma,
                }));
            }
            for (i, _) in views.iter().enumerate().filter(|(_, v)| **v >= 3) {
                let (s0, s) = (&initial.segments[i], &truth.segments[i]);
                problem.add(
                    format!("l{i}"),
                    "OrthonormalLine",
                    line_json(&s0.start, &s0.end),
                    line_json(&s.start, &s.end),
                    false,
                );
                problem.counts[2] += 1;
            }
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
            let mut planes_used = vec![false; truth.planes.len()];
            for o in &scene.plane_observations {
                let plane = plane_of(&initial.planes[o.plane]);
                let camera_to_world = se3(&initial.cameras[o.camera].inverse());
                let (_, residual_information) = slam_factors::g2o::plane_observation(
                    &camera_to_world,
                    &plane,
                    &Se3::identity(),
                    &o.measured,
                    &information,
                )?;
                let upper = residual_information
                    .cholesky()
                    .ok_or_else(|| {
                        CliError::Solve(format!(
                            "plane {} seen by camera {}: the information in the residual space \
                             is not positive definite",
                            o.plane, o.camera
                        ))
                    })?
                    .l()
                    .transpose();
                let rows: Vec<Value> = upper
                    .row_iter()
                    .map(|r| vector_json(&[r[0], r[1], r[2]]))
                    .collect();
                cameras_used[o.camera] = true;
                planes_used[o.plane] = true;
                problem.factors.push(json!({
                    "factor": "plane",
                    "variables": {"pose": format!("c{}", o.camera), "plane": format!("pi{}", o.plane)},
                    "constants": {"measured": vector_json(o.measured.as_slice())},
                    "noise": {"sqrt_information": rows},
                }));
            }
            for (i, _) in planes_used.iter().enumerate().filter(|(_, u)| **u) {
                problem.add(
                    format!("pi{i}"),
                    "InfinitePlane",
                    vector_json(initial.planes[i].as_slice()),
                    vector_json(truth.planes[i].as_slice()),
                    false,
                );
                problem.counts[3] += 1;
            }
        }
        for (i, _) in cameras_used.iter().enumerate().filter(|(_, u)| **u) {
            // The gauge: the first two cameras at their true poses.
            let fixed = i < 2;
            let start = if fixed {
                &truth.cameras[i]
            } else {
                &initial.cameras[i]
            };
            problem.add(
                format!("c{i}"),
                "Se3",
                pose_json(start),
                pose_json(&truth.cameras[i]),
                fixed,
            );
            problem.counts[0] += 1;
        }
        Ok(problem)
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
            "slamjac_problem": crate::PROBLEM_FILE_VERSION,
            "variables": self.variables,
            "factors": self.factors,
            "truth": self.truth,
        })
    }
}

/// The factors' plane of `[n, d]`.
fn plane_of(plane: &Vector4<f64>) -> InfinitePlane<f64> {
    InfinitePlane::from_normal_offset(&plane.xyz(), plane.w)
}
