//! The g2o factors' cost on the graphs g2o's own simulators wrote
//! (`data/g2o-addons/`, see its `SOURCES.md`) equals g2o's χ² at the files'
//! values, edge type by edge type.
//!
//! The references are g2o's, computed independently by g2o 2.3 (PyPI
//! `g2opy`) with Eigen 3.3: `bash bench-peers/g2o/run.sh`, which loads each
//! file with `SparseOptimizer::load` and prints `initial_chi2_by_tag` (the
//! sum of `eᵀ Ω e` over the active edges of each tag) before optimising
//! (`bench-peers/g2o/README.md`).

use std::collections::HashMap;

use factor_core::Factor;
use factor_core::geometry::{InfinitePlane, OrthonormalLine};
use factor_core::lie::{Quaternion, Se3, Se3RhoTheta, So3};
#[cfg(feature = "kernels")]
use factor_testing::{GENERATED_TOLERANCE, check_generated};
use nalgebra::{SMatrix, SVector};
use slam_data::{G2oGraph, Pose, Rotation, g2o};
use slam_factors::g2o::{line_landmark, line_observation};
use slam_factors::{G2oLineEdge, G2oPlaneEdge, G2oPointEdge, G2oPriorEdge, G2oSe3Edge};

/// g2o's χ² per edge tag at the files' values (`initial_chi2_by_tag`), as
/// the driver printed them (17 significant digits).
#[allow(clippy::excessive_precision)]
const REFERENCES: [(&str, f64, f64); 3] = [
    // (file, EDGE_SE3:QUAT, EDGE_SE3_LINE3D or EDGE_SE3_PLANE_CALIB)
    ("line3d.g2o", 0.099211678076170096, 19820.193338391444),
    ("plane3d.g2o", 0.038929255237025319, 32527.683822563864),
    (
        "plane3d_calib.g2o",
        0.038929255237025319,
        39632.410094349289,
    ),
];

/// g2o's χ² per edge tag at the files' values of its slam3d graphs (poses
/// with priors, planes or points), as the driver printed them.
#[allow(clippy::excessive_precision)]
const SLAM3D_REFERENCES: [(&str, [(&str, f64); 3]); 2] = [
    (
        "plane3d_planar.g2o",
        [
            ("EDGE_SE3:QUAT", 6.1743412389468475e-05),
            ("EDGE_SE3_PLANE_CALIB", 3572.7024015739771),
            ("EDGE_SE3_PRIOR", 2436598.4658174342),
        ],
    ),
    (
        "points3d_gps.g2o",
        [
            ("EDGE_SE3:QUAT", 8.8573928396316808e-06),
            ("EDGE_SE3_TRACKXYZ", 86804.278711209394),
            ("EDGE_SE3_PRIOR", 332799.37969138921),
        ],
    ),
];

/// Agreement required: the costs are sums of hundreds of terms computed in
/// another order of operations (and the polar factor by another method).
const TOLERANCE: f64 = 1e-10;

fn graph(name: &str) -> G2oGraph {
    let path = format!("{}/../data/g2o-addons/{name}", env!("CARGO_MANIFEST_DIR"));
    g2o::read_graph(path).unwrap()
}

/// A file's pose with its quaternion as written (not normalised).
fn pose(p: &Pose) -> Se3<f64> {
    let Rotation::Quaternion([x, y, z, w]) = p.rotation else {
        panic!("g2o files hold quaternions");
    };
    Se3::new(
        So3::from_quaternion(Quaternion::new(x, y, z, w)),
        p.translation,
    )
}

fn chi2<const N: usize>(e: &SVector<f64, N>, information: &SMatrix<f64, N, N>) -> f64 {
    (e.transpose() * information * e)[0]
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The g2o factors of a graph at the file's values, each with its edge's
/// information matrix.
struct Factors {
    poses: Vec<(G2oSe3Edge, SMatrix<f64, 6, 6>)>,
    lines: Vec<(G2oLineEdge, SMatrix<f64, 4, 4>)>,
    planes: Vec<(G2oPlaneEdge, SMatrix<f64, 3, 3>)>,
    points: Vec<(G2oPointEdge, SMatrix<f64, 3, 3>)>,
    priors: Vec<(G2oPriorEdge, SMatrix<f64, 6, 6>)>,
}

fn factors(graph: &G2oGraph) -> Factors {
    let poses: HashMap<usize, Se3<f64>> =
        graph.poses.iter().map(|v| (v.id, pose(&v.pose))).collect();
    let lines: HashMap<usize, OrthonormalLine<f64>> = graph
        .lines
        .iter()
        .map(|v| (v.id, line_landmark(&v.line).unwrap()))
        .collect();
    let planes: HashMap<usize, InfinitePlane<f64>> = graph
        .planes
        .iter()
        .map(|v| (v.id, InfinitePlane::from_coefficients(&v.plane)))
        .collect();
    let points: HashMap<usize, nalgebra::Vector3<f64>> =
        graph.points.iter().map(|v| (v.id, v.point)).collect();
    let offsets: HashMap<usize, Se3<f64>> = graph
        .offsets
        .iter()
        .map(|p| (p.id, pose(&p.offset)))
        .collect();
    let pose_at = |id: &usize| Se3RhoTheta::new(poses[id]);
    Factors {
        poses: graph
            .pose_edges
            .iter()
            .map(|e| {
                let factor = G2oSe3Edge {
                    measured: pose(&e.measurement),
                    pose_i: pose_at(&e.from),
                    pose_j: pose_at(&e.to),
                };
                (factor, e.information)
            })
            .collect(),
        lines: graph
            .line_edges
            .iter()
            .map(|e| {
                let factor = G2oLineEdge {
                    measured: e.measurement,
                    pose: pose_at(&e.pose),
                    line: lines[&e.line],
                };
                (factor, e.information)
            })
            .collect(),
        planes: graph
            .plane_edges
            .iter()
            .map(|e| {
                let factor = G2oPlaneEdge {
                    measured: e.measurement,
                    pose: pose_at(&e.pose),
                    plane: planes[&e.plane],
                    offset: pose_at(&e.offset),
                };
                (factor, e.information)
            })
            .collect(),
        points: graph
            .point_edges
            .iter()
            .map(|e| {
                let factor = G2oPointEdge {
                    measured: e.measurement,
                    offset: offsets[&e.offset],
                    pose: pose_at(&e.pose),
                    point: points[&e.point],
                };
                (factor, e.information)
            })
            .collect(),
        priors: graph
            .priors
            .iter()
            .map(|e| {
                let factor = G2oPriorEdge {
                    measured: pose(&e.measurement),
                    offset: offsets[&e.offset],
                    pose: pose_at(&e.pose),
                };
                (factor, e.information)
            })
            .collect(),
    }
}

/// `Σ eᵀ Ω e` over the factors.
fn cost<F: Factor, const N: usize>(factors: &[(F, SMatrix<f64, N, N>)]) -> f64 {
    factors
        .iter()
        .map(|(factor, information)| {
            let e = SVector::<f64, N>::from_column_slice(factor.residual_dyn().unwrap().as_slice());
            chi2(&e, information)
        })
        .sum()
}

#[test]
fn costs_at_the_files_values_equal_g2os_chi2() {
    for (name, pose_reference, landmark_reference) in REFERENCES {
        let factors = factors(&graph(name));
        let pose_cost = cost(&factors.poses);
        let landmark_cost = cost(&factors.lines) + cost(&factors.planes);
        println!(
            "{name}: pose edges {pose_cost} (g2o {pose_reference}, {:.1e}), landmark edges \
             {landmark_cost} (g2o {landmark_reference}, {:.1e})",
            relative(pose_cost, pose_reference),
            relative(landmark_cost, landmark_reference)
        );
        assert!(
            relative(pose_cost, pose_reference) <= TOLERANCE,
            "{name}: pose edges {pose_cost} vs g2o's {pose_reference}"
        );
        assert!(
            relative(landmark_cost, landmark_reference) <= TOLERANCE,
            "{name}: landmark edges {landmark_cost} vs g2o's {landmark_reference}"
        );
    }
}

/// The same on the graphs of g2o's slam3d types its simulators wrote:
/// `plane3d_planar.g2o` (`simulator_3d_plane --planar_motion=true`: a prior
/// on every pose, information `diag(0, 0, 1e9, 0, 0, 0)`, through the
/// identity offset) and `points3d_gps.g2o` (g2o's 3D simulator: points
/// seen through one sensor offset, priors through another, both rotated
/// and translated).
#[test]
fn costs_of_points_and_priors_equal_g2os_chi2() {
    for (name, references) in SLAM3D_REFERENCES {
        let factors = factors(&graph(name));
        for (tag, reference) in references {
            let ours = match tag {
                "EDGE_SE3:QUAT" => cost(&factors.poses),
                "EDGE_SE3_PLANE_CALIB" => cost(&factors.planes),
                "EDGE_SE3_TRACKXYZ" => cost(&factors.points),
                "EDGE_SE3_PRIOR" => cost(&factors.priors),
                _ => unreachable!("{tag}"),
            };
            println!(
                "{name}: {tag} {ours} (g2o {reference}, {:.1e})",
                relative(ours, reference)
            );
            assert!(
                relative(ours, reference) <= TOLERANCE,
                "{name}: {tag} {ours} vs g2o's {reference}"
            );
        }
    }
}

/// Every pose edge of the graphs, at the files' values (quaternions off unit
/// by up to 1e-6), linearizes through its generated kernel as through dual
/// numbers, to rounding. (The line and plane edges have no generated
/// kernel.)
#[cfg(feature = "kernels")]
#[test]
fn generated_kernels_match_dual_numbers_on_every_edge() {
    fn check<F: Factor, const N: usize>(factors: &[(F, SMatrix<f64, N, N>)]) -> f64 {
        let mut worst = 0.0_f64;
        for (factor, _) in factors {
            let check = check_generated(factor)
                .unwrap()
                .expect("a generated kernel");
            assert!(
                check.max_error() <= GENERATED_TOLERANCE,
                "{}: {check:?}",
                F::NAME
            );
            worst = worst.max(check.max_error());
        }
        worst
    }
    for (name, ..) in REFERENCES {
        let factors = factors(&graph(name));
        let worst = check(&factors.poses);
        println!("{name}: worst relative error, generated vs dual {worst:.1e}");
    }
}

/// At the simulator's ground truth (`line3d_truth.g2o`: true poses and
/// lines) each residual of `line3d.g2o` is the measurement's noise alone
/// (standard deviations 0.001 and 0.0001). There the documents' line factor,
/// with the edges' information moved into its residual space
/// (`slam_factors::g2o::line_observation`), costs what g2o's error costs, up
/// to terms of relative size `0.65 ν²` (`tests/g2o_documents.rs`): 1e-5 at
/// most for noise of three standard deviations.
#[test]
fn the_documents_line_factor_at_the_truth_costs_what_g2os_does() {
    let (graph, truth) = (graph("line3d.g2o"), graph("line3d_truth.g2o"));
    let mut at_truth = graph.clone();
    at_truth.poses = truth.poses.clone();
    at_truth.lines = truth.lines.clone();
    let lines = factors(&at_truth).lines;
    let g2o_cost = cost(&lines);
    let mut documents_cost = 0.0;
    for (factor, information) in &lines {
        let (observation, mapped) = line_observation(
            &factor.pose.se3(),
            &factor.line,
            &factor.measured,
            information,
        )
        .unwrap();
        documents_cost += chi2(&observation.residual().unwrap(), &mapped);
    }
    let difference = relative(documents_cost, g2o_cost);
    println!(
        "line3d.g2o at the truth: g2o's errors {g2o_cost}, the documents' factor \
         {documents_cost} ({difference:.1e})"
    );
    assert!(difference <= 1e-5, "{difference:e}");
}
