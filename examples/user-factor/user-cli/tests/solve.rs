//! `user-cli solve`: problem files of the user's own factors, over the
//! user's own manifolds (Sim(3), S²), solved through their kernels generated
//! in apex-solver's chart, checked against the truth they were made from and
//! against dual numbers (an independent linearization).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use factor_core::Storage;
use factor_core::lie::So3;
use factor_core::nalgebra::Vector3;
use serde_json::{Value, json};
use user_factors::sim3::Sim3;
use user_factors::unit_vector::UnitVector3;

fn user_cli(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_user-cli"))
        .args(args)
        .output()
        .expect("user-cli runs")
}

/// A scratch directory for this test, emptied first.
fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("user-cli-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temporary directory");
    dir
}

fn write(path: &Path, json: &Value) -> String {
    std::fs::write(path, json.to_string()).expect("written");
    path.to_str().expect("UTF-8 path").to_owned()
}

/// The JSON of a value: its stored scalars in the order `list` prints.
fn sim3_json(s: &Sim3<f64>) -> Value {
    let x = s.to_scalars();
    json!({"rotation": &x[0..4], "translation": &x[4..7], "log_scale": x[7]})
}

fn sim3(w: [f64; 3], t: [f64; 3], log_scale: f64) -> Sim3<f64> {
    Sim3::new(So3::exp(&Vector3::from(w)), Vector3::from(t), log_scale)
}

/// A loop of five similarity transforms (a monocular trajectory whose scale
/// drifts), `s0` fixed, measured exactly by its relative transforms,
/// started away from the truth.
fn sim3_loop() -> (Value, Vec<Sim3<f64>>) {
    let truth: Vec<Sim3<f64>> = (0..5)
        .map(|k| {
            let a = k as f64;
            sim3(
                [0.1 * a, -0.05 * a, 0.3 * a],
                [a, 0.5 * a * a, -0.2 * a],
                0.08 * a,
            )
        })
        .collect();
    let start: Vec<Sim3<f64>> = truth
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let e = if k == 0 { 0.0 } else { 0.05 };
            s.compose(&sim3([e, -e, 0.5 * e], [2.0 * e, e, -e], -e))
        })
        .collect();
    let mut variables = serde_json::Map::new();
    for (k, s) in start.iter().enumerate() {
        variables.insert(
            format!("s{k}"),
            json!({"type": "Sim3", "value": sim3_json(s), "fixed": k == 0}),
        );
    }
    let edges = [(0, 1), (1, 2), (2, 3), (3, 4), (4, 0), (1, 3)];
    let factors: Vec<Value> = edges
        .iter()
        .map(|&(i, j)| {
            let measured = truth[i].inverse().compose(&truth[j]);
            json!({"factor": "relative_sim3",
                   "variables": {"sim_i": format!("s{i}"), "sim_j": format!("s{j}")},
                   "constants": {"measured": sim3_json(&measured)},
                   "noise": {"sigmas": [0.01, 0.01, 0.01, 0.05, 0.05, 0.05, 0.02]}})
        })
        .collect();
    let problem = json!({"slamjac_problem": 1, "variables": variables, "factors": factors});
    (problem, truth)
}

/// The summary's final cost (`cost: initial …, final X (…)`).
fn final_cost(output: &Output) -> f64 {
    let stdout = String::from_utf8_lossy(&output.stdout);
    stdout
        .lines()
        .find_map(|l| l.trim().strip_prefix("cost: initial"))
        .and_then(|l| l.split("final ").nth(1))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|x| x.parse().ok())
        .unwrap_or_else(|| panic!("no final cost in {stdout}"))
}

fn assert_success(output: &Output) {
    assert!(
        output.status.success(),
        "exit {:?}\nstdout: {}\nstderr: {}",
        output.status.code(),
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

/// The solution of `file` as `--output` wrote it.
fn solved_sim3(file: &Path, name: &str) -> Sim3<f64> {
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(file).expect("written")).expect("JSON");
    let value = &json["variables"][name]["value"];
    let scalars: Vec<f64> = ["rotation", "translation"]
        .iter()
        .flat_map(|k| value[k].as_array().expect("an array").clone())
        .chain([value["log_scale"].clone()])
        .map(|x| x.as_f64().expect("a number"))
        .collect();
    let mut next = scalars.into_iter();
    Sim3::read_scalars(&mut || next.next().expect("8 scalars"))
}

/// The generated kernel in apex's chart and dual numbers reach the truth
/// (the measurements are exact), the same cost, and the written file solves
/// again from its own optimum.
#[test]
fn a_sim3_loop_of_the_users_factor_reaches_its_truth() {
    let dir = scratch("sim3");
    let (problem, truth) = sim3_loop();
    let file = write(&dir.join("loop.json"), &problem);
    let mut costs = Vec::new();
    for kernels in ["generated", "dual"] {
        let out = dir.join(format!("solved-{kernels}.json"));
        let output = user_cli(&[
            "solve",
            &file,
            "--kernels",
            kernels,
            "--output",
            out.to_str().unwrap(),
        ]);
        assert_success(&output);
        // Every factor through the user's apex kernel, or every one through
        // dual numbers.
        let header = if kernels == "generated" {
            "6 through generated kernels and 0 through dual numbers"
        } else {
            "0 through generated kernels and 6 through dual numbers"
        };
        assert!(
            String::from_utf8_lossy(&output.stdout).contains(header),
            "{}",
            String::from_utf8_lossy(&output.stdout)
        );
        costs.push(final_cost(&output));
        for (k, t) in truth.iter().enumerate() {
            let error = t
                .inverse()
                .compose(&solved_sim3(&out, &format!("s{k}")))
                .log();
            assert!(error.norm() < 1e-8, "{kernels}: s{k} off by {error}");
        }
    }
    assert!(costs[0] < 1e-16 && costs[1] < 1e-16, "{costs:?}");
    let again = user_cli(&["solve", dir.join("solved-generated.json").to_str().unwrap()]);
    assert_success(&again);
    assert!(final_cost(&again) <= costs[0].max(1e-20));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Orientations (`So3`, the first fixed if `fix_first`) and two world
/// directions (the user's S² type, served to apex-solver as `Rn(3)` and
/// normalised) from directions measured in each sensor frame, with noise.
fn directions_problem(fix_first: bool) -> Value {
    let rotations = [
        So3::identity(),
        So3::exp(&Vector3::new(0.3, -0.2, 0.1)),
        So3::exp(&Vector3::new(-0.4, 0.5, 0.2)),
    ];
    let directions = [Vector3::new(0.0, 0.0, 1.0), Vector3::new(0.6, -0.8, 0.0)];
    let mut variables = serde_json::Map::new();
    for (k, r) in rotations.iter().enumerate() {
        let start = r.compose(&So3::exp(&(Vector3::new(0.05, 0.02, -0.03) * k as f64)));
        variables.insert(
            format!("r{k}"),
            json!({"type": "So3", "value": start.to_scalars(), "fixed": fix_first && k == 0}),
        );
    }
    for (k, d) in directions.iter().enumerate() {
        let start = UnitVector3::from_direction(&(d + Vector3::new(0.1, 0.05, -0.08)));
        variables.insert(
            format!("d{k}"),
            json!({"type": "UnitVector3", "value": start.vector().as_slice()}),
        );
    }
    let mut factors = Vec::new();
    for (i, r) in rotations.iter().enumerate() {
        for (j, d) in directions.iter().enumerate() {
            // A few milliradians of measurement noise, fixed.
            let noisy = r.rotate(d) + Vector3::new(0.003, -0.002, 0.001) * (1 + i + j) as f64;
            factors.push(json!({
                "factor": "direction",
                "variables": {"orientation": format!("r{i}"), "direction": format!("d{j}")},
                "constants": {"measured": UnitVector3::from_direction(&noisy).vector().as_slice()},
                "noise": {"sigma": 0.01}
            }));
        }
    }
    json!({"slamjac_problem": 1, "variables": variables, "factors": factors})
}

/// The directions problem with one orientation fixed: the generated kernel
/// and dual numbers stop at the same optimum. The radius apex holds beyond
/// each direction's 2-dimensional tangent moves no residual and is not
/// taken for an undetermined direction.
#[test]
fn directions_on_the_users_sphere_solve_alike_with_kernels_and_dual_numbers() {
    let dir = scratch("direction");
    let file = write(&dir.join("directions.json"), &directions_problem(true));
    let generated = user_cli(&["solve", &file]);
    let dual = user_cli(&["solve", &file, "--kernels", "dual"]);
    assert_success(&generated);
    assert_success(&dual);
    let (a, b) = (final_cost(&generated), final_cost(&dual));
    assert!(a > 0.0, "noisy measurements leave a cost: {a}");
    assert!((a - b).abs() <= 1e-9 * a, "{a} vs {b}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// With no orientation fixed, a rotation of the whole scene is free: the
/// observability check finds exactly its three directions (none along the
/// directions' radii) and names the directions' own tangent coordinates.
#[test]
fn a_free_rotation_of_the_scene_is_three_directions_on_the_sphere_and_rotations() {
    let dir = scratch("gauge");
    let file = write(&dir.join("gauge.json"), &directions_problem(false));
    let output = user_cli(&["solve", &file]);
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("not observable: 3 directions of the free variables")
            && !stderr.contains("δ[2]")
            && stderr.lines().count() == 1,
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A factor of slamjac's own, not registered in this command line, and a
/// variable type the factor does not take: one-line errors at the field
/// path, exit 2.
#[test]
fn factors_and_types_the_registry_does_not_know_are_field_errors() {
    let dir = scratch("errors");
    let (mut problem, _) = sim3_loop();
    problem["factors"][2]["factor"] = json!("point_reprojection");
    let output = user_cli(&["solve", &write(&dir.join("unknown.json"), &problem)]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.starts_with("error: factors[2].factor: unknown factor \"point_reprojection\"")
            && stderr.contains("known factors: relative_pose, point_to_plane"),
        "{stderr}"
    );
    let (mut problem, _) = sim3_loop();
    problem["variables"]["s3"]["type"] = json!("Se3");
    let output = user_cli(&["solve", &write(&dir.join("type.json"), &problem)]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.starts_with("error: factors[2].variables.sim_j: variable \"s3\" is a Se3"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
