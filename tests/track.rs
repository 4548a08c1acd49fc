//! `slamjac track` (feature `solve`): pose-only tracking of `synth-plp`
//! sequences against their fixed map. One frame solved by the tracker and
//! by apex-solver (through `factor_apex::builder::ProblemBuilder`, the
//! landmarks fixed: an independent solver, chart and linearization path)
//! reaches the same pose; a small sequence is tracked within the noise;
//! frames that cannot be tracked and malformed files get their one-line
//! errors and exit codes.
#![cfg(feature = "solve")]

use std::path::{Path, PathBuf};

use factor_apex::builder::{Noise, ProblemBuilder, stored_value_of};
use factor_apex::solve::{SolveOptions, solve};
use factor_core::Storage;
use factor_core::geometry::{InfinitePlane, Intrinsics, OrthonormalLine};
use factor_core::lie::{Quaternion, Se3, So3};
use factor_core::nalgebra::{DMatrix, Isometry3, Unit};
use factor_tracking::{Options, PoseProblem};
use serde_json::Value;
use slam_data::plp_scene::{PlpConfig, generate};
use slam_factors::{LineReprojection, PlaneFactor, PointReprojection};

mod common;
use common::{slamjac, stderr, stdout};

/// A fresh directory for this file's tests.
fn temp_dir(tag: &str) -> PathBuf {
    common::temp_dir("track", tag)
}

/// `synth-plp --seed 2 --cameras 10` written into `dir`.
fn sequence(dir: &Path) -> PathBuf {
    let file = dir.join("plp.json");
    let output = slamjac(&[
        "synth-plp",
        "--seed",
        "2",
        "--cameras",
        "10",
        "--output",
        file.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    file
}

fn se3(pose: &Isometry3<f64>) -> Se3<f64> {
    let q = pose.rotation.coords;
    Se3::new(
        So3::from_quaternion(Quaternion::new(q.x, q.y, q.z, q.w)),
        pose.translation.vector,
    )
}

/// One noisy frame of a scene (points, lines, planes; the planes whitened
/// by a full square-root information) against its true map, solved by the
/// tracker and by apex-solver from the same perturbed pose, both to
/// convergence: the poses agree to 1e-8 (`|Log(T_a T_b⁻¹)|`).
#[test]
fn a_frame_solved_by_apex_solver_reaches_the_same_pose() {
    let scene = generate(&PlpConfig::room(4)).unwrap();
    let camera = 6;
    let [fu, fv, cu, cv] = scene.config.intrinsics;
    let intrinsics = Intrinsics::new(fu, fv, cu, cv);
    let initial = se3(&scene.initial.cameras[camera]);
    let s = DMatrix::from_row_slice(3, 3, &[80.0, 5.0, -2.0, 0.0, 60.0, 3.0, 0.0, 0.0, 40.0]);
    let mut tracker = PoseProblem::new();
    let mut builder = ProblemBuilder::new();
    let first = scene
        .point_observations
        .iter()
        .find(|o| o.camera == camera)
        .unwrap();
    let pose_factor = PointReprojection {
        intrinsics,
        observed: first.pixel,
        pose: initial,
        point: scene.truth.points[first.point],
    };
    let pose = builder.add_variable_of(&pose_factor, 0);
    // Each factor is added to both, its landmark a fixed variable of its own.
    macro_rules! both {
        ($factor:expr, $whitening:expr, $noise:expr) => {{
            let factor = $factor;
            tracker.add(&factor, &$whitening).unwrap();
            let landmark = builder.add_variable_of(&factor, 1);
            builder.fix_any(&landmark).unwrap();
            builder
                .add_factor(&factor, &[pose.clone(), landmark], &$noise, None)
                .unwrap();
        }};
    }
    for o in scene
        .point_observations
        .iter()
        .filter(|o| o.camera == camera)
    {
        both!(
            PointReprojection {
                intrinsics,
                observed: o.pixel,
                pose: initial,
                point: scene.truth.points[o.point],
            },
            Noise::Sigma(1.0),
            Noise::Sigma(1.0)
        );
    }
    for o in scene
        .segment_observations
        .iter()
        .filter(|o| o.camera == camera)
    {
        let segment = &scene.truth.segments[o.segment];
        both!(
            LineReprojection {
                intrinsics,
                start: o.start,
                end: o.end,
                pose: initial,
                line: OrthonormalLine::try_from_points(&segment.start, &segment.end).unwrap(),
            },
            Noise::Sigma(1.0),
            Noise::Sigma(1.0)
        );
    }
    for o in scene
        .plane_observations
        .iter()
        .filter(|o| o.camera == camera)
    {
        let p = scene.truth.planes[o.plane];
        both!(
            PlaneFactor {
                measured: Unit::new_normalize(o.measured),
                pose: initial,
                plane: InfinitePlane::from_normal_offset(&p.xyz(), p.w),
            },
            Noise::SqrtInformation(s.clone()),
            Noise::SqrtInformation(s.clone())
        );
    }
    let tracked = tracker
        .solve(
            &initial,
            &Options {
                solve: SolveOptions::converged(100),
                ..Options::default()
            },
        )
        .unwrap();
    assert!(tracked.verdict.is_converged(), "{tracked:?}");
    let mut built = builder.build().unwrap();
    let outcome = solve(&mut built, &SolveOptions::converged(100), |_| {}).unwrap();
    let stored = stored_value_of::<PointReprojection>(&outcome.values, &pose, 0);
    let apex = Se3::<f64>::from_scalars(&stored);
    let difference = tracked.pose.compose(&apex.inverse()).log().norm();
    assert!(difference < 1e-8, "{difference:e}");
    // Both minimise the same cost, and moved well away from the start.
    assert!((tracked.cost - outcome.final_cost).abs() <= 1e-9 * outcome.final_cost);
    assert!(tracked.pose.compose(&initial.inverse()).log().norm() > 1e-3);
}

/// A figure of the report: the cell of `column` (0 for the first
/// measurement set) on the row labelled `label`, split at " / ".
fn figure(report: &str, label: &str, column: usize) -> Vec<f64> {
    let line = report
        .lines()
        .find(|l| l.trim_start().starts_with(label))
        .unwrap_or_else(|| panic!("no {label:?} in:\n{report}"));
    let cells: Vec<&str> = line[line.find(label).unwrap() + label.len()..]
        .split("  ")
        .map(str::trim)
        .filter(|c| !c.is_empty())
        .collect();
    cells[column]
        .split([' ', '/', ','])
        .filter_map(|x| x.parse().ok())
        .collect()
}

/// Ten frames of seed 2, the map at the truth: every frame converges and
/// stays within the noise. With 1 px noise on 15–40 observations 2–4 m
/// away seen at 400 px, a camera centre is determined to about
/// `z σ / (f √n)` ≈ 3 m / 400 / 4 ≈ 2 mm per axis (a few times more along
/// the view axis) and its rotation to about `σ / (f √n)` ≈ 0.04°: the
/// bounds, 2 cm and 0.5°, are about 10 standard deviations, and below the
/// files' initial perturbation (0.05 m per axis), which no frame starts
/// from but the tracker's own previous estimate.
#[test]
fn a_small_sequence_is_tracked_within_the_noise() {
    let dir = temp_dir("sequence");
    let file = sequence(&dir);
    let plot = dir.join("errors.svg");
    let tracked = dir.join("tracked.json");
    let output = slamjac(&[
        "track",
        file.to_str().unwrap(),
        "--plot",
        plot.to_str().unwrap(),
        "--output",
        tracked.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let report = stdout(&output);
    assert!(report.contains("10 frames"), "{report}");
    for column in 0..2 {
        assert_eq!(figure(&report, "frames converged", column), [10.0, 10.0]);
        let translation = figure(&report, "translation error (m): median / max", column);
        let rotation = figure(&report, "rotation error (°): median / max", column);
        assert!(translation[1] < 0.02, "{report}");
        assert!(rotation[1] < 0.5, "{report}");
        let ate = figure(&report, "ATE RMSE, no alignment (m)", column)[0];
        assert!(ate <= translation[1] && ate > 0.0, "{report}");
    }
    assert!(std::fs::read_to_string(&plot).unwrap().starts_with("<svg"));
    // Against the files' perturbed landmarks (0.05 m per coordinate) the
    // map's error dominates: a larger ATE than against the exact map.
    let values = slamjac(&["track", file.to_str().unwrap(), "--map", "values"]);
    assert_eq!(values.status.code(), Some(0), "{}", stderr(&values));
    let values = stdout(&values);
    assert!(values.contains("at the file's values"), "{values}");
    for column in 0..2 {
        let exact = figure(&report, "ATE RMSE, no alignment (m)", column)[0];
        let perturbed = figure(&values, "ATE RMSE, no alignment (m)", column)[0];
        assert!(perturbed > 2.0 * exact, "{perturbed} vs {exact}");
    }
    // The output's poses are the tracked ones: tracking from them again
    // (the map unchanged) gives the same errors.
    let json: Value = serde_json::from_str(&std::fs::read_to_string(&tracked).unwrap()).unwrap();
    let input: Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    assert_ne!(json["variables"]["c5"], input["variables"]["c5"]);
    assert_eq!(json["truth"], input["truth"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `file` with its factors filtered by `keep` (given the factor), written
/// as `name` in `dir`.
fn filtered(dir: &Path, file: &Path, name: &str, keep: impl Fn(usize, &Value) -> bool) -> PathBuf {
    let mut json: Value = serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
    let factors: Vec<Value> = json["factors"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .filter(|(k, f)| keep(*k, f))
        .map(|(_, f)| f.clone())
        .collect();
    json["factors"] = Value::Array(factors);
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_string(&json).unwrap()).unwrap();
    path
}

fn failure(args: &[&str]) -> (Option<i32>, String) {
    let output = slamjac(args);
    assert!(stdout(&output).is_empty(), "{}", stdout(&output));
    let error = stderr(&output);
    assert_eq!(error.lines().count(), 1, "{error}");
    (output.status.code(), error)
}

/// A frame that no observation of the chosen kinds names, or too few to
/// determine its pose, stops the run naming the frame (exit 1); so does
/// a set of kinds that the file does not have. A frame no factor names at
/// all is refused as `solve` refuses it (exit 2).
#[test]
fn frames_that_cannot_be_tracked_are_named() {
    let dir = temp_dir("frames");
    let file = sequence(&dir);
    let pose = |f: &Value| f["variables"]["pose"].as_str().unwrap().to_owned();
    // A frame no factor names is an unused variable, refused by `track` as
    // by `solve`: one reader, one set of checks (issue 28, class M).
    let none = filtered(&dir, &file, "none.json", |_, f| pose(f) != "c3");
    for command in ["track", "solve"] {
        let (code, error) = failure(&[command, none.to_str().unwrap()]);
        assert_eq!(code, Some(2), "{command}: {error}");
        assert_eq!(
            error, "error: variables.c3: no factor uses this variable\n",
            "{command}"
        );
    }
    // Two point observations of c3 and nothing else of it.
    let json: Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    let kept: Vec<usize> = json["factors"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .filter(|(_, f)| pose(f) == "c3" && f["factor"] == "point_reprojection")
        .map(|(k, _)| k)
        .take(2)
        .collect();
    let two = filtered(&dir, &file, "two.json", |k, f| {
        pose(f) != "c3" || kept.contains(&k)
    });
    let (code, error) = failure(&["track", two.to_str().unwrap(), "--kinds", "points"]);
    assert_eq!(code, Some(1));
    assert!(
        error.contains("frame 3 (c3): the 2 observations (4 residuals) do not determine"),
        "{error}"
    );
    assert!(!error.contains("NaN"), "{error}");
    let points = dir.join("points.json");
    let output = slamjac(&[
        "synth-plp",
        "--seed",
        "2",
        "--cameras",
        "10",
        "--kinds",
        "points,planes",
        "--output",
        points.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(0));
    let (code, error) = failure(&["track", points.to_str().unwrap(), "--kinds", "lines"]);
    assert_eq!(code, Some(1));
    assert!(
        error.contains("frame 0 (c0): no observations of lines"),
        "{error}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Malformed files and files `track` cannot read: one line naming the
/// field, exit 2.
#[test]
fn bad_files_are_refused_naming_the_field() {
    let dir = temp_dir("bad");
    let file = sequence(&dir);
    let text = std::fs::read_to_string(&file).unwrap();
    let json: Value = serde_json::from_str(&text).unwrap();
    let write = |name: &str, json: &Value| {
        let path = dir.join(name);
        std::fs::write(&path, serde_json::to_string(json).unwrap()).unwrap();
        path
    };
    let mut cases: Vec<(PathBuf, &str)> = Vec::new();
    let mut no_truth = json.clone();
    no_truth.as_object_mut().unwrap().remove("truth");
    cases.push((write("no_truth.json", &no_truth), "error: truth: missing"));
    let mut no_pose_truth = json.clone();
    no_pose_truth["truth"].as_object_mut().unwrap().remove("c4");
    cases.push((
        write("no_pose_truth.json", &no_pose_truth),
        "error: truth.c4: missing",
    ));
    let mut robust = json.clone();
    robust["factors"][0]["robust"] = Value::from("huber:2");
    cases.push((
        write("robust.json", &robust),
        "error: factors[0].robust: track solves least squares",
    ));
    let mut between = json.clone();
    between["factors"][1]["factor"] = Value::from("between");
    cases.push((
        write("between.json", &between),
        "error: factors[1].factor: \"between\" is not a factor of one pose",
    ));
    let mut sigma = json.clone();
    sigma["factors"][2]["noise"] = serde_json::json!({"sigma": -1});
    cases.push((
        write("sigma.json", &sigma),
        "error: factors[2].noise.sigma: a standard deviation must be from 1e-100 to 1e100, found -1",
    ));
    let mut no_poses = json.clone();
    no_poses["variables"] = serde_json::json!({});
    no_poses["factors"] = serde_json::json!([]);
    no_poses["truth"] = serde_json::json!({});
    cases.push((
        write("no_poses.json", &no_poses),
        "error: variables: no Se3 variable",
    ));
    let truncated = dir.join("truncated.json");
    std::fs::write(&truncated, &text[..text.len() / 2]).unwrap();
    cases.push((truncated, "error: "));
    for (path, expected) in &cases {
        let (code, error) = failure(&["track", path.to_str().unwrap()]);
        assert_eq!(code, Some(2), "{error}");
        assert!(error.starts_with(expected), "{path:?}: {error}");
    }
    // The output may not overwrite the input.
    let (code, error) = failure(&[
        "track",
        file.to_str().unwrap(),
        "--output",
        file.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(2), "{error}");
    std::fs::remove_dir_all(&dir).unwrap();
}
