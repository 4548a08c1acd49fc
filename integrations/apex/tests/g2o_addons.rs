//! g2o's line graph (`data/g2o-addons/line3d.g2o`, written by g2o's own
//! simulator) solved with g2o's error definitions and with the documents'
//! line factor.
//!
//! References, computed by g2o 2.3 (PyPI `g2opy`, Eigen 3.3) with
//! `bench-peers/g2o/run.sh` (`bench-peers/g2o/README.md`): g2o's χ² of the
//! file, 19 820.29255006952, and what g2o's own Levenberg–Marquardt stops at
//! from it, 13.228768618444994; g2o's χ² of the solution this project
//! reaches (written with `slamjac solve --output` and loaded by the same
//! driver), 13.064024927603548, which g2o's optimizer does not lower further.

use factor_apex::Kernels;
use factor_apex::problems::g2o_addons::{LandmarkFactors, build_with};
use factor_apex::problems::{BuildOptions, Built, FactorChoice, Keys};
use factor_apex::solve::{SolveOptions, Verdict, solve};
use slam_data::G2oGraph;

const G2O_INITIAL_CHI2: f64 = 19_820.292_550_069_52;
const G2O_FINAL_CHI2: f64 = 13.228_768_618_444_994;
const G2O_CHI2_OF_OUR_SOLUTION: f64 = 13.064_024_927_603_548;

fn graph() -> G2oGraph {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/g2o-addons/line3d.g2o");
    slam_data::g2o::read_graph(path).expect("the shipped graph")
}

fn built(graph: &G2oGraph, landmarks: LandmarkFactors) -> Built {
    let options = BuildOptions {
        factors: FactorChoice::Ours(Kernels::Generated),
        robust: None,
        keep_blocks: false,
    };
    build_with(graph, &options, landmarks)
        .expect("builds")
        .map_keys(Keys::G2oAddons)
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The solution of `graph` with `landmarks`' factors, and the problem's cost
/// at its initial values and at the solution.
fn solved(graph: &G2oGraph, landmarks: LandmarkFactors) -> (G2oGraph, f64, f64) {
    let mut problem = built(graph, landmarks);
    let outcome = solve(&mut problem, &SolveOptions::default(), |_| {}).expect("solves");
    let data = slam_data::Problem::G2oAddons(graph.clone());
    let slam_data::Problem::G2oAddons(solution) = problem.write_back(&data, &outcome.values) else {
        panic!("a line and plane graph is written back as one");
    };
    (solution, outcome.initial_cost, outcome.final_cost)
}

/// The cost is g2o's χ² / 2: at the file's values to 1e-5 (the quaternions
/// of the file are unit to 1e-6, apex's are unit), and at the solution
/// below what g2o's optimizer stops at, equal to g2o's χ² of that solution.
#[test]
fn line3d_reaches_g2os_chi2_with_g2os_errors() {
    let (solution, initial, last) = solved(&graph(), LandmarkFactors::G2o);
    let (initial, last) = (2.0 * initial, 2.0 * last);
    println!(
        "line3d.g2o: χ² {initial} → {last}; g2o {G2O_INITIAL_CHI2} → {G2O_FINAL_CHI2}, g2o's \
         χ² of this solution {G2O_CHI2_OF_OUR_SOLUTION}"
    );
    assert!(relative(initial, G2O_INITIAL_CHI2) <= 1e-5, "{initial}");
    assert!(last <= G2O_FINAL_CHI2 * (1.0 + 1e-5), "{last}");
    assert!(relative(last, G2O_CHI2_OF_OUR_SOLUTION) <= 1e-5, "{last}");
    // The written solution costs, rebuilt, what the solve ended at.
    let again = 2.0 * built(&solution, LandmarkFactors::G2o).initial_cost;
    assert!(relative(again, last) <= 1e-9, "{again} vs {last}");
}

/// The documents' line factor (on the inverse of each pose, its
/// information moved into its residual space) reaches the same optimum:
/// its solution costs, by g2o's errors, g2o's χ² of the optimum to 1e-5.
#[test]
fn line3d_with_the_documents_line_factor_reaches_the_same_optimum() {
    let (solution, ..) = solved(&graph(), LandmarkFactors::Documents);
    let chi2 = 2.0 * built(&solution, LandmarkFactors::G2o).initial_cost;
    println!("line3d.g2o, documents' factor: g2o's χ² of its solution {chi2}");
    assert!(relative(chi2, G2O_CHI2_OF_OUR_SOLUTION) <= 1e-5, "{chi2}");
}

/// The documents' plane factor has one pose: a free sensor offset is refused.
#[test]
fn the_documents_plane_factor_needs_a_fixed_offset() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/g2o-addons/plane3d_calib.g2o");
    let graph = slam_data::g2o::read_graph(path).unwrap();
    let options = BuildOptions {
        factors: FactorChoice::Ours(Kernels::Generated),
        robust: None,
        keep_blocks: false,
    };
    let Err(error) = build_with(&graph, &options, LandmarkFactors::Documents) else {
        panic!("a free offset is refused");
    };
    assert!(
        error.to_string().contains("the sensor offset is free"),
        "{error}"
    );
}

/// g2o's χ² of its slam3d graphs (`bench-peers/g2o/simulate.sh`, solved by
/// `bench-peers/g2o/run.sh`): at the file's values and where g2o's own
/// Levenberg–Marquardt stops.
#[allow(clippy::excessive_precision)]
const SLAM3D_G2O: [(&str, f64, f64); 2] = [
    // A planar-motion plane graph: a prior per pose holding its height.
    (
        "plane3d_planar.g2o",
        2_440_171.168_280_751_4,
        27.844_158_923_698_124,
    ),
    // Poses, points seen through a sensor offset, priors through another.
    (
        "points3d_gps.g2o",
        419_603.658_411_456_04,
        1_268.148_676_231_050_6,
    ),
];

/// The graphs with g2o's pose priors and points solve with the defaults,
/// converged, at or below g2o's final χ² (1e-5 relative), from g2o's χ² of
/// the file (1e-5: the file's quaternions are unit to 1e-6, apex's are
/// unit); the solution written back (`--output`) keeps every record and
/// reads again as the same graph.
#[test]
fn graphs_with_priors_and_points_reach_g2os_chi2() {
    for (name, g2o_initial, g2o_final) in SLAM3D_G2O {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../data/g2o-addons")
            .join(name);
        let graph = slam_data::g2o::read_graph(path).unwrap();
        let mut problem = built(&graph, LandmarkFactors::G2o);
        let outcome = solve(&mut problem, &SolveOptions::default(), |_| {}).expect("solves");
        let (initial, last) = (2.0 * outcome.initial_cost, 2.0 * outcome.final_cost);
        println!(
            "{name}: χ² {initial} → {last} in {} iterations ({:?}); g2o {g2o_initial} → \
             {g2o_final}",
            outcome.iterations,
            outcome.verdict()
        );
        assert!(
            matches!(outcome.verdict(), Verdict::Converged(_)),
            "{name}: {:?}",
            outcome.verdict()
        );
        assert!(relative(initial, g2o_initial) <= 1e-5, "{name}: {initial}");
        assert!(last <= g2o_final * (1.0 + 1e-5), "{name}: {last}");
        let data = slam_data::Problem::G2oAddons(graph.clone());
        let slam_data::Problem::G2oAddons(solution) = problem.write_back(&data, &outcome.values)
        else {
            panic!("written back as a g2o graph");
        };
        assert_eq!(solution.priors, graph.priors);
        assert_eq!(solution.point_edges, graph.point_edges);
        assert_eq!(solution.points.len(), graph.points.len());
        let mut text = Vec::new();
        slam_data::g2o::write_graph_to(&solution, &mut text, "out").unwrap();
        let again = slam_data::g2o::graph_from_text(std::str::from_utf8(&text).unwrap(), "out");
        assert_eq!(again.unwrap(), solution);
        let rebuilt = 2.0 * built(&solution, LandmarkFactors::G2o).initial_cost;
        assert!(relative(rebuilt, last) <= 1e-9, "{rebuilt} vs {last}");
    }
}

/// A pose graph with priors and no `FIX`, written here from a known truth:
/// poses on a helix, exact odometry, priors through a rotated and shifted
/// sensor offset measuring the truth exactly (full information on the first
/// pose, g2o's planar-motion semi-definite `diag(0, 0, 1e9, 0, 0, 0)` on
/// the others — the helix is not planar, so they hold each sensor's
/// height), and perturbed initial values. It solves to zero cost at the
/// truth.
#[test]
fn a_pose_graph_with_priors_solves_to_its_truth() {
    use nalgebra::{Isometry3, Matrix6, Translation3, UnitQuaternion, Vector3};
    use slam_data::{Edge, Pose, PriorEdge, Se3Offset, Vertex};
    let truth: Vec<Isometry3<f64>> = (0..12)
        .map(|k| {
            let a = 0.4 * k as f64;
            Isometry3::from_parts(
                Translation3::new(3.0 * a.cos(), 3.0 * a.sin(), 0.2 * k as f64),
                UnitQuaternion::from_euler_angles(0.05 * a, -0.1, a + 1.0),
            )
        })
        .collect();
    let offset = Isometry3::from_parts(
        Translation3::new(0.1, -0.2, 0.5),
        UnitQuaternion::from_euler_angles(0.3, 1.2, -0.7),
    );
    let mut graph = G2oGraph::default();
    graph.offsets.push(Se3Offset {
        id: 7,
        offset: Pose::from(offset),
    });
    for (k, pose) in truth.iter().enumerate() {
        let step = Vector3::new(0.05, -0.03, 0.04) * ((k % 3) as f64 - 1.0);
        let noisy = Isometry3::new(pose.translation.vector + step, pose.rotation.scaled_axis())
            * UnitQuaternion::from_scaled_axis(step * 2.0);
        graph.poses.push(Vertex {
            id: k,
            pose: Pose::from(noisy),
        });
        let mut information = Matrix6::zeros();
        information[(5, 5)] = 1e9; // z, in the reader's [δω, δρ] order
        if k == 0 {
            information = Matrix6::identity() * 100.0;
        }
        graph.priors.push(PriorEdge {
            pose: k,
            offset: 7,
            measurement: Pose::from(pose * offset),
            information,
        });
        if k > 0 {
            graph.pose_edges.push(Edge {
                from: k - 1,
                to: k,
                measurement: Pose::from(truth[k - 1].inverse() * pose),
                information: Matrix6::identity() * 10.0,
            });
        }
    }
    // Through the text: what `slamjac solve` reads.
    let mut text = Vec::new();
    slam_data::g2o::write_graph_to(&graph, &mut text, "helix.g2o").unwrap();
    let graph =
        slam_data::g2o::graph_from_text(std::str::from_utf8(&text).unwrap(), "helix").unwrap();
    let (solution, initial, last) = solved(&graph, LandmarkFactors::G2o);
    println!("helix with priors: cost {initial} → {last}");
    assert!(initial > 1.0, "{initial}");
    assert!(last <= 1e-12, "{last}");
    for (vertex, pose) in solution.poses.iter().zip(&truth) {
        let error = vertex.pose.isometry().inverse() * pose;
        assert!(error.translation.vector.norm() <= 1e-6, "{error}");
        assert!(error.rotation.angle() <= 1e-6, "{error}");
    }
}
