//! `slamjac solve` and `slamjac synth-bal` on the command line (feature
//! `solve`): final costs of the small shipped data sets against GTSAM 4.3's,
//! `--output` round trips in every format, both kernel choices, robust
//! losses, plots, and the errors and exit codes of bad input.
//!
//! The stored costs are GTSAM 4.3.0's (PyPI `gtsam`, `bench-peers/gtsam_solve.py`:
//! Levenberg–Marquardt to tolerances of 1e-12, the gauge held as `solve`
//! holds it), computed independently of this project.
#![cfg(feature = "solve")]

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
mod hostile_problems;
use common::{Rng, slamjac, stderr, stdout};

/// A fresh directory for this file's tests.
fn temp_dir(tag: &str) -> PathBuf {
    common::temp_dir("solve", tag)
}

fn data(file: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(file)
        .to_string_lossy()
        .into_owned()
}

/// `(initial, final)` costs of the summary line `cost: initial X, final Y`.
fn costs(output: &Output) -> (f64, f64) {
    let text = stdout(output);
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("cost: initial"))
        .unwrap_or_else(|| panic!("no cost line in:\n{text}\nstderr: {}", stderr(output)));
    let number = |key: &str| -> f64 {
        let rest = &line[line.find(key).expect(key) + key.len()..];
        let end = rest.find([',', ' ']).unwrap_or(rest.len());
        rest[..end].parse().expect("a number")
    };
    (number("initial "), number("final "))
}

/// Runs a solve that must succeed and returns its output.
fn solve_ok(args: &[&str]) -> Output {
    let output = slamjac(args);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{args:?}\nstdout: {}\nstderr: {}",
        stdout(&output),
        stderr(&output)
    );
    output
}

fn assert_relative(value: f64, expected: f64, tolerance: f64, what: &str) {
    let error = (value - expected).abs() / expected.abs();
    assert!(
        error <= tolerance,
        "{what}: {value} vs {expected}: relative error {error:e} above {tolerance:e}"
    );
}

/// The tolerance on final costs: `solve` stops (by default) when an
/// accepted step lowers the cost by less than 1e-8 relative, and the
/// issue's requirement is to end within 1e-6 of GTSAM's optimum (run to the
/// optimum, the two agree to
/// 2e-8 or better, KITTI VO to 3e-6 for the reason given at its test: the
/// `compare` binary of `integrations/apex`, in `bench-peers/README.md`).
const STOPPING: f64 = 1e-6;

/// GTSAM: 126.92832321247 → 125.16959405405 (camera 0's pose fixed, 6 LM
/// iterations). The initial costs agree to 1e-10 relative: GTSAM keeps the
/// file's rotation matrices (orthonormal to about 1e-11), `solve` their
/// nearest rotations.
#[test]
fn balbianello_reaches_gtsams_optimum() {
    let output = solve_ok(&["solve", &data("Balbianello.out")]);
    let (initial, last) = costs(&output);
    assert_relative(initial, 126.92832321247148, 1e-10, "initial cost");
    assert_relative(last, 125.16959405405, STOPPING, "final cost");
    let text = stdout(&output);
    assert!(text.contains("converged"), "{text}");
    assert!(text.contains("RMS reprojection error"), "{text}");
    assert!(text.contains("median reprojection error"), "{text}");
    assert!(text.contains("linearization"), "{text}");
}

/// GTSAM: 64941.32289 → 18853.020732555 (first pose fixed).
#[test]
fn pose3example_reaches_gtsams_optimum() {
    let output = solve_ok(&["solve", &data("pose3example.txt")]);
    let (initial, last) = costs(&output);
    assert_relative(initial, 64941.32288838, 1e-9, "initial cost");
    assert_relative(last, 18853.020732555, STOPPING, "final cost");
}

/// GTSAM (`load3D`, poses chained through the odometry, LM to relative and
/// absolute error tolerances of 1e-12, 113 iterations): 12280978.769842 →
/// 1132.9919955365. With the default options (uniform damping for pose
/// graphs, cost tolerance 1e-8) `solve` stops within [`STOPPING`] of that
/// optimum, where apex's defaults stopped 0.14% above it.
#[test]
fn sphere2500_reaches_gtsams_optimum_with_the_defaults() {
    let output = solve_ok(&["solve", &data("sphere2500.txt")]);
    let (initial, last) = costs(&output);
    assert_relative(initial, 12280978.769842198, 1e-9, "initial cost");
    assert_relative(last, 1132.9919955365212, STOPPING, "final cost");
    assert!(stdout(&output).contains("converged (the last step"));
}

/// GTSAM: 14538.70641 → 1577.0301094628. Tolerance 1e-5 relative: GTSAM
/// keeps the VO file's rotation matrices as written (orthonormal to about
/// 1e-6), `solve` takes their nearest rotations, so the two problems differ
/// at that level (their initial costs by 2.5e-6 relative, their optima by
/// 2.9e-6).
#[test]
fn kitti_vo_reaches_gtsams_optimum() {
    let output = solve_ok(&["solve", &data("VO_stereo_factors_large.txt")]);
    let (initial, last) = costs(&output);
    assert_relative(initial, 14538.70641, 1e-5, "initial cost");
    assert_relative(last, 1577.0301094628, 1e-5, "final cost");
}

/// Dubrovnik's 19 observations (38 residuals) cannot determine its 3
/// cameras and 7 points (48 parameters, 41 once camera 0's pose and the
/// scale are held): the cost has no isolated minimum and goes to zero, in
/// GTSAM too (1.7e-4 after 1000 iterations). Within the default iteration
/// limit the solve reaches the rounding of zero, where the undamped steps
/// are shorter than the parameter tolerance: converged, every observation
/// fitted exactly (with 100 iterations it stopped at the limit, 1e-4).
#[test]
fn dubrovnik_is_underdetermined() {
    let output = solve_ok(&["solve", &data("dubrovnik-3-7-pre.txt")]);
    let (initial, last) = costs(&output);
    assert_relative(initial, 2764.2199844221705, 1e-12, "initial cost");
    assert!(last < 1e-20, "{last}");
    assert!(
        stdout(&output).contains("converged (the last step was shorter than 1e-8"),
        "{}",
        stdout(&output)
    );
    let limited = solve_ok(&[
        "solve",
        &data("dubrovnik-3-7-pre.txt"),
        "--max-iterations",
        "100",
    ]);
    assert!(stdout(&limited).contains("iteration limit"));
    assert!(costs(&limited).1 < 1e-3);
}

/// Dual numbers and the generated kernels take the same steps, on either
/// solver.
#[test]
fn dual_kernels_reach_the_same_cost() {
    for solver in ["schur", "apex"] {
        let generated = costs(&solve_ok(&[
            "solve",
            &data("Balbianello.out"),
            "--solver",
            solver,
        ]));
        let output = solve_ok(&[
            "solve",
            &data("Balbianello.out"),
            "--solver",
            solver,
            "--kernels",
            "dual",
        ]);
        if solver == "schur" {
            assert!(
                stdout(&output).contains("dual numbers, one factor at a time"),
                "{}",
                stdout(&output)
            );
        }
        let dual = costs(&output);
        assert_relative(dual.0, generated.0, 1e-12, "initial cost");
        assert_relative(dual.1, generated.1, 1e-10, "final cost");
    }
}

/// Every data set goes to the Schur-complement solver by default and
/// reaches apex-solver's final cost (within the stopping tolerance: their
/// iterates differ by the rounding of two implementations); g2o's line and
/// plane graphs with the documents' factors too.
#[test]
fn the_schur_solver_is_chosen_where_it_applies() {
    for file in [
        "Balbianello.out",
        "VO_stereo_factors_large.txt",
        "pose3example.txt",
        "sphere2500.txt",
        "g2o-addons/line3d.g2o",
        "g2o-addons/points3d_gps.g2o",
    ] {
        let schur = solve_ok(&["solve", &data(file)]);
        let apex = solve_ok(&["solve", &data(file), "--solver", "apex"]);
        assert!(
            stdout(&schur).contains("Schur complement") || stdout(&schur).contains("factor-schur"),
            "{}",
            stdout(&schur)
        );
        assert!(stdout(&apex).contains("(apex-solver)"), "{}", stdout(&apex));
        let (a, b) = (costs(&schur), costs(&apex));
        assert_relative(a.0, b.0, 1e-12, "initial cost");
        assert_relative(a.1, b.1, STOPPING, "final cost");
    }
    // The documents' factors on g2o's graphs: the Schur-complement solver
    // (the factors on the body pose, by dual numbers) against apex-solver
    // (the documents' generated kernels on its inverse pose).
    for file in ["g2o-addons/line3d.g2o", "g2o-addons/plane3d_planar.g2o"] {
        let file = data(file);
        let schur = solve_ok(&["solve", &file, "--factors", "documents"]);
        let forced = solve_ok(&[
            "solve",
            &file,
            "--factors",
            "documents",
            "--solver",
            "schur",
        ]);
        let apex = solve_ok(&["solve", &file, "--factors", "documents", "--solver", "apex"]);
        for (text, words) in [
            (stdout(&schur), "by dual numbers"),
            (stdout(&forced), "by dual numbers"),
            (stdout(&apex), "(apex-solver)"),
        ] {
            assert!(text.contains(words), "{text}");
        }
        assert!(stdout(&schur).contains("on_body"), "{}", stdout(&schur));
        let (a, b) = (costs(&schur), costs(&forced));
        assert_relative(a.1, b.1, 1e-12, "final cost, --solver schur");
        let (a, b) = (costs(&schur), costs(&apex));
        assert_relative(a.0, b.0, 1e-12, "initial cost");
        assert_relative(a.1, b.1, STOPPING, "final cost");
    }
}

/// A problem file of the documents' factors (`synth-plp`'s default room,
/// seed 2: points, orthonormal lines, planes with a full noise model) goes
/// to the Schur-complement solver by default, printing it in the header,
/// and reaches apex-solver's optimum (or lower) with the same trajectory
/// errors; `--solver schur` on a file it cannot take is a one-line error.
#[test]
fn problem_files_take_the_schur_solver_and_agree_with_apex() {
    let dir = temp_dir("plp_schur");
    let file = dir.join("room.json");
    let file = file.to_str().unwrap();
    solve_ok(&["synth-plp", "--seed", "2", "--output", file]);
    let schur = solve_ok(&["solve", file]);
    let apex = solve_ok(&["solve", file, "--solver", "apex", "--max-iterations", "500"]);
    assert!(
        stdout(&schur).contains("(problem file)") && stdout(&schur).contains("Schur complement"),
        "{}",
        stdout(&schur)
    );
    assert!(stdout(&apex).contains("(apex-solver)"), "{}", stdout(&apex));
    let (a, b) = (costs(&schur), costs(&apex));
    assert_relative(a.0, b.0, 1e-12, "initial cost");
    assert!(
        a.1 <= b.1 * (1.0 + 1e-6),
        "final cost {} against apex's {}",
        a.1,
        b.1
    );
    let ate = |output: &Output| -> String {
        let text = stdout(output);
        let line = text
            .lines()
            .find(|l| l.contains("ATE RMSE"))
            .expect("an ATE line");
        line.to_owned()
    };
    assert_eq!(ate(&schur), ate(&apex));
    // A free line seen from poses that the point factors perturb on the
    // left and the free-line factors on the right: the Schur solver (one
    // chart per variable) cannot take it, apex-solver (its own chart)
    // can, and the default path says why it goes there.
    let mut room: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
    room["variables"]["fl"] = serde_json::json!({"type": "FreeLine", "value": {"rotation": [0, 0, 0, 1], "distance": 2.0}});
    for (k, pose) in ["c3", "c4", "c5", "c6"].iter().enumerate() {
        let k = k as f64;
        room["factors"]
            .as_array_mut()
            .unwrap()
            .push(serde_json::json!({
                "factor": "free_line",
                "variables": {"body_pose": pose, "line": "fl"},
                "constants": {
                    "extrinsics": {"rotation": [0, 0, 0, 1], "translation": [0, 0, 0]},
                    "bearing_start": [0.1 * k, 0.2, 1.0],
                    "bearing_end": [0.3, -0.2 + 0.05 * k, 1.0]
                }
            }));
    }
    let mixed = dir.join("mixed.json");
    let mixed = mixed.to_str().unwrap();
    std::fs::write(mixed, room.to_string()).unwrap();
    let auto = solve_ok(&["solve", mixed]);
    let apex = solve_ok(&["solve", mixed, "--solver", "apex"]);
    let text = stdout(&auto);
    assert!(
        text.contains("solved by apex-solver: the Schur-complement solver cannot take it")
            && text.contains("variable \"c3\"")
            && !text.contains("left: left"),
        "{text}"
    );
    assert_relative(costs(&auto).1, costs(&apex).1, 1e-12, "the same solve");
    let refused = slamjac(&["solve", mixed, "--solver", "schur"]);
    assert_error(
        &refused,
        2,
        &["--solver schur cannot take this problem file: variable \"c3\""],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `room` (a problem file of points and `Se3` cameras, `X_c = R X_w + t`)
/// with its world moved by `shift`: every point and true point plus
/// `shift`, every camera's `t` less `R shift`; the same residuals.
fn shifted(room: &serde_json::Value, shift: nalgebra::Vector3<f64>) -> serde_json::Value {
    let move_value = |value: &mut serde_json::Value| {
        if let Some(xyz) = value.as_array_mut() {
            for (x, s) in xyz.iter_mut().zip(shift.iter()) {
                *x = (x.as_f64().unwrap() + s).into();
            }
        } else {
            let q: Vec<f64> = serde_json::from_value(value["rotation"].clone()).unwrap();
            let t: Vec<f64> = serde_json::from_value(value["translation"].clone()).unwrap();
            let rotation = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                q[3], q[0], q[1], q[2],
            ));
            let t = nalgebra::Vector3::from_column_slice(&t) - rotation * shift;
            value["translation"] = serde_json::json!([t.x, t.y, t.z]);
        }
    };
    let mut room = room.clone();
    for variable in room["variables"].as_object_mut().unwrap().values_mut() {
        move_value(&mut variable["value"]);
    }
    for value in room["truth"].as_object_mut().unwrap().values_mut() {
        move_value(value);
    }
    room
}

/// `synth-plp`'s room of points (seed 1), written in `dir`, and the final
/// cost of its solve with the defaults.
fn points_room(dir: &Path) -> (serde_json::Value, f64) {
    let file = dir.join("room.json");
    let file = file.to_str().unwrap();
    solve_ok(&[
        "synth-plp",
        "--seed",
        "1",
        "--kinds",
        "points",
        "--output",
        file,
    ]);
    let room = serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
    (room, costs(&solve_ok(&["solve", file])).1)
}

/// A room written in georeferenced coordinates (`synth-plp`'s points,
/// seed 1, moved by up to 10⁵ m) reaches the unmoved room's optimum. Moved
/// by 10⁶ m, the steps towards it are refused by the accuracy envelope (a
/// depth of a few metres from coordinates of 10⁶) and the damping they
/// raise shortens the last accepted step below the parameter tolerance
/// (relative to `‖x‖ ≈ 10⁸`): the summary says it stopped short, not
/// converged, where it used to say "converged" at 13 times the optimum.
#[test]
fn georeferenced_rooms_reach_the_optimum_or_say_they_stopped_short() {
    let dir = temp_dir("georeferenced");
    let (room, optimum) = points_room(&dir);
    let direction = nalgebra::Vector3::new(1.0, 0.6, 0.3);
    for magnitude in [1e3, 1e5, 1e6] {
        let moved = dir.join(format!("room-{magnitude:e}.json"));
        std::fs::write(&moved, shifted(&room, direction * magnitude).to_string()).unwrap();
        let output = slamjac(&["solve", moved.to_str().unwrap()]);
        if magnitude < 1e6 {
            assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
            assert_relative(costs(&output).1, optimum, 1e-8, "the moved room's optimum");
        } else {
            assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
            let summary = stdout(&output);
            assert!(
                summary.contains("summary: stopped short of a minimum, not converged")
                    && summary.contains("outside the accuracy envelope"),
                "{summary}"
            );
            assert!(costs(&output).1 > optimum, "{summary}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Noise models spanning the `f64` range: every σ 1e-80 (weights 1e160,
/// gradients near 1e165) reaches the unit optimum times 1e160 on both
/// paths; one observation 1e4 times tighter than the rest is solved (not
/// refused as unobservable: the tight rows determine two directions of its
/// point, the loose ones the third) at the same cost by both paths.
#[test]
fn noise_scales_decide_neither_observability_nor_convergence() {
    let dir = temp_dir("noise-scales");
    let (room, optimum) = points_room(&dir);
    let mut tiny = room.clone();
    for factor in tiny["factors"].as_array_mut().unwrap() {
        factor["noise"] = serde_json::json!({"sigma": 1e-80});
    }
    let mut tight = room.clone();
    tight["factors"][5]["noise"] = serde_json::json!({"sigma": 1e-4});
    for (name, problem) in [("tiny", tiny), ("tight", tight)] {
        let path = dir.join(format!("{name}.json"));
        std::fs::write(&path, problem.to_string()).unwrap();
        let schur = solve_ok(&["solve", path.to_str().unwrap()]);
        let apex = solve_ok(&["solve", path.to_str().unwrap(), "--solver", "apex"]);
        assert!(
            stdout(&schur).contains("Schur complement"),
            "{}",
            stdout(&schur)
        );
        assert_relative(costs(&schur).1, costs(&apex).1, 1e-8, "both paths");
        if name == "tiny" {
            assert_relative(costs(&schur).1, optimum * 1e160, 1e-8, "the scaled optimum");
        }
    }
    // Every σ larger by 1e6 reaches the optimum divided by 1e12; by 1e10
    // and 1e15 (Marquardt's absolute floor of 1e-6 on `D` then outweighs
    // the curvature) the Schur path may run out of iterations, but says
    // "converged" only at the optimum: it said so at 46% above it (1e10,
    // the absolute cost floor) and at the initial cost (1e15).
    for scale in [1e6_f64, 1e10, 1e15] {
        let mut loose = room.clone();
        for factor in loose["factors"].as_array_mut().unwrap() {
            factor["noise"] = serde_json::json!({"sigma": scale});
        }
        let path = dir.join(format!("loose-{scale:e}.json"));
        std::fs::write(&path, loose.to_string()).unwrap();
        let output = solve_ok(&["solve", path.to_str().unwrap()]);
        let summary = stdout(&output);
        let expected = optimum / (scale * scale);
        if scale == 1e6 || summary.contains("summary: converged") {
            assert_relative(costs(&output).1, expected, 1e-8, &format!("σ {scale:e}"));
        } else {
            assert!(summary.contains("not converged"), "{summary}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--output` writes the optimized problem in the input's format: solving
/// it again starts at the first solve's final cost. For every format.
#[test]
fn output_round_trips_in_every_format() {
    let dir = temp_dir("output");
    let cases = [
        ("dubrovnik-3-7-pre.txt", "bal.txt", "bal"),
        ("Balbianello.out", "bundle.out", "bundler"),
        ("pose3example.txt", "graph.g2o", "g2o"),
        ("sphere2500.txt", "sphere.txt", "edge3"),
        (
            "VO_stereo_factors_large.txt",
            "VO_camera_poses_opt.txt",
            "kitti-vo",
        ),
    ];
    for (input, name, format) in cases {
        let out = dir.join(name).to_string_lossy().into_owned();
        let first = solve_ok(&[
            "solve",
            &data(input),
            "--max-iterations",
            "5",
            "--output",
            &out,
        ]);
        let (_, last) = costs(&first);
        let again = solve_ok(&["solve", &out, "--format", format, "--max-iterations", "1"]);
        let (initial, _) = costs(&again);
        assert_relative(initial, last, 1e-9, &format!("{input}: re-read cost"));
    }
}

#[test]
fn robust_losses_lower_the_cost_of_outliers() {
    let plain = costs(&solve_ok(&["solve", &data("Balbianello.out")]));
    for loss in ["huber:1", "cauchy:1"] {
        let output = solve_ok(&["solve", &data("Balbianello.out"), "--robust", loss]);
        assert!(stdout(&output).contains(&format!("robust {loss}")));
        let (initial, _) = costs(&output);
        assert!(initial < plain.0, "{loss}: {initial} vs {}", plain.0);
    }
}

#[test]
fn plots_are_svg_with_both_panels() {
    let dir = temp_dir("plot");
    let plot = dir.join("ba.svg");
    solve_ok(&[
        "solve",
        &data("Balbianello.out"),
        "--plot",
        plot.to_str().unwrap(),
    ]);
    let svg = std::fs::read_to_string(&plot).expect("the plot is written");
    assert!(svg.starts_with("<svg"), "{}", &svg[..100.min(svg.len())]);
    assert!(svg.contains("cost per iteration") && svg.contains("reprojection error"));
    let graph = dir.join("graph.svg");
    solve_ok(&[
        "solve",
        &data("pose3example.txt"),
        "--plot",
        graph.to_str().unwrap(),
    ]);
    let svg = std::fs::read_to_string(&graph).expect("the plot is written");
    assert!(svg.contains("cost per iteration") && !svg.contains("reprojection error"));
}

/// Asserts exit code `code` and one line `error: …` on stderr containing
/// every needle.
/// g2o's plane graph (written by g2o's simulator) with g2o's errors: the
/// cost is g2o's χ² / 2 (g2o 2.3's χ² from `bench-peers/g2o/run.sh`: of the
/// file 32 527.722751819099, where g2o's optimizer stops 44.660993284204025;
/// loaded by the same driver, the solution `solve` writes has χ²
/// 44.628383402722477, which g2o does not lower); errors against the
/// simulator's truth are reported; `--output` writes a g2o graph back.
#[test]
fn g2o_plane_graph_reaches_g2os_chi2() {
    let dir = temp_dir("plane3d");
    let out = dir.join("plane3d.g2o").to_string_lossy().into_owned();
    let first = solve_ok(&[
        "solve",
        &data("g2o-addons/plane3d.g2o"),
        "--max-iterations",
        "1000",
        "--output",
        &out,
    ]);
    let (initial, last) = costs(&first);
    assert_relative(2.0 * initial, 32_527.722_751_819_1, 1e-5, "initial χ²");
    assert_relative(2.0 * last, 44.628_383_402_722_48, 1e-5, "final χ²");
    assert!(2.0 * last <= 44.660_993_284_204_03, "{last}");
    let text = stdout(&first);
    assert!(
        text.contains("errors against") && text.contains("plane 3: normal"),
        "{text}"
    );
    let again = solve_ok(&["solve", &out, "--max-iterations", "1"]);
    assert_relative(costs(&again).0, last, 1e-9, "re-read cost");
    // The documents' factors need the offset fixed: the calibration graph
    // is refused with them.
    let refused = slamjac(&[
        "solve",
        &data("g2o-addons/plane3d_calib.g2o"),
        "--factors",
        "documents",
    ]);
    assert_error(&refused, 2, &["the sensor offset is free"]);
}

/// g2o's planar-motion plane graph (`simulator_3d_plane
/// --planar_motion=true`: an `EDGE_SE3_PRIOR` on every pose) solves with the
/// defaults, converged, at or below where g2o's optimizer stops
/// (27.844158923698124, `bench-peers/g2o/README.md`), from g2o's χ² of the
/// file (2 440 171.1682807514); `--output` writes the priors back; a prior
/// naming an undefined offset parameter is an error at its line.
#[test]
fn g2o_planar_motion_graph_with_priors_solves() {
    let dir = temp_dir("planar");
    let out = dir.join("planar.g2o").to_string_lossy().into_owned();
    let first = solve_ok(&[
        "solve",
        &data("g2o-addons/plane3d_planar.g2o"),
        "--output",
        &out,
    ]);
    let text = stdout(&first);
    assert!(
        text.contains("161 priors") && text.contains("converged"),
        "{text}"
    );
    let (initial, last) = costs(&first);
    assert_relative(2.0 * initial, 2_440_171.168_280_751_4, 1e-5, "initial χ²");
    assert!(
        2.0 * last <= 27.844_158_923_698_124 * (1.0 + 1e-5),
        "{last}"
    );
    let written = std::fs::read_to_string(&out).unwrap();
    assert_eq!(written.matches("EDGE_SE3_PRIOR ").count(), 161);
    let again = solve_ok(&["solve", &out, "--max-iterations", "1"]);
    assert_relative(costs(&again).0, last, 1e-9, "re-read cost");
    let bad = dir.join("bad.g2o");
    let original = std::fs::read_to_string(data("g2o-addons/plane3d_planar.g2o")).unwrap();
    std::fs::write(
        &bad,
        original.replacen("EDGE_SE3_PRIOR 4 0 ", "EDGE_SE3_PRIOR 4 5 ", 1),
    )
    .unwrap();
    let output = slamjac(&["solve", bad.to_str().unwrap()]);
    assert_error(&output, 2, &["bad.g2o:", "parameter 5 is not defined"]);
}

fn assert_error(output: &Output, code: i32, needles: &[&str]) {
    let err = stderr(output);
    assert_eq!(output.status.code(), Some(code), "stderr: {err}");
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("error: "), "{err}");
    for needle in needles {
        assert!(err.contains(needle), "`{err}` lacks `{needle}`");
    }
}

#[test]
fn malformed_files_are_reported_at_their_line() {
    let dir = temp_dir("malformed");
    let bal = dir.join("bad.txt");
    std::fs::write(&bal, "1 1 1\n0 0 1.5 x\n").unwrap();
    let output = slamjac(&["solve", bal.to_str().unwrap()]);
    assert_error(&output, 2, &[&format!("{}:2:", bal.display())]);
    let g2o = dir.join("bad.g2o");
    std::fs::write(&g2o, "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nEDGE_SE3:QUAT 0 0\n").unwrap();
    let output = slamjac(&["solve", g2o.to_str().unwrap()]);
    assert_error(&output, 2, &[&format!("{}:2:", g2o.display())]);
    let missing = dir.join("missing.txt");
    let output = slamjac(&["solve", missing.to_str().unwrap()]);
    assert_error(&output, 2, &["missing.txt"]);
}

#[test]
fn bad_options_are_usage_errors() {
    let output = slamjac(&["solve", &data("Balbianello.out"), "--robust", "tukey:1"]);
    assert_error(&output, 2, &["--robust", "tukey"]);
    let output = slamjac(&["solve", &data("Balbianello.out"), "--robust", "huber:-1"]);
    assert_error(&output, 2, &["--robust", "above 0"]);
    let output = slamjac(&["solve", &data("Balbianello.out"), "--format", "ply"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("ply"));
    let output = slamjac(&["solve", &data("Balbianello.out"), "--max-iterations", "0"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
}

/// A point behind its camera at the initial values: nothing to start from.
#[test]
fn degenerate_initial_values_exit_1() {
    let dir = temp_dir("degenerate");
    let bal = dir.join("behind.txt");
    // One camera at the identity, looking down −z, and a point at +z.
    std::fs::write(&bal, "1 1 1\n0 0 10 20\n0 0 0 0 0 0 500 0 0\n0.1 0.2 3\n").unwrap();
    let output = slamjac(&["solve", bal.to_str().unwrap()]);
    assert_error(
        &output,
        1,
        &[
            "observation 1 of 1 (camera index 0, point index 0)",
            "behind the camera",
        ],
    );
    // A problem file's point behind its cameras: the entry is named.
    let mut problem = triangulation();
    problem["variables"]["p"]["value"] = serde_json::json!([0.0, 0.0, -3.0]);
    let file = dir.join("behind.json");
    std::fs::write(&file, problem.to_string()).unwrap();
    assert_error(
        &slamjac(&["solve", file.to_str().unwrap()]),
        1,
        &["error: factors[0]: point_reprojection: degenerate geometry"],
    );
}

/// Values within the readers' range (magnitudes up to 1e100) whose
/// residuals are finite (1e224 px, from f = k1 = 1e100 and a point 1e8
/// times off-axis) but whose squares overflow: the solve stops on
/// non-finite values, says so and exits 1 without writing `--output`.
#[test]
fn non_finite_solves_exit_1() {
    let dir = temp_dir("overflow");
    let bal = dir.join("overflow.txt");
    let out = dir.join("out.txt");
    std::fs::write(
        &bal,
        "2 2 4\n0 0 0 0\n0 1 0 0\n1 0 0 0\n1 1 0 0\n\
         0 0 0 0 0 0 1e100 1e100 0\n0 0 0 0 0 0 500 0 0\n\
         1e8 0 -1\n0.1 0.2 -3\n",
    )
    .unwrap();
    let output = slamjac(&[
        "solve",
        bal.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    let err = stderr(&output);
    assert_eq!(
        output.status.code(),
        Some(1),
        "stdout: {}\nstderr: {err}",
        stdout(&output)
    );
    assert!(
        err.starts_with("error: ") && err.lines().count() == 1,
        "{err}"
    );
    assert!(!out.exists(), "no output after a failed solve");
}

#[test]
fn synthetic_problems_are_generated_and_solved() {
    let dir = temp_dir("synth");
    let file = dir.join("synth.txt");
    let output = slamjac(&[
        "synth-bal",
        "--cameras",
        "8",
        "--points",
        "300",
        "--seed",
        "7",
        "--output",
        file.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(
        stdout(&output).contains("1500 observations"),
        "{}",
        stdout(&output)
    );
    let same = dir.join("same.txt");
    slamjac(&[
        "synth-bal",
        "--cameras",
        "8",
        "--points",
        "300",
        "--seed",
        "7",
        "--output",
        same.to_str().unwrap(),
    ]);
    assert_eq!(
        std::fs::read(&file).unwrap(),
        std::fs::read(&same).unwrap(),
        "seeded"
    );
    // Without outliers, 1 px of noise per coordinate: the optimum's cost is
    // about ½ (3000 residuals − 966 parameters) ≈ 1017.
    let clean = dir.join("clean.txt");
    slamjac(&[
        "synth-bal",
        "--cameras",
        "8",
        "--points",
        "300",
        "--outliers",
        "0",
        "--output",
        clean.to_str().unwrap(),
    ]);
    let (initial, last) = costs(&solve_ok(&["solve", clean.to_str().unwrap()]));
    assert!(last < 1500.0 && initial > 10.0 * last, "{initial} → {last}");
    // With outliers, Huber's cost grows linearly with them.
    let (plain, _) = costs(&solve_ok(&["solve", file.to_str().unwrap()]));
    let (robust, _) = costs(&solve_ok(&[
        "solve",
        file.to_str().unwrap(),
        "--robust",
        "huber:2",
    ]));
    assert!(robust < plain / 10.0, "{plain} vs {robust}");
    let output = slamjac(&[
        "synth-bal",
        "--cameras",
        "1",
        "--points",
        "10",
        "--output",
        dir.join("x.txt").to_str().unwrap(),
    ]);
    assert_error(&output, 2, &["cameras"]);
}

/// A copy of the shipped file `name` in `dir`.
fn copied(name: &str, dir: &Path) -> PathBuf {
    let path = dir.join(name);
    std::fs::copy(data(name), &path).expect("copied");
    path
}

/// Issue 17: an output that names an input (the KITTI VO triple included)
/// or another output is refused before anything is read, and an output
/// that cannot be written before the solve starts; the input is untouched.
#[test]
fn outputs_naming_inputs_or_each_other_are_refused_before_any_work() {
    let dir = temp_dir("collide");
    let input = copied("Balbianello.out", &dir);
    let original = std::fs::read(&input).unwrap();
    let (input_text, svg) = (
        input.to_str().unwrap().to_owned(),
        dir.join("plot.svg").to_str().unwrap().to_owned(),
    );
    let respelled = dir.join(".").join("Balbianello.out");
    let nowhere = dir.join("nowhere/x.out");
    let cases: [(&[&str], &str); 5] = [
        (
            &["--output", &input_text],
            "--output names the same file as the input",
        ),
        (
            &["--plot", &input_text],
            "--plot names the same file as the input",
        ),
        (
            &["--output", respelled.to_str().unwrap()],
            "--output names the same file as the input",
        ),
        (
            &["--plot", &svg, "--output", &svg],
            "--plot names the same file as --output",
        ),
        (
            &["--output", nowhere.to_str().unwrap()],
            "--output: cannot write here",
        ),
    ];
    for (options, message) in cases {
        let mut args = vec!["solve", &input_text];
        args.extend_from_slice(options);
        let output = slamjac(&args);
        assert_error(&output, 2, &[message]);
        assert!(output.stdout.is_empty(), "nothing was read or solved");
    }
    assert_eq!(std::fs::read(&input).unwrap(), original);
    // The KITTI VO set: an output named `VO_calibration.txt` writes the
    // shared calibration the input reads.
    let vo = temp_dir("collide-vo");
    for name in [
        "VO_calibration.txt",
        "VO_camera_poses_large.txt",
        "VO_stereo_factors_large.txt",
    ] {
        copied(name, &vo);
    }
    let output = slamjac(&[
        "solve",
        vo.join("VO_stereo_factors_large.txt").to_str().unwrap(),
        "--output",
        vo.join("VO_calibration.txt").to_str().unwrap(),
    ]);
    assert_error(&output, 2, &["--output names the same file as the input"]);
    assert_eq!(
        std::fs::read(vo.join("VO_calibration.txt")).unwrap(),
        std::fs::read(data("VO_calibration.txt")).unwrap()
    );
}

/// Issue 17: a pipe is read once, its format told from what was read: the
/// same problem, the same costs as from the file.
#[test]
fn piped_problems_are_read_once() {
    for name in [
        "pose3example.txt",
        "sphere2500.txt",
        "dubrovnik-3-7-pre.txt",
    ] {
        let from_file = costs(&solve_ok(&["solve", &data(name), "--max-iterations", "2"]));
        let piped = common::slamjac_with_stdin(
            &["solve", "/dev/stdin", "--max-iterations", "2"],
            &std::fs::read(data(name)).unwrap(),
        );
        assert_eq!(piped.status.code(), Some(0), "{name}: {}", stderr(&piped));
        assert_eq!(costs(&piped), from_file, "{name}");
    }
}

/// Issue 17: a problem without a single observation or edge has nothing to
/// solve (it reported a cost of `-0` and exit 0).
#[test]
fn empty_problems_are_errors() {
    let dir = temp_dir("empty");
    let cases = [
        (
            "bal.txt",
            "1 1 0\n0 0 0 0 0 0 500 0 0\n0 0 -3\n",
            None,
            "observations",
        ),
        (
            "graph.g2o",
            "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n",
            None,
            "edges",
        ),
        ("sphere.txt", "", Some("edge3"), "edges"),
    ];
    for (name, text, format, what) in cases {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let mut args = vec!["solve", path.to_str().unwrap()];
        if let Some(format) = format {
            args.extend_from_slice(&["--format", format]);
        }
        assert_error(
            &slamjac(&args),
            2,
            &[&format!("nothing to solve: the problem has no {what}")],
        );
    }
}

/// Issue 17: Cauchy's loss with a large δ is least squares (apex-solver's
/// rounded its cost to 0); δ is bounded to the readers' range.
#[test]
fn a_large_cauchy_scale_is_least_squares() {
    let plain = costs(&solve_ok(&["solve", &data("Balbianello.out")]));
    let cauchy = costs(&solve_ok(&[
        "solve",
        &data("Balbianello.out"),
        "--robust",
        "cauchy:1e10",
    ]));
    assert_relative(cauchy.0, plain.0, 1e-12, "initial cost");
    assert_relative(cauchy.1, plain.1, STOPPING, "final cost");
    let output = slamjac(&[
        "solve",
        &data("Balbianello.out"),
        "--robust",
        "cauchy:1e200",
    ]);
    assert_error(&output, 2, &["--robust", "from 1e-100 to 1e100"]);
}

/// Issue 17: the README's "name any of the three": the shared calibration
/// names the set it serves.
#[test]
fn the_shared_calibration_names_the_kitti_set() {
    let output = solve_ok(&[
        "solve",
        &data("VO_calibration.txt"),
        "--max-iterations",
        "1",
    ]);
    assert!(
        stdout(&output).contains("8189 stereo observations"),
        "{}",
        stdout(&output)
    );
}

/// A shipped file's text with `count` seeded edits: a line dropped,
/// doubled or truncated, a field replaced by a hostile token, bytes
/// flipped.
fn mutated(text: &[u8], rng: &mut Rng, count: usize) -> Vec<u8> {
    const TOKENS: &[&str] = &[
        "0",
        "-1",
        "1e999",
        "nan",
        "inf",
        "-0",
        "1e100",
        "1e101",
        "4.9e-324",
        "1e-300",
        "18446744073709551616",
        "999999999",
        "x",
        "\u{feff}",
        "\u{200b}",
        "\u{1b}[2J",
        "",
        "VERTEX3",
        "EDGE_SE3:QUAT",
        "#",
    ];
    let mut lines: Vec<Vec<u8>> = text.split(|b| *b == b'\n').map(<[u8]>::to_vec).collect();
    for _ in 0..count {
        let at = rng.below(lines.len());
        match rng.below(5) {
            0 => {
                lines.remove(at);
            }
            1 => {
                let line = lines[at].clone();
                lines.insert(at, line);
            }
            2 => {
                let keep = rng.below(lines[at].len() + 1);
                lines[at].truncate(keep);
            }
            3 => {
                let mut fields: Vec<Vec<u8>> = lines[at]
                    .split(|b| *b == b' ')
                    .map(<[u8]>::to_vec)
                    .collect();
                let field = rng.below(fields.len());
                fields[field] = rng.pick(TOKENS).as_bytes().to_vec();
                lines[at] = fields.join(&b' ');
            }
            _ if !lines[at].is_empty() => {
                let byte = rng.below(lines[at].len());
                lines[at][byte] = rng.next() as u8;
            }
            _ => {}
        }
        if lines.is_empty() {
            lines.push(Vec::new());
        }
    }
    lines.join(&b'\n')
}

/// Issue 17: `solve`'s five readers fuzzed end to end (seeded mutations of
/// the shipped files, one solve step each): exit 0 with a summary, or 1 or
/// 2 with one printable line `error: …` printing no computed `NaN` or
/// `inf`; never a panic or a signal. A few seconds in all.
#[test]
fn fuzzed_problem_files_keep_the_contract() {
    let mut rng = Rng(0x501e_f022);
    let dir = temp_dir("fuzz");
    let singles = [
        ("dubrovnik-3-7-pre.txt", "bal.txt", 60),
        ("Balbianello.out", "bundle.out", 40),
        ("pose3example.txt", "graph.g2o", 60),
        ("sphere2500.txt", "sphere.txt", 24),
    ];
    let mut cases: Vec<(String, PathBuf)> = Vec::new();
    for (name, target, count) in singles {
        let text = std::fs::read(data(name)).unwrap();
        for k in 0..count {
            let path = dir.join(format!("{k}-{target}"));
            let edits = 1 + rng.below(3);
            std::fs::write(&path, mutated(&text, &mut rng, edits)).unwrap();
            cases.push((format!("{name} #{k}"), path));
        }
    }
    // KITTI VO: one of the three files mutated in a copy of the set.
    let vo_files = [
        "VO_calibration.txt",
        "VO_camera_poses_large.txt",
        "VO_stereo_factors_large.txt",
    ];
    for k in 0..18 {
        let set = dir.join(format!("vo-{k}"));
        std::fs::create_dir_all(&set).unwrap();
        let victim = rng.below(3);
        for (i, name) in vo_files.iter().enumerate() {
            let text = std::fs::read(data(name)).unwrap();
            let edits = 1 + rng.below(3);
            let text = if i == victim {
                mutated(&text, &mut rng, edits)
            } else {
                text
            };
            std::fs::write(set.join(name), text).unwrap();
        }
        cases.push((
            format!("KITTI VO #{k} ({})", vo_files[victim]),
            set.join(vo_files[2]),
        ));
    }
    for (label, path) in cases {
        let output = slamjac(&["solve", path.to_str().unwrap(), "--max-iterations", "1"]);
        let err = stderr(&output);
        match output.status.code() {
            Some(0) => assert!(stdout(&output).contains("cost: initial"), "{label}"),
            Some(1 | 2) => {
                let line = err.strip_suffix('\n').unwrap_or(&err);
                assert!(
                    line.starts_with("error: ") && !line.contains('\n'),
                    "{label}: {err}"
                );
                assert!(
                    !line
                        .chars()
                        .any(slamjac_problem::field_path::is_unprintable),
                    "{label}: {line:?}"
                );
                // Outside the input's own tokens (quoted in backticks), no
                // number is printed non-finite.
                let computed = line.split('`').step_by(2).collect::<String>();
                assert!(
                    !computed
                        .split(|c: char| !(c.is_alphanumeric() || c == '-'))
                        .any(|w| matches!(w, "NaN" | "inf" | "-inf")),
                    "{label}: {line}"
                );
            }
            other => panic!("{label}: exit {other:?}: {err}"),
        }
    }
}

/// A problem file: two fixed cameras triangulating a point (observations
/// computed here from the true point), its factor's noise and robust loss
/// as written.
fn triangulation() -> serde_json::Value {
    let truth = [0.2, -0.1, 4.0];
    let mut factors = Vec::new();
    for (name, x) in [("c0", -0.5), ("c1", 0.5)] {
        let p = [truth[0] + x, truth[1], truth[2]];
        factors.push(serde_json::json!({
            "factor": "point_reprojection",
            "variables": {"pose": name, "point": "p"},
            "constants": {
                "intrinsics": [500.0, 500.0, 320.0, 240.0],
                "observed": [500.0 * p[0] / p[2] + 320.0, 500.0 * p[1] / p[2] + 240.0]
            },
            "noise": {"sigmas": [1.0, 2.0]},
            "robust": "huber:10"
        }));
    }
    let camera = |x: f64| {
        serde_json::json!({
            "type": "Se3",
            "value": {"rotation": [0.0, 0.0, 0.0, 1.0], "translation": [x, 0.0, 0.0]},
            "fixed": true
        })
    };
    serde_json::json!({
        "slamjac_problem": 1,
        "variables": {
            "p": {"type": "Vector3", "value": [0.0, 0.0, 3.0]},
            "c0": camera(-0.5),
            "c1": camera(0.5)
        },
        "factors": factors
    })
}

/// Solved, the point is the true one; `--output` then `solve` again gives
/// the same cost.
#[test]
fn problem_files_are_solved_and_round_trip() {
    let dir = temp_dir("problem-file");
    let input = dir.join("tri.json");
    std::fs::write(&input, triangulation().to_string()).unwrap();
    let out = dir.join("tri-solved.json");
    let first = solve_ok(&[
        "solve",
        input.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    let (initial, last) = costs(&first);
    assert!(initial > 1.0 && last < 1e-12, "{initial} → {last}");
    // The measurements fit exactly: converged at the rounding of a zero
    // residual (it said "no step reduces the cost any more" once the cost
    // reached 0 under the scale-free tests).
    assert!(
        stdout(&first).contains("summary: converged"),
        "{}",
        stdout(&first)
    );
    let solved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let point: Vec<f64> =
        serde_json::from_value(solved["variables"]["p"]["value"].clone()).unwrap();
    for (got, want) in point.iter().zip([0.2, -0.1, 4.0]) {
        assert!((got - want).abs() < 1e-9, "{point:?}");
    }
    let again = solve_ok(&["solve", out.to_str().unwrap(), "--max-iterations", "1"]);
    assert_relative(costs(&again).0 + 1e-30, last + 1e-30, 1e-6, "re-read cost");
}

/// A way to spoil a problem file, and what its error must say.
type Spoiled = (fn(&mut serde_json::Value), &'static [&'static str]);

/// Malformed problem files: one line naming the field, exit 2.
#[test]
fn malformed_problem_files_name_the_field() {
    let dir = temp_dir("bad-problem-file");
    let cases: Vec<Spoiled> = vec![
        (
            |p| p["slamjac_problem"] = 2.into(),
            &["slamjac_problem: version 2"],
        ),
        (
            |p| p["variables"]["p"]["type"] = "Vector2".into(),
            &["factors[0].variables.point", "is a Vector2"],
        ),
        (
            |p| p["factors"][1]["variables"]["pose"] = "c9".into(),
            &["factors[1].variables.pose", "no variable \"c9\""],
        ),
        (
            |p| p["factors"][0]["noise"] = serde_json::json!({"sigmas": [1.0]}),
            &["factors[0].noise.sigmas"],
        ),
        (
            |p| p["factors"][0]["noise"] = serde_json::json!({"sigma": -1.0}),
            &[
                "factors[0].noise.sigma",
                "a standard deviation must be from 1e-100",
            ],
        ),
        (
            |p| p["factors"][0]["robust"] = "tukey:1".into(),
            &["factors[0].robust", "unknown loss"],
        ),
        (
            |p| p["variables"]["c0"]["value"]["rotation"] = serde_json::json!([0, 0, 0, 2]),
            &["error: variables.c0.value.rotation: ", "norm"],
        ),
        (
            |p| p["variables"]["p"]["value"] = serde_json::json!([0, 0, "x"]),
            &["error: variables.p.value[2]: "],
        ),
        (
            |p| p["factors"][0]["factor"] = "nope".into(),
            &["factors[0].factor", "unknown factor"],
        ),
        (
            |p| p["variables"]["q"] = serde_json::json!({"type": "Vector3", "value": [0, 0, 1]}),
            &["variables.q", "no factor uses this variable"],
        ),
        (
            |p| p["factors"][0]["extra"] = 1.into(),
            &["factors[0].extra", "unknown field"],
        ),
        (
            |p| p["truth"] = serde_json::json!({"c9": [0, 0, 1]}),
            &["truth.c9", "no variable of this name"],
        ),
        (
            |p| p["truth"] = serde_json::json!({"p": [0, 1]}),
            &["truth.p", "3 numbers"],
        ),
    ];
    for (k, (spoil, needles)) in cases.into_iter().enumerate() {
        let mut problem = triangulation();
        spoil(&mut problem);
        let path = dir.join(format!("bad{k}.json"));
        std::fs::write(&path, problem.to_string()).unwrap();
        assert_error(&slamjac(&["solve", path.to_str().unwrap()]), 2, needles);
    }
}

/// The `(initial, final)` SE(3)-aligned ATE of `solve`'s errors against a
/// problem file's truth.
fn ate(output: &Output) -> (f64, f64) {
    let text = stdout(output);
    let key = "ATE RMSE SE(3)-aligned ";
    let at = text
        .find(key)
        .unwrap_or_else(|| panic!("no ATE in:\n{text}"))
        + key.len();
    let numbers: Vec<f64> = text[at..]
        .split_whitespace()
        .take(3)
        .filter_map(|w| w.parse().ok())
        .collect();
    (numbers[0], numbers[1])
}

/// A `synth-plp` room with points, lines and planes: solved, its trajectory
/// is nearer the truth than it started; the same seed writes the same file.
#[test]
fn synthetic_point_line_plane_rooms_are_solved_against_their_truth() {
    let dir = temp_dir("plp");
    let file = dir.join("room.json");
    let again = dir.join("room-again.json");
    for path in [&file, &again] {
        let written = solve_ok(&[
            "synth-plp",
            "--seed",
            "2",
            "--points",
            "150",
            "--output",
            path.to_str().unwrap(),
        ]);
        assert!(
            stdout(&written).contains("15 cameras"),
            "{}",
            stdout(&written)
        );
    }
    assert_eq!(
        std::fs::read(&file).unwrap(),
        std::fs::read(&again).unwrap()
    );
    let solved = solve_ok(&["solve", file.to_str().unwrap()]);
    let (initial, last) = ate(&solved);
    assert!(last < initial, "ATE {initial} → {last}");
    let text = stdout(&solved);
    assert!(text.contains(" lines: mean direction") && text.contains(" planes: mean normal"));
    assert_error(
        &slamjac(&["synth-plp", "--kinds", "points,walls", "--output", "x.json"]),
        2,
        &["--kinds", "walls"],
    );
    // Four cameras of the room see no point twice: refused, nothing written.
    let empty = std::env::temp_dir().join(format!("plp-empty-{}.json", std::process::id()));
    let refused = slamjac(&[
        "synth-plp",
        "--cameras",
        "4",
        "--kinds",
        "points",
        "--output",
        empty.to_str().unwrap(),
    ]);
    assert_error(
        &refused,
        2,
        &["nothing measured with --cameras 4 --kinds points"],
    );
    assert!(!empty.exists(), "nothing written");
}

/// A `synth-plp` room whose lines are Plücker lines `[n, v]`
/// (`plucker_line_reprojection`): solved in their orthonormal chart by the
/// Schur-complement solver (as `line_reprojection`), by default, and by
/// apex-solver (`SO3 × SO2`) on request; both reach the optimum of the same
/// room with orthonormal lines, and every line returned is on the Klein
/// quadric (`n · v = 0` to rounding) with a unit direction, and passes
/// `OrthonormalLine::try_from_plucker`. (Served as a free `Rn(6)`, the
/// lines left the quadric, cosines up to 0.61, and now that unobservable
/// directions are refused, the scale of each `[n, v]`, seen by no residual,
/// made the solve refuse the file.)
#[test]
fn plucker_lines_stay_on_the_klein_quadric() {
    use factor_core::geometry::{OrthonormalLine, PluckerLine};
    use nalgebra::Vector3;
    let dir = temp_dir("plucker");
    let orthonormal = dir.join("room.json");
    let file = dir.join("room-plucker.json");
    let solved_file = dir.join("room-solved.json");
    solve_ok(&[
        "synth-plp",
        "--seed",
        "2",
        "--kinds",
        "points,lines",
        "--output",
        orthonormal.to_str().unwrap(),
    ]);
    let mut room: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&orthonormal).unwrap()).unwrap();
    let mut lines = Vec::new();
    for (name, variable) in room["variables"].as_object_mut().unwrap() {
        if variable["type"] == "OrthonormalLine" {
            variable["type"] = "PluckerLine".into();
            lines.push(name.clone());
        }
    }
    // A truth is read for orthonormal lines, not Plücker lines.
    let truth = room["truth"].as_object_mut().unwrap();
    lines.iter().for_each(|name| drop(truth.remove(name)));
    for factor in room["factors"].as_array_mut().unwrap() {
        if factor["factor"] == "line_reprojection" {
            factor["factor"] = "plucker_line_reprojection".into();
        }
    }
    assert!(lines.len() > 10, "{lines:?}");
    std::fs::write(&file, room.to_string()).unwrap();
    // The same lines in the same 4-dof chart: the optimum of the room with
    // orthonormal lines (each solver stops when a step gains less than 1e-8
    // of the cost).
    let same = solve_ok(&["solve", orthonormal.to_str().unwrap()]);
    let vector = |value: &serde_json::Value| -> Vector3<f64> {
        Vector3::from_vec(serde_json::from_value(value.clone()).unwrap())
    };
    for (solver, words) in [("auto", "Schur complement"), ("apex", "(apex-solver)")] {
        let plucker = solve_ok(&[
            "solve",
            file.to_str().unwrap(),
            "--solver",
            solver,
            "--output",
            solved_file.to_str().unwrap(),
        ]);
        assert!(stdout(&plucker).contains(words), "{}", stdout(&plucker));
        assert_relative(costs(&plucker).1, costs(&same).1, 1e-7, "final cost");
        let solved: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&solved_file).unwrap()).unwrap();
        for name in &lines {
            let value = &solved["variables"][name]["value"];
            let line = PluckerLine::new(vector(&value["normal"]), vector(&value["direction"]));
            let (n, v) = (line.normal, line.direction);
            assert!(
                (v.norm() - 1.0).abs() < 1e-12,
                "{solver} {name}: |v| = {}",
                v.norm()
            );
            assert!(
                n.dot(&v).abs() <= 1e-12 * n.norm().max(1.0),
                "{solver} {name}: n · v = {:e}",
                n.dot(&v)
            );
            if let Err(e) = OrthonormalLine::try_from_plucker(&line) {
                panic!("{solver} {name}: {e}");
            }
        }
    }
    // Any scale of `[n, v]` is the same line: the first line at 1e200 (its
    // image line beyond the accuracy envelope at that scale) is solved at
    // a unit direction, to the same optimum.
    let first = &lines[0];
    let scaled = dir.join("room-scaled.json");
    let mut huge = room.clone();
    for key in ["normal", "direction"] {
        let value = &mut huge["variables"][first]["value"][key];
        let scaled: Vec<f64> = serde_json::from_value::<Vec<f64>>(value.clone())
            .unwrap()
            .iter()
            .map(|x| x * 1e200)
            .collect();
        *value = scaled.into();
    }
    std::fs::write(&scaled, huge.to_string()).unwrap();
    let output = solve_ok(&["solve", scaled.to_str().unwrap()]);
    assert!(
        stdout(&output).contains("Schur complement"),
        "{}",
        stdout(&output)
    );
    assert_relative(
        costs(&output).1,
        costs(&same).1,
        1e-7,
        "final cost at 1e200",
    );
    // A line through the world origin (`n = 0`), where the orthonormal
    // chart is singular: apex-solver's path takes the file, saying why.
    let through = dir.join("room-origin.json");
    room["variables"][first]["value"]["normal"] = serde_json::json!([0.0, 0.0, 0.0]);
    std::fs::write(&through, room.to_string()).unwrap();
    let output = solve_ok(&["solve", through.to_str().unwrap()]);
    let why = format!(
        "variable \"{first}\": the line passes through the world origin, where its orthonormal \
         chart (this solver's) is singular"
    );
    assert!(
        stdout(&output).contains("(apex-solver)"),
        "{}",
        stdout(&output)
    );
    assert!(stderr(&output).contains(&why) || stdout(&output).contains(&why));
    let refused = slamjac(&["solve", through.to_str().unwrap(), "--solver", "schur"]);
    assert_error(&refused, 2, &[&why, "(use --solver apex)"]);
}

/// A problem file of factors without fused kernels (`g2o_se3`, a loop of
/// six poses with a loop closure): the Schur-complement solver takes it by
/// default, one factor at a time (every other pose eliminated), and reaches
/// apex-solver's cost; with `--kernels dual`, by dual numbers, the same.
#[test]
fn problem_files_of_factors_without_fused_kernels_take_the_schur_solver() {
    use factor_core::lie::{Se3, So3};
    use nalgebra::Vector3;
    let pose = |k: usize| {
        let angle = k as f64 * std::f64::consts::PI / 3.0;
        Se3::new(
            So3::exp(&Vector3::new(0.0, 0.0, angle + 0.1)),
            Vector3::new(3.0 * angle.cos(), 3.0 * angle.sin(), 0.1 * k as f64),
        )
    };
    let json = |p: &Se3<f64>| {
        let q = p.rotation.quaternion;
        serde_json::json!({
            "rotation": [q.x, q.y, q.z, q.w],
            "translation": [p.translation.x, p.translation.y, p.translation.z]
        })
    };
    let mut variables = serde_json::Map::new();
    for k in 0..6 {
        // Initial values off the truth by a rotation and a shift.
        let off = Se3::new(
            So3::exp(&Vector3::new(0.02 * k as f64, -0.03, 0.05)),
            Vector3::new(0.1, -0.2 * k as f64, 0.05),
        );
        variables.insert(
            format!("x{k}"),
            serde_json::json!({
                "type": "Se3RhoTheta",
                "value": json(&if k == 0 { pose(0) } else { pose(k).compose(&off) }),
                "fixed": k == 0
            }),
        );
    }
    let factors: Vec<serde_json::Value> = (0..6)
        .map(|k| {
            let (i, j) = (k, (k + 1) % 6);
            // A measurement a little off the truth, so the optimum is not 0.
            let noise = Se3::new(
                So3::exp(&Vector3::new(0.01, 0.0, -0.01 * k as f64)),
                Vector3::new(0.02, 0.01, 0.0),
            );
            let measured = pose(i).inverse().compose(&pose(j)).compose(&noise);
            serde_json::json!({
                "factor": "g2o_se3",
                "variables": {"pose_i": format!("x{i}"), "pose_j": format!("x{j}")},
                "constants": {"measured": json(&measured)},
                "noise": {"sigma": 0.1}
            })
        })
        .collect();
    let truth: serde_json::Map<String, serde_json::Value> =
        (0..6).map(|k| (format!("x{k}"), json(&pose(k)))).collect();
    let problem = serde_json::json!({
        "slamjac_problem": 1,
        "variables": variables,
        "factors": factors,
        "truth": truth
    });
    let dir = temp_dir("schur_each");
    let file = dir.join("loop.json");
    std::fs::write(&file, problem.to_string()).unwrap();
    let file = file.to_str().unwrap();
    let schur = solve_ok(&["solve", file]);
    let text = stdout(&schur);
    assert!(
        text.contains("Schur complement")
            && text.contains("its generated kernel, one factor at a time")
            && text.contains("converged")
            && text.contains("6 cameras: ATE RMSE"),
        "{text}"
    );
    let dual = solve_ok(&["solve", file, "--kernels", "dual"]);
    assert!(
        stdout(&dual).contains("dual numbers, one factor at a time"),
        "{}",
        stdout(&dual)
    );
    let apex = solve_ok(&["solve", file, "--solver", "apex"]);
    let (a, b, c) = (costs(&schur), costs(&dual), costs(&apex));
    assert!(a.1 > 1e-6, "a loop with an inconsistent closure: {}", a.1);
    assert_relative(a.0, c.0, 1e-12, "initial cost");
    assert_relative(a.1, c.1, STOPPING, "final cost");
    assert_relative(b.1, a.1, 1e-10, "dual numbers' final cost");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A generated kernel found stale at the initial values (a debug build's
/// comparison with dual numbers, which a release build like this one does
/// not make) is the factor's error, which the problem file's reader
/// reports at the entry with exit 1, as `eval` does; not a refusal of the
/// problem (exit 2).
#[test]
fn a_stale_kernel_at_the_initial_values_is_the_factors_error() {
    use factor_apex::problems::BuildError;
    use factor_core::FactorError;
    use slamjac_registry::RegistryError;
    use slamjac_registry::problem_assembly::build_error;

    let stale = FactorError::StaleKernel {
        factor: "f",
        kernel: "k",
        detail: "regenerate it".into(),
    };
    let refused = build_error(BuildError::StaleKernel {
        which: "f at the initial values".into(),
        error: stale.clone(),
    });
    assert_eq!(refused, RegistryError::Factor(stale));
}
