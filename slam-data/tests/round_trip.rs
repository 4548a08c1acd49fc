//! read → write → read gives the same problem, bit for bit, on every
//! shipped file; conversions between pose-graph dialects keep rotations.

use crate::common;

use common::{SINGLE_FILES, data};
use slam_data::{Format, Problem, VoFiles, bal, bundler, edge3, g2o, kitti_vo};

#[test]
fn every_shipped_file_round_trips_exactly_through_text() {
    let bal = bal::read(data("dubrovnik-3-7-pre.txt")).unwrap();
    let mut out = Vec::new();
    bal::write_to(&bal, &mut out, "out").unwrap();
    assert_eq!(
        bal::from_text(std::str::from_utf8(&out).unwrap(), "out").unwrap(),
        bal
    );

    let bundler = bundler::read(data("Balbianello.out")).unwrap();
    let mut out = Vec::new();
    bundler::write_to(&bundler, &mut out, "out").unwrap();
    assert_eq!(
        bundler::from_text(std::str::from_utf8(&out).unwrap(), "out").unwrap(),
        bundler
    );

    let graph = g2o::read(data("pose3example.txt")).unwrap();
    let mut out = Vec::new();
    g2o::write_to(&graph, &mut out, "out").unwrap();
    assert_eq!(
        g2o::from_text(std::str::from_utf8(&out).unwrap(), "out").unwrap(),
        graph
    );

    let graph = edge3::read(data("sphere2500.txt")).unwrap();
    let mut out = Vec::new();
    edge3::write_to(&graph, &mut out, "out").unwrap();
    assert_eq!(
        edge3::from_text(std::str::from_utf8(&out).unwrap(), "out").unwrap(),
        graph
    );

    let vo =
        kitti_vo::read(&VoFiles::beside(&data("VO_stereo_factors_large.txt")).unwrap()).unwrap();
    let (mut calibration, mut poses, mut factors) = (Vec::new(), Vec::new(), Vec::new());
    kitti_vo::write_to(
        &vo,
        (&mut calibration, "c"),
        (&mut poses, "p"),
        (&mut factors, "f"),
    )
    .unwrap();
    let text = |bytes: &[u8]| String::from_utf8(bytes.to_vec()).unwrap();
    let again = kitti_vo::from_texts(
        (&text(&calibration), "c"),
        (&text(&poses), "p"),
        (&text(&factors), "f"),
    )
    .unwrap();
    assert_eq!(again, vo);
}

#[test]
fn every_shipped_file_round_trips_exactly_through_files() {
    let folder = tempfile::tempdir().unwrap();
    let mut files: Vec<&str> = SINGLE_FILES.iter().map(|(name, _)| *name).collect();
    files.push("VO_stereo_factors_large.txt");
    for name in files {
        let problem = Problem::read(data(name), None).unwrap();
        let written = folder.path().join(name);
        problem.write(&written).unwrap();
        let again = Problem::read(&written, None).unwrap();
        assert_eq!(again, problem, "{name}");
    }
    // The VO set was written as three files.
    let vo_files = VoFiles::beside(&folder.path().join("VO_stereo_factors_large.txt")).unwrap();
    assert!(
        vo_files.calibration.ends_with("VO_calibration_large.txt") && vo_files.calibration.exists()
    );
    assert!(vo_files.poses.exists());
}

#[test]
fn problems_read_back_in_the_format_given() {
    for (name, format) in SINGLE_FILES {
        let format: Format = format.parse().unwrap();
        let problem = Problem::read(data(name), Some(format)).unwrap();
        assert_eq!(problem.format(), format);
    }
}

/// Largest difference between the rotation matrices of two graphs' edges.
fn rotation_difference(a: &slam_data::PoseGraph, b: &slam_data::PoseGraph) -> f64 {
    a.edges
        .iter()
        .zip(&b.edges)
        .map(|(x, y)| {
            let rx = x
                .measurement
                .rotation
                .unit_quaternion()
                .to_rotation_matrix();
            let ry = y
                .measurement
                .rotation
                .unit_quaternion()
                .to_rotation_matrix();
            (rx.into_inner() - ry.into_inner()).amax()
        })
        .fold(0.0, f64::max)
}

#[test]
fn pose_graphs_convert_between_dialects_keeping_rotations_and_information() {
    let sphere = edge3::read(data("sphere2500.txt")).unwrap();
    let mut out = Vec::new();
    g2o::write_to(&sphere, &mut out, "sphere.g2o").unwrap();
    let as_g2o = g2o::from_text(std::str::from_utf8(&out).unwrap(), "sphere.g2o").unwrap();
    assert!(rotation_difference(&sphere, &as_g2o) < 1e-15);
    for (x, y) in sphere.edges.iter().zip(&as_g2o.edges) {
        assert_eq!((x.from, x.to, x.information), (y.from, y.to, y.information));
        assert_eq!(x.measurement.translation, y.measurement.translation);
    }

    let example = g2o::read(data("pose3example.txt")).unwrap();
    let mut out = Vec::new();
    edge3::write_to(&example, &mut out, "example.edge3").unwrap();
    let as_edge3 = edge3::from_text(std::str::from_utf8(&out).unwrap(), "example.edge3").unwrap();
    assert!(rotation_difference(&example, &as_edge3) < 1e-15);
    assert_eq!(example.vertices.len(), as_edge3.vertices.len());
}

/// g2o's line and plane graphs (and their ground truth) read → write → read
/// exactly, through text and through files; a pose graph read as a line and
/// plane graph is the same pose graph.
#[test]
fn g2o_line_and_plane_graphs_round_trip_exactly() {
    let folder = tempfile::tempdir().unwrap();
    for name in [
        "line3d.g2o",
        "line3d_truth.g2o",
        "plane3d.g2o",
        "plane3d_calib.g2o",
        "plane3d_truth.g2o",
    ] {
        let graph = g2o::read_graph(data(&format!("g2o-addons/{name}"))).unwrap();
        let mut out = Vec::new();
        g2o::write_graph_to(&graph, &mut out, "out").unwrap();
        let again = g2o::graph_from_text(std::str::from_utf8(&out).unwrap(), "out").unwrap();
        assert_eq!(again, graph, "{name}");
        let path = folder.path().join(name);
        g2o::write_graph(&graph, &path).unwrap();
        assert_eq!(g2o::read_graph(&path).unwrap(), graph, "{name}");
    }
    let lines = g2o::read_graph(data("g2o-addons/line3d.g2o")).unwrap();
    assert_eq!(
        (lines.offsets.len(), lines.poses.len(), lines.lines.len()),
        (1, 161, 3)
    );
    assert_eq!((lines.pose_edges.len(), lines.line_edges.len()), (160, 480));
    assert_eq!(lines.fixed, [4]);
    let planes = g2o::read_graph(data("g2o-addons/plane3d.g2o")).unwrap();
    assert_eq!((planes.poses.len(), planes.planes.len()), (162, 3));
    assert_eq!(planes.plane_edges.len(), 480);
    assert_eq!(planes.fixed, [0, 4]);

    let pose_graph = g2o::read(data("pose3example.txt")).unwrap();
    let as_graph = g2o::read_graph(data("pose3example.txt")).unwrap();
    assert_eq!(as_graph.pose_graph(), pose_graph);
}
