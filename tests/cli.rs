//! The `slamjac` command line end to end: the example inputs evaluate with
//! every method and agree, `list` describes every factor and its kernel,
//! `generate` and `check` write and verify the generated crate, and every
//! class of bad input gets a one-line error naming the field and a non-zero
//! exit code, never a panic.

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

use serde_json::{Value, json};

use crate::common;
use common::stderr;

/// Exit code of rejected input (and clap usage errors).
const BAD_INPUT: i32 = 2;
/// Exit code of degenerate geometry and non-finite results.
const DEGENERATE: i32 = 1;

/// A factor's name, residual dimension and variables with their tangent dimensions.
type Shape = (&'static str, usize, &'static [(&'static str, usize)]);
/// An edit of an example input.
type Edit = fn(&mut Value);
/// A bad-input case: the example edited and the field path the error must name.
type Case = (&'static str, Edit, &'static str);

/// The registered factors, in `list` order.
const FACTORS: [Shape; 12] = [
    ("point_reprojection", 2, &[("pose", 6), ("point", 3)]),
    ("line_reprojection", 2, &[("pose", 6), ("line", 4)]),
    ("plane", 3, &[("pose", 6), ("plane", 3)]),
    ("free_line", 2, &[("body_pose", 6), ("line", 4)]),
    ("plucker_line_reprojection", 2, &[("pose", 6), ("line", 6)]),
    ("line_observation", 4, &[("pose", 6), ("line", 4)]),
    (
        "snavely_reprojection",
        2,
        &[("pose", 6), ("intrinsics", 3), ("point", 3)],
    ),
    ("stereo_reprojection", 3, &[("pose", 6), ("landmark", 3)]),
    ("between", 6, &[("pose_i", 6), ("pose_j", 6)]),
    ("g2o_se3", 6, &[("pose_i", 6), ("pose_j", 6)]),
    ("g2o_se3_line3d", 4, &[("pose", 6), ("line", 4)]),
    (
        "g2o_se3_plane_calib",
        3,
        &[("pose", 6), ("plane", 3), ("offset", 6)],
    ),
];

/// The registered factors without a generated kernel: `eval` uses dual
/// numbers for them (`slam_factors::g2o`, "Linearization").
const DUAL_ONLY: [&str; 2] = ["g2o_se3_line3d", "g2o_se3_plane_calib"];

/// The method `eval --method method` reports for `factor`: `generated`
/// falls back to `dual` without a kernel.
fn method_used(factor: &str, method: &'static str) -> &'static str {
    if method == "generated" && DUAL_ONLY.contains(&factor) {
        "dual"
    } else {
        method
    }
}

fn slamjac(args: &[&str], stdin: &str) -> Output {
    common::slamjac_with_stdin(args, stdin.as_bytes())
}

fn example_path(factor: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("examples/inputs/{factor}.json"))
}

fn example(factor: &str) -> Value {
    let text = std::fs::read_to_string(example_path(factor)).expect("example exists");
    serde_json::from_str(&text).expect("example is JSON")
}

/// A fresh path in the temporary directory.
fn temp_path(tag: &str) -> PathBuf {
    common::temp_path("test", tag).with_extension("json")
}

/// Runs `eval -` on `text` and parses the output, which must succeed.
fn eval_ok(text: &str, method: &str) -> Value {
    let output = slamjac(&["eval", "-", "--method", method], text);
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    serde_json::from_slice(&output.stdout).expect("output is JSON")
}

/// Asserts a failure with `code`, a one-line stderr containing every needle, no panic, no stdout.
fn assert_error(output: &Output, code: i32, needles: &[&str]) {
    let err = stderr(output);
    assert_eq!(output.status.code(), Some(code), "stderr: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    assert!(err.starts_with("error: "), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    assert!(
        output.stdout.is_empty(),
        "stdout: {}",
        String::from_utf8_lossy(&output.stdout)
    );
    for needle in needles {
        assert!(err.contains(needle), "stderr lacks {needle:?}: {err}");
    }
}

/// Evaluates `input` from stdin and asserts the error.
fn assert_eval_error(input: &Value, code: i32, needles: &[&str]) {
    let output = slamjac(&["eval", "-"], &input.to_string());
    assert_error(&output, code, needles);
}

/// The example of `factor` with `edit` applied.
fn edited(factor: &str, edit: impl FnOnce(&mut Value)) -> Value {
    let mut value = example(factor);
    edit(&mut value);
    value
}

fn matrix(value: &Value) -> Vec<Vec<f64>> {
    value
        .as_array()
        .expect("rows")
        .iter()
        .map(|row| {
            row.as_array()
                .expect("row")
                .iter()
                .map(|x| x.as_f64().expect("number"))
                .collect()
        })
        .collect()
}

fn frobenius(a: &[Vec<f64>]) -> f64 {
    a.iter().flatten().map(|x| x * x).sum::<f64>().sqrt()
}

fn relative_error(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let diff: Vec<Vec<f64>> = a
        .iter()
        .zip(b)
        .map(|(ra, rb)| ra.iter().zip(rb).map(|(x, y)| x - y).collect())
        .collect();
    frobenius(&diff) / frobenius(b).max(1e-9)
}

#[test]
fn examples_evaluate_with_every_method_and_agree() {
    for (factor, rows, variables) in FACTORS {
        let text = example(factor).to_string();
        let generated = eval_ok(&text, "generated");
        let dual = eval_ok(&text, "dual");
        let numeric = eval_ok(&text, "numeric");
        for (out, method) in [
            (&generated, "generated"),
            (&dual, "dual"),
            (&numeric, "numeric"),
        ] {
            assert_eq!(out["factor"], factor);
            assert_eq!(out["method"], method_used(factor, method));
            assert_eq!(
                out["residual"].as_array().expect("residual").len(),
                rows,
                "{factor}"
            );
            let names: Vec<&str> = out["jacobians"]
                .as_object()
                .expect("jacobians")
                .keys()
                .map(String::as_str)
                .collect();
            let declared: Vec<&str> = variables.iter().map(|(name, _)| *name).collect();
            assert_eq!(names, declared, "{factor}: Jacobians in declaration order");
            let tangents: Vec<&str> = out["tangents"]
                .as_object()
                .expect("tangents")
                .keys()
                .map(String::as_str)
                .collect();
            assert_eq!(
                tangents, declared,
                "{factor}: tangents in declaration order"
            );
            for (name, cols) in variables {
                let block = matrix(&out["jacobians"][name]);
                assert_eq!(block.len(), rows, "{factor}.{name} rows");
                assert!(
                    block.iter().all(|row| row.len() == *cols),
                    "{factor}.{name}: {rows}×{cols} expected"
                );
                assert!(
                    !out["tangents"][name]
                        .as_str()
                        .expect("tangent words")
                        .is_empty()
                );
            }
        }
        let residual = |v: &Value| {
            vec![
                v["residual"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap())
                    .collect(),
            ]
        };
        assert!(
            relative_error(&residual(&dual), &residual(&numeric)) <= 1e-12,
            "{factor} residual"
        );
        assert!(
            relative_error(&residual(&generated), &residual(&dual)) <= 1e-12,
            "{factor} residual"
        );
        for (name, _) in variables {
            let error = relative_error(
                &matrix(&dual["jacobians"][name]),
                &matrix(&numeric["jacobians"][name]),
            );
            assert!(
                error <= 1e-6,
                "{factor}.{name}: dual vs numeric relative Frobenius error {error:e}"
            );
            let error = relative_error(
                &matrix(&generated["jacobians"][name]),
                &matrix(&dual["jacobians"][name]),
            );
            assert!(
                error <= 1e-12,
                "{factor}.{name}: generated vs dual relative Frobenius error {error:e}"
            );
        }
    }
}

#[test]
fn eval_reads_files_and_defaults_to_generated() {
    let path = example_path("point_reprojection");
    let output = slamjac(&["eval", path.to_str().expect("utf-8 path")], "");
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    let from_file: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(from_file["method"], "generated");
    assert_eq!(
        from_file,
        eval_ok(&example("point_reprojection").to_string(), "generated")
    );
}

#[test]
fn list_shows_every_factor_with_its_dimensions() {
    let output = slamjac(&["list"], "");
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    let table = String::from_utf8(output.stdout).expect("utf-8");
    for (factor, rows, variables) in FACTORS {
        assert!(
            table.contains(&format!("{factor}  (residual dimension {rows})")),
            "{table}"
        );
        for (name, cols) in variables {
            let line = table
                .lines()
                .find(|l| {
                    l.trim_start().starts_with(&format!("{name} "))
                        && l.contains(&format!(" {cols} "))
                })
                .unwrap_or_else(|| {
                    panic!("no row for {factor}.{name} with dimension {cols}:\n{table}")
                });
            assert!(
                line.contains("left") || line.contains("right") || line.contains("additive"),
                "{line}"
            );
        }
    }

    for (factor, _, _) in FACTORS {
        if DUAL_ONLY.contains(&factor) {
            let block = table
                .split(&format!("{factor}  (residual dimension"))
                .nth(1)
                .expect("listed");
            let kernel = block.lines().find(|l| l.starts_with("  kernel: ")).unwrap();
            assert_eq!(
                kernel, "  kernel: none (`eval` uses dual numbers)",
                "{factor}"
            );
            continue;
        }
        let line = format!("  kernel: factor_generated::{factor}::{factor}, ");
        let kernel = table
            .lines()
            .find(|l| l.starts_with(&line))
            .unwrap_or_else(|| panic!("no kernel line for {factor}:\n{table}"));
        assert!(
            kernel.contains(" operations (add ") && kernel.contains("residual only"),
            "{kernel}"
        );
    }

    let output = slamjac(&["list", "--json"], "");
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    let listed: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    let listed = listed["factors"].as_array().expect("factors");
    assert_eq!(listed.len(), FACTORS.len());
    for (entry, (factor, rows, variables)) in listed.iter().zip(FACTORS) {
        assert_eq!(entry["name"], factor);
        assert_eq!(entry["residual_dim"], rows);
        let got: Vec<(&str, u64)> = entry["variables"]
            .as_array()
            .expect("variables")
            .iter()
            .map(|v| {
                (
                    v["name"].as_str().unwrap(),
                    v["tangent_dim"].as_u64().unwrap(),
                )
            })
            .collect();
        let want: Vec<(&str, u64)> = variables.iter().map(|(n, d)| (*n, *d as u64)).collect();
        assert_eq!(got, want, "{factor}");
        if DUAL_ONLY.contains(&factor) {
            assert!(entry["kernel"].is_null() && entry["operations"].is_null());
            continue;
        }
        assert_eq!(
            entry["kernel"],
            format!("factor_generated::{factor}::{factor}")
        );
        let operations = &entry["operations"];
        let kinds = ["add", "mul", "div", "neg", "sqrt", "func", "branch"];
        let sum: u64 = kinds.iter().map(|k| operations[k].as_u64().unwrap()).sum();
        assert_eq!(operations["total"].as_u64(), Some(sum), "{factor}");
        assert!(entry["residual_operations"].as_u64().unwrap() < sum);
    }
}

#[test]
fn unknown_factor_lists_the_known_ones() {
    let input = edited("plane", |v| v["factor"] = json!("planar"));
    assert_eval_error(
        &input,
        BAD_INPUT,
        &["factor:", "\"planar\"", "point_reprojection", "free_line"],
    );
}

#[test]
fn missing_fields_are_named_at_every_level() {
    let cases: [Case; 5] = [
        (
            "point_reprojection",
            |v| drop(v.as_object_mut().unwrap().remove("constants")),
            "constants",
        ),
        (
            "point_reprojection",
            |v| drop(v["variables"].as_object_mut().unwrap().remove("point")),
            "variables.point",
        ),
        (
            "line_reprojection",
            |v| drop(v["constants"].as_object_mut().unwrap().remove("end")),
            "constants.end",
        ),
        (
            "plane",
            |v| {
                drop(
                    v["variables"]["pose"]
                        .as_object_mut()
                        .unwrap()
                        .remove("translation"),
                )
            },
            "variables.pose.translation",
        ),
        (
            "free_line",
            |v| {
                drop(
                    v["variables"]["line"]
                        .as_object_mut()
                        .unwrap()
                        .remove("distance"),
                )
            },
            "variables.line.distance",
        ),
    ];
    for (factor, edit, path) in cases {
        assert_eval_error(
            &edited(factor, edit),
            BAD_INPUT,
            &[&format!("{path}: missing field")],
        );
    }
}

#[test]
fn unknown_fields_are_rejected_at_every_level() {
    let cases: [Case; 6] = [
        (
            "point_reprojection",
            |v| v["comment"] = json!("x"),
            "comment",
        ),
        (
            "point_reprojection",
            |v| v["variables"]["velocity"] = json!([0, 0, 0]),
            "variables.velocity",
        ),
        (
            "plane",
            |v| v["constants"]["skew"] = json!(0),
            "constants.skew",
        ),
        (
            "line_reprojection",
            |v| v["variables"]["pose"]["scale"] = json!(1),
            "variables.pose.scale",
        ),
        (
            "line_reprojection",
            |v| v["variables"]["line"]["moment"] = json!([1, 0, 0]),
            "variables.line.moment",
        ),
        (
            "free_line",
            |v| v["constants"]["extrinsics"]["time"] = json!(0),
            "constants.extrinsics.time",
        ),
    ];
    for (factor, edit, path) in cases {
        assert_eval_error(
            &edited(factor, edit),
            BAD_INPUT,
            &[&format!("{path}: unknown field")],
        );
    }
}

#[test]
fn wrong_array_lengths_are_rejected() {
    let input = edited("point_reprojection", |v| {
        v["variables"]["point"] = json!([1.0, 2.0])
    });
    assert_eval_error(
        &input,
        BAD_INPUT,
        &["variables.point:", "expected 3", "found 2"],
    );
    let input = edited("free_line", |v| {
        v["variables"]["body_pose"]["rotation"] = json!([0, 0, 1])
    });
    assert_eval_error(
        &input,
        BAD_INPUT,
        &["variables.body_pose.rotation:", "expected 4"],
    );
    let input = edited("point_reprojection", |v| {
        v["constants"]["intrinsics"] = json!([500, 500, 320])
    });
    assert_eval_error(&input, BAD_INPUT, &["constants.intrinsics:", "expected 4"]);
}

#[test]
fn wrong_types_are_rejected() {
    let cases: [(&str, Edit, &[&str]); 6] = [
        (
            "point_reprojection",
            |v| v["factor"] = json!(7),
            &["factor:", "expected a string", "number"],
        ),
        (
            "point_reprojection",
            |v| v["variables"]["point"] = json!("far"),
            &["variables.point:", "expected an array", "string"],
        ),
        (
            "point_reprojection",
            |v| v["variables"]["point"][1] = json!(null),
            &["variables.point[1]:", "expected a number", "null"],
        ),
        (
            "plane",
            |v| v["variables"]["pose"] = json!([0, 0, 0, 1]),
            &["variables.pose:", "expected an object", "array"],
        ),
        (
            "free_line",
            |v| v["variables"]["line"]["distance"] = json!("3"),
            &["variables.line.distance:", "expected a number"],
        ),
        (
            "plane",
            |v| v["constants"] = json!(true),
            &["constants:", "expected an object", "boolean"],
        ),
    ];
    for (factor, edit, needles) in cases {
        assert_eval_error(&edited(factor, edit), BAD_INPUT, needles);
    }
    let output = slamjac(&["eval", "-"], "[1, 2, 3]");
    assert_error(&output, BAD_INPUT, &["input:", "expected an object"]);
}

#[test]
fn numbers_beyond_the_f64_range_are_non_finite_at_their_field() {
    let input = edited("point_reprojection", |v| {
        v["variables"]["point"][2] = json!(123.25)
    });
    let text = serde_json::to_string_pretty(&input)
        .unwrap()
        .replace("123.25", "1e999");
    let output = slamjac(&["eval", "-"], &text);
    assert_error(
        &output,
        BAD_INPUT,
        &["variables.point[2]:", "non-finite", "1e999"],
    );

    let input = edited("free_line", |v| {
        v["variables"]["line"]["distance"] = json!(123.25)
    });
    let text = input.to_string().replace("123.25", "-2E+400");
    let output = slamjac(&["eval", "-"], &text);
    assert_error(
        &output,
        BAD_INPUT,
        &["variables.line.distance:", "non-finite"],
    );
}

#[test]
fn non_unit_quaternions_are_rejected_beyond_the_tolerance() {
    let cases: [Case; 3] = [
        (
            "point_reprojection",
            |v| v["variables"]["pose"]["rotation"] = json!([0.0, 0.0, 0.0, 1.01]),
            "variables.pose.rotation",
        ),
        (
            "free_line",
            |v| v["variables"]["line"]["rotation"] = json!([0.0, 0.0, 0.0, 0.0]),
            "variables.line.rotation",
        ),
        (
            "free_line",
            |v| v["constants"]["extrinsics"]["rotation"] = json!([0.5, 0.5, 0.5, 0.6]),
            "constants.extrinsics.rotation",
        ),
    ];
    for (factor, edit, path) in cases {
        assert_eval_error(
            &edited(factor, edit),
            BAD_INPUT,
            &[&format!("{path}:"), "norm"],
        );
    }
    // Within 1e-6 of unit norm: accepted and re-normalised.
    let input = edited("point_reprojection", |v| {
        v["variables"]["pose"]["rotation"] = json!([0.0, 0.0, 0.0, 1.0000005]);
    });
    eval_ok(&input.to_string(), "dual");
}

#[test]
fn zero_norm_plane_and_line_vectors_are_rejected() {
    let cases: [Case; 3] = [
        (
            "plane",
            |v| v["variables"]["plane"] = json!([0, 0, 0, 0]),
            "variables.plane",
        ),
        (
            "line_reprojection",
            |v| v["variables"]["line"]["normal"] = json!([0, 0, 0]),
            "variables.line.normal",
        ),
        (
            "line_reprojection",
            |v| v["variables"]["line"]["direction"] = json!([0, 0, 0]),
            "variables.line.direction",
        ),
    ];
    for (factor, edit, path) in cases {
        assert_eval_error(
            &edited(factor, edit),
            BAD_INPUT,
            &[&format!("{path}:"), "zero norm"],
        );
    }
}

/// A zero measured plane or bearing vector is a vector like any other as
/// input; the factor finds the geometry degenerate (exit 1), naming it.
#[test]
fn zero_measurement_vectors_are_rejected() {
    // Stored at unit norm (any other scale is normalised): a zero vector has
    // no direction to store.
    let cases: [(&str, Edit, &str); 2] = [
        (
            "plane",
            |v| v["constants"]["measured"] = json!([0, 0, 0, 0.0]),
            "constants.measured: zero vector: it has no direction",
        ),
        (
            "free_line",
            |v| v["constants"]["bearing_end"] = json!([0, 0, 0]),
            "constants.bearing_end: zero vector: it has no direction",
        ),
    ];
    for (factor, edit, message) in cases {
        assert_eval_error(&edited(factor, edit), BAD_INPUT, &[message]);
    }
}

#[test]
fn plucker_constraint_violations_are_rejected() {
    let input = edited("line_reprojection", |v| {
        v["variables"]["line"] = json!({"normal": [1.0, 0.0, 0.0], "direction": [0.1, 1.0, 0.0]});
    });
    assert_eval_error(&input, BAD_INPUT, &["variables.line:", "Plücker", "n · v"]);
}

#[test]
fn zero_focal_lengths_are_rejected() {
    let input = edited("point_reprojection", |v| {
        v["constants"]["intrinsics"][1] = json!(0.0)
    });
    assert_eval_error(
        &input,
        BAD_INPUT,
        &["constants.intrinsics[1]:", "focal length"],
    );
}

#[test]
fn unreadable_files_are_reported() {
    let path = temp_path("missing");
    let output = slamjac(&["eval", path.to_str().unwrap()], "");
    assert_error(&output, BAD_INPUT, &[path.to_str().unwrap(), "cannot read"]);
}

#[test]
fn invalid_json_is_reported_with_its_source() {
    let output = slamjac(&["eval", "-"], "{\"factor\": \"plane\",");
    assert_error(&output, BAD_INPUT, &["<stdin>:", "invalid JSON"]);

    let path = temp_path("invalid");
    std::fs::write(&path, "{\"factor\": plane}").unwrap();
    let output = slamjac(&["eval", path.to_str().unwrap()], "");
    let _ = std::fs::remove_file(&path);
    assert_error(
        &output,
        BAD_INPUT,
        &[&format!("{}:", path.display()), "invalid JSON"],
    );
}

#[test]
fn usage_errors_keep_clap_exit_code() {
    let output = slamjac(&["eval", "-", "--method", "symbolic"], "{}");
    assert_eq!(output.status.code(), Some(BAD_INPUT));
    assert!(stderr(&output).contains("symbolic"));
    let output = slamjac(&["eval"], "");
    assert_eq!(output.status.code(), Some(BAD_INPUT));
}

/// A pose with identity rotation and the given translation.
fn pose(t: [f64; 3]) -> Value {
    json!({"rotation": [0.0, 0.0, 0.0, 1.0], "translation": t})
}

#[test]
fn point_behind_the_camera_is_degenerate() {
    let input = edited("point_reprojection", |v| {
        v["variables"]["pose"] = pose([0.0, 0.0, 0.0]);
        v["variables"]["point"] = json!([0.3, -0.2, -4.0]);
    });
    assert_eval_error(
        &input,
        DEGENERATE,
        &["point_reprojection", "degenerate", "behind the camera"],
    );
}

#[test]
fn line_through_the_optical_centre_is_degenerate() {
    // Camera centre −Rᵀt = (−1, 0, 0); the line through it along y has n = c × v = (0, 0, −1).
    let input = edited("line_reprojection", |v| {
        v["variables"]["pose"] = pose([1.0, 0.0, 0.0]);
        v["variables"]["line"] = json!({"normal": [0.0, 0.0, -1.0], "direction": [0.0, 1.0, 0.0]});
    });
    assert_eval_error(
        &input,
        DEGENERATE,
        &["line_reprojection", "degenerate", "optical centre"],
    );
}

#[test]
fn parallel_bearings_are_degenerate() {
    let input = edited("free_line", |v| {
        let f1 = v["constants"]["bearing_start"].clone();
        let scaled: Vec<f64> = f1
            .as_array()
            .unwrap()
            .iter()
            .map(|x| 2.0 * x.as_f64().unwrap())
            .collect();
        v["constants"]["bearing_end"] = json!(scaled);
    });
    assert_eval_error(&input, DEGENERATE, &["free_line", "degenerate", "parallel"]);
}

#[test]
fn camera_centre_on_the_free_line_anchor_is_degenerate() {
    // q_WL = identity puts the anchor at (0, 0, d); with identity rotations the
    // camera centre is −t_BW − t_CB = (0, 0, d).
    let input = edited("free_line", |v| {
        v["constants"]["extrinsics"] = pose([0.0, 0.0, 0.0]);
        v["variables"]["body_pose"] = pose([0.0, 0.0, -2.5]);
        v["variables"]["line"] = json!({"rotation": [0.0, 0.0, 0.0, 1.0], "distance": 2.5});
    });
    assert_eval_error(&input, DEGENERATE, &["free_line", "degenerate", "anchor"]);
}

#[test]
fn antipodal_plane_quaternion_is_degenerate() {
    // With the identity pose the predicted plane is the measured one: measuring
    // −π makes the error quaternion exactly −1.
    let input = edited("plane", |v| {
        v["variables"]["pose"] = pose([0.0, 0.0, 0.0]);
        let negated: Vec<f64> = v["variables"]["plane"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| -x.as_f64().unwrap())
            .collect();
        v["constants"]["measured"] = json!(negated);
    });
    assert_eval_error(&input, DEGENERATE, &["plane", "degenerate", "antipodal"]);
}

#[test]
fn non_finite_results_are_reported() {
    // Finite, valid input whose projection overflows: f_u X = 1e308 · 4.
    let input = edited("point_reprojection", |v| {
        v["variables"]["pose"] = pose([0.0, 0.0, 0.0]);
        v["variables"]["point"] = json!([4.0, 0.5, 1.0]);
        v["constants"]["intrinsics"] = json!([1e308, 1e308, 320.0, 240.0]);
    });
    for method in ["generated", "dual", "numeric"] {
        let output = slamjac(&["eval", "-", "--method", method], &input.to_string());
        assert_error(&output, DEGENERATE, &["point_reprojection", "non-finite"]);
    }
}

/// A fresh directory in the temporary directory.
fn temp_dir(tag: &str) -> PathBuf {
    common::temp_dir("test", tag)
}

#[test]
fn generate_writes_a_crate_that_check_accepts_until_it_is_edited() {
    let dir = temp_dir("generate");
    let dir_text = dir.to_str().expect("utf-8 path");
    let output = slamjac(&["generate", "--out", dir_text], "");
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    let report = String::from_utf8(output.stdout).expect("utf-8");
    for (factor, _, _) in FACTORS.iter().filter(|(f, ..)| !DUAL_ONLY.contains(f)) {
        let line = report
            .lines()
            .find(|l| l.starts_with(&format!("{factor} ")))
            .unwrap_or_else(|| panic!("no line for {factor}:\n{report}"));
        assert!(
            line.contains(" ops (add ") && line.ends_with(" ms"),
            "{line}"
        );
    }
    assert!(report.contains("generated 10 kernels into"), "{report}");
    assert!(report.trim_end().ends_with("in process)"), "{report}");
    let src = dir.join("src");
    for file in ["lib.rs", "real.rs", "point_reprojection.rs", "free_line.rs"] {
        assert!(src.join(file).is_file(), "{file} written");
    }
    // The generated sources are the committed ones.
    let committed = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("generated/src");
    for file in ["lib.rs", "real.rs", "point_reprojection.rs", "plane.rs"] {
        assert_eq!(
            std::fs::read_to_string(src.join(file)).unwrap(),
            std::fs::read_to_string(committed.join(file)).unwrap(),
            "{file}"
        );
    }

    // An edited module, an extra file and a missing one are all stale.
    // (Each run of `generate` or `check` generates every kernel anew, about
    // 4 s of CPU in a debug build: the test runs as few as it can.)
    let plane = src.join("plane.rs");
    let mut text = std::fs::read_to_string(&plane).unwrap();
    text.push_str("// edited\n");
    std::fs::write(&plane, text).unwrap();
    std::fs::write(src.join("extra.rs"), "").unwrap();
    std::fs::remove_file(src.join("real.rs")).unwrap();
    let output = slamjac(&["check", "--dir", dir_text], "");
    assert_error(
        &output,
        DEGENERATE,
        &["plane.rs", "extra.rs", "real.rs", "stale"],
    );

    // Regenerating repairs all three, and `check` accepts the crate.
    let output = slamjac(&["generate", "--out", dir_text], "");
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    assert!(!src.join("extra.rs").exists());
    assert!(src.join("real.rs").is_file());
    let output = slamjac(&["check", "--dir", dir_text], "");
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    assert!(String::from_utf8_lossy(&output.stdout).contains("up to date"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `audit` prints its table, writes both reports with the verdict
/// vocabulary of the specification, and exits 0 because every disagreement
/// found in the documents is recorded as a known erratum.
#[test]
fn audit_writes_reports_and_gates_on_unexpected_disagreements() {
    let dir = std::env::temp_dir().join(format!("slamjac-audit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let (json_path, markdown_path) = (dir.join("audit.json"), dir.join("audit.md"));
    let output = slamjac(
        &[
            "audit",
            "--samples",
            "20",
            "--json",
            json_path.to_str().unwrap(),
            "--markdown",
            markdown_path.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    let table = String::from_utf8(output.stdout).expect("UTF-8");
    assert!(
        table.contains("(5) ∂ρ/∂ξ") && table.contains("malformed"),
        "{table}"
    );
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(&json_path).unwrap()).unwrap();
    let entries = report.as_array().expect("array");
    assert!(!entries.is_empty());
    for entry in entries {
        let verdict = entry["verdict"].as_str().expect("verdict");
        assert!(
            ["correct", "convention", "wrong", "malformed"].contains(&verdict),
            "{verdict}"
        );
        for key in [
            "document",
            "equation",
            "claim",
            "max_relative_error",
            "convention_note",
            "corrected_latex",
        ] {
            assert!(entry.get(key).is_some(), "missing {key}");
        }
    }
    let markdown = std::fs::read_to_string(&markdown_path).unwrap();
    assert!(markdown.starts_with("# Derivation audit") && markdown.contains("$$"));
    let zero = slamjac(&["audit", "--samples", "0"], "");
    assert_eq!(zero.status.code(), Some(2));
    assert!(stderr(&zero).contains("--samples"));
    std::fs::remove_dir_all(&dir).ok();
}

/// A huge `--samples` is refused with one line naming the bound; it used to
/// panic allocating the samples ("capacity overflow", exit 101) or abort.
#[test]
fn audit_bounds_the_number_of_samples() {
    for (samples, shown) in [
        ("18446744073709551615", "18446744073709551615"),
        ("100001", "100001"),
        ("4000000000", "4000000000"),
    ] {
        let output = slamjac(&["audit", "--samples", samples], "");
        assert_error(
            &output,
            2,
            &[&format!(
                "error: --samples: {shown} is out of range: must be between 1 and 100000"
            )],
        );
    }
}

/// Asserts that stderr holds no raw control or line-separator character
/// besides its final newline.
fn assert_printable(output: &Output) {
    let err = stderr(output);
    let line = err.strip_suffix('\n').unwrap_or(&err);
    assert!(
        !line
            .chars()
            .any(|c| c.is_control() || matches!(c, '\u{2028}' | '\u{2029}')),
        "raw control character: {line:?}"
    );
}

#[test]
fn field_paths_are_escaped_quoted_and_never_empty() {
    let cases = [
        ("a\nb", "variables[\"a\\nb\"]: unknown field"),
        ("a\rb", "variables[\"a\\rb\"]: unknown field"),
        (
            "\u{1b}[31mred",
            "variables[\"\\u001b[31mred\"]: unknown field",
        ),
        ("nul\u{0}", "variables[\"nul\\u0000\"]: unknown field"),
        (
            "line\u{2028}sep",
            "variables[\"line\\u2028sep\"]: unknown field",
        ),
        (
            "next\u{85}line",
            "variables[\"next\\u0085line\"]: unknown field",
        ),
        (
            "quote\"back\\slash",
            "variables[\"quote\\\"back\\\\slash\"]: unknown field",
        ),
        ("a b", "variables[\"a b\"]: unknown field"),
        ("", "variables[\"\"]: unknown field"),
    ];
    for (key, path) in cases {
        let input = edited("point_reprojection", |v| v["variables"][key] = json!(1));
        let output = slamjac(&["eval", "-"], &input.to_string());
        assert_error(&output, BAD_INPUT, &[&format!("error: {path}")]);
        assert_printable(&output);
    }
    // At the top level an empty key shows as `""`.
    let input = edited("plane", |v| v[""] = json!(0));
    let output = slamjac(&["eval", "-"], &input.to_string());
    assert_error(&output, BAD_INPUT, &["error: \"\": unknown field"]);
}

#[test]
fn long_names_and_values_are_cut_at_64_characters() {
    let long = "x".repeat(10_000);
    let shown = format!("\"{}…\"", "x".repeat(64));
    let input = edited("plane", |v| v["constants"][long.as_str()] = json!(0));
    let output = slamjac(&["eval", "-"], &input.to_string());
    assert_error(
        &output,
        BAD_INPUT,
        &[&format!("error: constants[{shown}]: unknown field")],
    );
    assert!(stderr(&output).len() < 300, "{}", stderr(&output));

    let input = edited("plane", |v| v["factor"] = json!(format!("{long}\u{1b}")));
    let output = slamjac(&["eval", "-"], &input.to_string());
    assert_error(
        &output,
        BAD_INPUT,
        &[&format!(
            "error: factor: unknown factor {shown}; known factors"
        )],
    );
    // The message lists the known factors after the cut name.
    let known: usize = FACTORS.iter().map(|(name, ..)| name.len() + 2).sum();
    assert!(stderr(&output).len() < 150 + known, "{}", stderr(&output));
}

#[test]
fn no_input_text_is_mistaken_for_a_number() {
    // The string the old parser used to mark out-of-range literals.
    let marker = "\u{1}slamjac:out-of-range:";
    let input = edited("plane", |v| v["factor"] = json!(format!("{marker}1e999")));
    let output = slamjac(&["eval", "-"], &input.to_string());
    assert_error(
        &output,
        BAD_INPUT,
        &["error: factor: unknown factor \"\\u0001slamjac:out-of-range:1e999\""],
    );
    let input = edited("point_reprojection", |v| {
        v["variables"]["point"][0] = json!(format!("{marker}5"))
    });
    let output = slamjac(&["eval", "-"], &input.to_string());
    assert_error(
        &output,
        BAD_INPUT,
        &["error: variables.point[0]: expected a number, found a string"],
    );
}

#[test]
fn duplicate_keys_are_rejected_at_their_path() {
    let text = serde_json::to_string_pretty(&example("point_reprojection")).unwrap();
    let cases = [
        (
            text.replacen(
                "\"factor\": \"point_reprojection\"",
                "\"factor\": \"plane\", \"factor\": \"point_reprojection\"",
                1,
            ),
            "error: factor: duplicate key",
        ),
        (
            text.replacen("\"point\": [", "\"point\": [1, 2, 3], \"point\": [", 1),
            "error: variables.point: duplicate key",
        ),
        (
            text.replacen(
                "\"rotation\": [",
                "\"rotation\": [0, 0, 0, 1], \"rotation\": [",
                1,
            ),
            "error: variables.pose.rotation: duplicate key",
        ),
    ];
    for (input, needle) in cases {
        assert_ne!(input, text, "the edit applies");
        let output = slamjac(&["eval", "-"], &input);
        assert_error(&output, BAD_INPUT, &[needle]);
    }
}

#[test]
fn w_first_quaternions_get_a_hint_naming_the_field() {
    // The identity written w-first reads as a 180° turn about x: Z = -3.
    let input = edited("point_reprojection", |v| {
        v["variables"]["pose"] =
            json!({"rotation": [1.0, 0.0, 0.0, 0.0], "translation": [0.0, 0.0, 0.0]});
        v["variables"]["point"] = json!([0.3, -0.2, 3.0]);
    });
    assert_eval_error(
        &input,
        DEGENERATE,
        &[
            "error: point_reprojection: degenerate geometry: point is at or behind the camera \
             (depth Z = -3) (variables.pose.rotation looks w-first: quaternions are [x, y, z, w])",
        ],
    );
    // The example's rotation written w-first.
    let input = edited("point_reprojection", |v| {
        let q = v["variables"]["pose"]["rotation"].clone();
        v["variables"]["pose"]["rotation"] = json!([q[3], q[0], q[1], q[2]]);
    });
    assert_eval_error(
        &input,
        DEGENERATE,
        &["(variables.pose.rotation looks w-first: quaternions are [x, y, z, w])"],
    );
    // A point truly behind the camera gets no hint.
    let input = edited("point_reprojection", |v| {
        v["variables"]["pose"] = pose([0.0, 0.0, 0.0]);
        v["variables"]["point"] = json!([0.3, -0.2, -4.0]);
    });
    let output = slamjac(&["eval", "-"], &input.to_string());
    assert_error(&output, DEGENERATE, &["(depth Z = -4)"]);
    assert!(!stderr(&output).contains("w-first"), "{}", stderr(&output));
    // Outside the accuracy envelope (a residual of 320 px from terms of
    // 1.5e11 px), with the identity as given: no reading of the quaternion
    // is at fault, so no hint, though the w-first reading (a half turn
    // about z) would be accepted.
    let input = edited("point_reprojection", |v| {
        v["variables"]["pose"] = pose([0.0, 0.0, 0.0]);
        v["variables"]["point"] = json!([0.3, 0.0, 1e-9]);
        v["constants"]["observed"] = json!([1.5e11, 240.0]);
    });
    let output = slamjac(&["eval", "-"], &input.to_string());
    assert_error(
        &output,
        DEGENERATE,
        &["point_reprojection: outside the accuracy envelope: the residual"],
    );
    assert!(!stderr(&output).contains("w-first"), "{}", stderr(&output));
}

#[test]
fn numbers_in_messages_are_in_plain_notation() {
    let input = edited("line_reprojection", |v| {
        v["variables"]["line"] = json!({"normal": [1.0, 0.0, 0.0], "direction": [0.1, 1.0, 0.0]});
    });
    let output = slamjac(&["eval", "-"], &input.to_string());
    assert_error(&output, BAD_INPUT, &["n · v = 0.1 "]);
    let input = edited("point_reprojection", |v| {
        v["variables"]["pose"] = pose([0.0, 0.0, 0.0]);
        v["variables"]["point"] = json!([0.3, -0.2, -1.5e-12]);
    });
    let output = slamjac(&["eval", "-"], &input.to_string());
    assert_error(&output, DEGENERATE, &["(depth Z = -1.5e-12)"]);
}

/// `slamjac args…` run from `dir` without `CARGO_MANIFEST_DIR`, as an installed binary is.
fn slamjac_in(dir: &std::path::Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_slamjac"))
        .args(args)
        .current_dir(dir)
        .env_remove("CARGO_MANIFEST_DIR")
        .stdin(Stdio::null())
        .output()
        .expect("slamjac runs")
}

/// `check` accepts the committed `generated/`, which it finds from any
/// working directory (the one compiled in).
#[test]
fn check_and_generate_find_the_workspace_crate_from_anywhere() {
    let elsewhere = temp_dir("elsewhere");
    let output = slamjac_in(&elsewhere, &["check"]);
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    let expected = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("generated/src");
    assert!(
        String::from_utf8_lossy(&output.stdout).contains(&expected.display().to_string()),
        "{}",
        String::from_utf8_lossy(&output.stdout)
    );
    assert!(!elsewhere.join("generated").exists());
    let _ = std::fs::remove_dir_all(&elsewhere);
}

#[test]
fn check_says_not_found_for_a_missing_directory() {
    let missing = temp_path("missing").with_extension("d");
    let output = slamjac(&["check", "--dir", missing.to_str().unwrap()], "");
    assert_error(
        &output,
        BAD_INPUT,
        &[&format!("error: {}: not found", missing.display())],
    );
    assert!(!stderr(&output).contains("stale"), "{}", stderr(&output));
}

#[test]
fn check_reports_unreadable_files_as_read_errors() {
    let dir = temp_dir("unreadable");
    let dir_text = dir.to_str().unwrap();
    let output = slamjac(&["generate", "--out", dir_text], "");
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    // A directory where a module should be cannot be read (as root can read any file).
    let plane = dir.join("src/plane.rs");
    std::fs::remove_file(&plane).unwrap();
    std::fs::create_dir(&plane).unwrap();
    let output = slamjac(&["check", "--dir", dir_text], "");
    assert_error(
        &output,
        BAD_INPUT,
        &[&format!("error: {}: cannot read", plane.display())],
    );
    assert!(!stderr(&output).contains("stale"), "{}", stderr(&output));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn generate_refuses_a_directory_that_is_not_a_generated_crate() {
    let dir = temp_dir("not-a-crate");
    std::fs::create_dir(dir.join("src")).unwrap();
    std::fs::write(dir.join("src/main.rs"), "fn main() {}\n").unwrap();
    std::fs::write(dir.join("Cargo.toml"), "[package]\nname = \"mine\"\n").unwrap();
    let output = slamjac(&["generate", "--out", dir.to_str().unwrap()], "");
    assert_error(
        &output,
        BAD_INPUT,
        &[&format!("error: {}: not a generated crate", dir.display())],
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("src/main.rs")).unwrap(),
        "fn main() {}\n",
        "nothing touched"
    );
    assert!(!dir.join("src/lib.rs").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Where numerical differentiation cannot reach its tolerance (a point 1e-8
/// in front of a camera 5 from it, whose depth rounding leaves the residual
/// noisy), `eval --method numeric` exits 1 with one line naming the variable
/// and the estimate; the exact methods evaluate the same input.
#[test]
fn numeric_method_that_does_not_converge_is_an_error() {
    let input = json!({
        "factor": "point_reprojection",
        "variables": {
            "pose": {"rotation": [0, 0, 0, 1], "translation": [0.1, 0.2, -5]},
            "point": [0.3, -0.2, 5.00000001]
        },
        "constants": {"intrinsics": [500, 500, 320, 240], "observed": [300, 200]}
    })
    .to_string();
    let output = slamjac(&["eval", "-", "--method", "numeric"], &input);
    assert_error(
        &output,
        DEGENERATE,
        &[
            "error: point_reprojection: numerical differentiation w.r.t. `pose` did not \
             converge: estimated relative error ",
            "above the tolerance 1e-7",
        ],
    );
    for method in ["generated", "dual"] {
        eval_ok(&input, method);
    }
}

/// `audit DOC --symbols FILE` audits a document straight from its text:
/// both specification documents pass their gates with the verdict
/// vocabulary, and the reports quote each formula with its line, what was
/// understood and the engine's suggested correction.
#[test]
fn audit_from_a_documents_text_writes_reports_and_gates_on_expected_verdicts() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("slamjac-audit-text-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    for (name, count) in [("000_29653f4af9b68bb8", 23), ("001_85032ab900231dbd", 14)] {
        let document = root.join(format!("documents/{name}.txt"));
        let symbols = root.join(format!("documents/{name}.symbols.toml"));
        let json_path = dir.join(format!("{name}.json"));
        let markdown_path = dir.join(format!("{name}.md"));
        let output = slamjac(
            &[
                "audit",
                document.to_str().unwrap(),
                "--symbols",
                symbols.to_str().unwrap(),
                "--samples",
                "20",
                "--json",
                json_path.to_str().unwrap(),
                "--markdown",
                markdown_path.to_str().unwrap(),
            ],
            "",
        );
        assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
        let table = String::from_utf8(output.stdout).expect("UTF-8");
        assert!(
            table.contains(&format!("{count} formulas audited from the text")),
            "{table}"
        );
        let report: Value =
            serde_json::from_str(&std::fs::read_to_string(&json_path).unwrap()).unwrap();
        let entries = report.as_array().expect("array");
        assert_eq!(entries.len(), count);
        for entry in entries {
            let verdict = entry["verdict"].as_str().expect("verdict");
            assert_eq!(Some(verdict), entry["expected_verdict"].as_str());
            for key in [
                "line",
                "printed_latex",
                "understood_latex",
                "suggested_correction",
            ] {
                assert!(entry.get(key).is_some(), "missing {key}");
            }
        }
        let markdown = std::fs::read_to_string(&markdown_path).unwrap();
        assert!(markdown.contains("As printed:") && markdown.contains("As understood:"));
    }
    let report: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("000_29653f4af9b68bb8.json")).unwrap(),
    )
    .unwrap();
    let dphi = report
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["equation"] == "§IV-A ∂φ/∂y")
        .expect("∂φ/∂y");
    assert_eq!(
        dphi["suggested_correction"]["words"],
        "exponent 3/2 of |y| should be 3"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A user's notes with a mistake fail the gate (exit 1) after the table;
/// a symbols file that does not fit, or a missing one, is rejected input.
#[test]
fn audit_from_text_rejects_bad_input_and_fails_on_unexpected_verdicts() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let data = root.join("factor-audit/tests/data");
    let notes = data.join("icp_notes.md");
    let symbols = data.join("icp_notes.symbols.toml");
    let output = slamjac(
        &[
            "audit",
            notes.to_str().unwrap(),
            "--symbols",
            symbols.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(output.status.code(), Some(1), "stderr: {}", stderr(&output));
    let table = String::from_utf8_lossy(&output.stdout);
    assert!(table.contains("should be flipped"), "{table}");
    assert!(stderr(&output).contains("icp_notes.md (2) (wrong where correct is expected)"));
    // An undefined symbol: the equation and the fragment, on one line.
    let bad = temp_path("symbols").with_extension("toml");
    let text = std::fs::read_to_string(&symbols)
        .unwrap()
        .replace("\"n\" = { sample = \"vector3\" }\n", "");
    std::fs::write(&bad, text).unwrap();
    let output = slamjac(
        &[
            "audit",
            notes.to_str().unwrap(),
            "--symbols",
            bad.to_str().unwrap(),
        ],
        "",
    );
    // Each claim is read on its own: the table lists every claim with its
    // reading error (the fragment at fault), and the run fails (exit 2,
    // one line) because claims could not be read.
    assert_eq!(output.status.code(), Some(2), "stderr: {}", stderr(&output));
    let err = stderr(&output);
    assert!(
        err.starts_with("error: ") && !err.contains("panicked"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    assert!(
        err.contains("could not be read") && err.contains("undefined symbol"),
        "{err}"
    );
    let table = String::from_utf8_lossy(&output.stdout);
    for needle in ["(1)", "(2)", "(3)", "unread", "undefined symbol at `n`"] {
        assert!(table.contains(needle), "{needle}: {table}");
    }
    // With --allow-unread, the claims that cannot be read do not fail it.
    let output = slamjac(
        &[
            "audit",
            notes.to_str().unwrap(),
            "--symbols",
            bad.to_str().unwrap(),
            "--allow-unread",
        ],
        "",
    );
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    std::fs::remove_file(&bad).ok();
    // The document needs its symbols file.
    let output = slamjac(&["audit", notes.to_str().unwrap()], "");
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("--symbols"));
}

#[test]
fn init_writes_a_project_into_an_empty_directory_only() {
    let dir = temp_dir("init");
    let dir_text = dir.to_str().expect("utf-8 path");
    let output = slamjac(&["init", dir_text, "--name", "vio"], "");
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    let read = |path: &str| std::fs::read_to_string(dir.join(path)).expect(path);
    assert!(read("Cargo.toml").contains("[profile.dev.package.factor-codegen]\nopt-level = 3"));
    assert!(read("vio-kernels/Cargo.toml").contains("lanes = [\"dep:factor-lanes\"]"));
    assert!(read("vio-kernels/src/lib.rs").contains("compile_error!("));
    assert!(read("vio-factors/src/lib.rs").contains("kernel = vio_kernels::position_prior"));
    assert!(read("vio-cli/src/main.rs").contains(".run(\"vio\")"));
    // `cargo test` runs `check`: every registered kernel against its definition.
    assert!(
        read("vio-cli/tests/kernels_are_current.rs")
            .contains("Command::new(env!(\"CARGO_BIN_EXE_vio\"))\n        .arg(\"check\")")
    );
    // The example input names the project's factor.
    let input: Value = serde_json::from_str(&read("inputs/position_prior.json")).unwrap();
    assert_eq!(input["factor"], "position_prior");
    let again = slamjac(&["init", dir_text, "--name", "vio"], "");
    assert_error(
        &again,
        BAD_INPUT,
        &["refused: init writes into a new or empty directory"],
    );
    let empty = temp_dir("init-name");
    let bad = slamjac(&["init", empty.to_str().unwrap(), "--name", "Vio"], "");
    assert_error(&bad, BAD_INPUT, &["cannot name the crates"]);
    assert_eq!(
        std::fs::read_dir(&empty).unwrap().count(),
        0,
        "nothing written"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&empty);
}
