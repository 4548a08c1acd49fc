//! Hostile and broken input: each gets a one-line error at its line, never
//! a panic, a hang or an allocation sized by a claimed count.

use crate::common;

use std::fmt::Debug;

use common::data;
use nalgebra::{Vector2, Vector3};
use slam_data::{
    BalProblem, Error, MAX_FILE_BYTES, Observation, Problem, bal, bundler, edge3, g2o, kitti_vo,
};

/// Asserts `result` failed at `line` of `file` with a message containing `what`.
fn assert_error<T: Debug>(result: Result<T, Error>, file: &str, line: usize, what: &str) {
    let message = result.expect_err("input accepted").to_string();
    let prefix = format!("{file}:{line}: ");
    assert!(
        message.starts_with(&prefix),
        "expected `{prefix}…`, got `{message}`"
    );
    assert!(message.contains(what), "expected `{what}` in `{message}`");
    assert!(!message.contains('\n'), "more than one line: {message:?}");
}

fn text(name: &str) -> String {
    std::fs::read_to_string(data(name)).unwrap()
}

/// The text with line `number` (1-based) replaced.
fn with_line(text: &str, number: usize, line: &str) -> String {
    let mut lines: Vec<&str> = text.lines().collect();
    lines[number - 1] = line;
    lines.join("\n") + "\n"
}

#[test]
fn a_header_claiming_absurd_counts_reads_what_is_there_and_stops() {
    let claimed = "3 7 1000000000000000000\n0 0 1.5 2.5\n";
    assert_error(
        bal::from_text(claimed, "huge.txt"),
        "huge.txt",
        2,
        "observation 2 of 1000000000000000000: the file ends before the camera index",
    );
    let claimed = "# Bundle file v0.3\n1000000000000000000 5\n";
    assert_error(
        bundler::from_text(claimed, "huge.out"),
        "huge.out",
        2,
        "camera 1 of 1000000000000000000: the file ends before the focal length",
    );
    let too_large = "3 7 100000000000000000000\n";
    assert_error(
        bal::from_text(too_large, "big.txt"),
        "big.txt",
        1,
        "`100000000000000000000` is too large",
    );
}

#[test]
fn counts_that_disagree_with_the_body_are_errors_where_they_show() {
    let dubrovnik = text("dubrovnik-3-7-pre.txt");
    // One observation more than there are: the first camera value is read as a camera index.
    let more = with_line(&dubrovnik, 1, "3 7 20");
    assert_error(
        bal::from_text(&more, "more.txt"),
        "more.txt",
        23,
        "observation 20 of 20: the camera index: expected a non-negative integer, found `-1.6943983532198115e-02`",
    );
    // One fewer: everything after is read four tokens early, and the third
    // camera's focal length lands on a negative number.
    let fewer = with_line(&dubrovnik, 1, "3 7 18");
    assert_error(
        bal::from_text(&fewer, "fewer.txt"),
        "fewer.txt",
        35,
        "camera 2 of 3: focal length must be positive, found -0.29278402790141456",
    );
    // One point fewer: observations of point 6 are out of range.
    let fewer = with_line(&dubrovnik, 1, "3 6 19");
    assert_error(
        bal::from_text(&fewer, "fewer.txt"),
        "fewer.txt",
        19,
        "observation 17 of 19: the point index 6 is out of range (there are 6 points)",
    );
    // Content after the last point.
    let longer = format!("{dubrovnik}4.5\n");
    assert_error(
        bal::from_text(&longer, "longer.txt"),
        "longer.txt",
        81,
        "unexpected `4.5` after the last point (the header's counts disagree with the body)",
    );
    let balbianello = text("Balbianello.out");
    let fewer_points = with_line(&balbianello, 2, "5 543");
    assert_error(
        bundler::from_text(&fewer_points, "b.out"),
        "b.out",
        1657,
        "after the last point",
    );
    // A point claiming one view more than its line has: the next point's position is read as a view.
    let views = with_line(
        &balbianello,
        30,
        "4 0 27 45.2700 -38.3700 3 20 0.5500 -13.8100 1 17 48.3800 -57.5500",
    );
    assert_error(
        bundler::from_text(&views, "v.out"),
        "v.out",
        31,
        "point 1 of 544: view 4 of 4: the camera index: expected a non-negative integer, found `-2.2635283095e-01`",
    );
}

#[test]
fn non_finite_and_out_of_range_numbers_are_rejected() {
    let dubrovnik = text("dubrovnik-3-7-pre.txt");
    for (token, what) in [
        ("nan", "expected a finite number, found `nan`"),
        ("inf", "expected a finite number, found `inf`"),
        ("1e999", "`1e999` is out of range (magnitude over 1e100)"),
        ("-2e100", "`-2e100` is out of range (magnitude over 1e100)"),
        ("0x1p3", "expected a number, found `0x1p3`"),
    ] {
        let broken = with_line(&dubrovnik, 3, &format!("0 0 {token} 3.871200e+02"));
        assert_error(bal::from_text(&broken, "n.txt"), "n.txt", 3, what);
    }
    let negative_focal = with_line(&dubrovnik, 29, "-1.4300319432711681e+03");
    assert_error(
        bal::from_text(&negative_focal, "f.txt"),
        "f.txt",
        29,
        "camera 1 of 3: focal length must be positive",
    );
    let sphere = text("sphere2500.txt");
    let broken = with_line(
        &sphere,
        7,
        "EDGE3 6 7 0.259333 -0.220076 -0.122115 NaN 0.0181515 0.151092 10 0 0 0 0 0 10 0 0 0 0 10 0 0 0 100 0 0 100 0 25",
    );
    assert_error(
        edge3::from_text(&broken, "s.txt"),
        "s.txt",
        7,
        "expected a finite number, found `NaN`",
    );
    let negative_id = with_line(
        &sphere,
        2,
        "EDGE3 -1 2 0 0 0 0 0 0 10 0 0 0 0 0 10 0 0 0 0 10 0 0 0 100 0 0 100 0 25",
    );
    assert_error(
        edge3::from_text(&negative_id, "s.txt"),
        "s.txt",
        2,
        "the first pose id: expected a non-negative integer, found `-1`",
    );
}

#[test]
fn indices_out_of_range_are_rejected() {
    let dubrovnik = text("dubrovnik-3-7-pre.txt");
    let broken = with_line(&dubrovnik, 5, "3 0     -6.679200e+02 1.231100e+02");
    assert_error(
        bal::from_text(&broken, "i.txt"),
        "i.txt",
        5,
        "observation 3 of 19: the camera index 3 is out of range (there are 3 cameras)",
    );
    let broken = with_line(&dubrovnik, 5, "2 7     -6.679200e+02 1.231100e+02");
    assert_error(
        bal::from_text(&broken, "i.txt"),
        "i.txt",
        5,
        "the point index 7 is out of range (there are 7 points)",
    );
    let balbianello = text("Balbianello.out");
    let broken = with_line(
        &balbianello,
        30,
        "3 5 27 45.2700 -38.3700 3 20 0.5500 -13.8100 1 17 48.3800 -57.5500",
    );
    assert_error(
        bundler::from_text(&broken, "i.out"),
        "i.out",
        30,
        "the camera index 5 is out of range (there are 5 cameras)",
    );
}

#[test]
fn pose_graph_structure_is_checked() {
    let example = text("pose3example.txt");
    let duplicate = with_line(
        &example,
        3,
        "VERTEX_SE3:QUAT 1 1.993500 0.023275 0.003793 -0.351729 -0.597838 0.584174 0.421446",
    );
    assert_error(
        g2o::from_text(&duplicate, "d.txt"),
        "d.txt",
        3,
        "vertex id 1 defined again (first as vertex 2 of 5)",
    );
    let dangling = with_line(
        &example,
        10,
        "EDGE_SE3:QUAT 1 9   -0.577841 0.628016 -0.543592   -0.125250 -0.534379 0.769122 0.327419   10000 0 0 0 0 0 10000 0 0 0 0 10000 0 0 0 10000 0 0 10000 0 10000",
    );
    assert_error(
        g2o::from_text(&dangling, "d.txt"),
        "d.txt",
        10,
        "pose 9 is not a vertex",
    );
    let self_loop = with_line(
        &example,
        10,
        "EDGE_SE3:QUAT 4 4   -0.577841 0.628016 -0.543592   -0.125250 -0.534379 0.769122 0.327419   10000 0 0 0 0 0 10000 0 0 0 0 10000 0 0 0 10000 0 0 10000 0 10000",
    );
    assert_error(
        g2o::from_text(&self_loop, "d.txt"),
        "d.txt",
        10,
        "edge from pose 4 to itself",
    );
    let unknown = with_line(&example, 2, "VERTEX_SE2 1 1.0 2.0 0.5");
    assert_error(
        g2o::from_text(&unknown, "u.txt"),
        "u.txt",
        2,
        "unsupported tag `VERTEX_SE2` (a g2o file has VERTEX_SE3:QUAT and EDGE_SE3:QUAT lines)",
    );
    let mixed = with_line(
        &example,
        2,
        "EDGE3 0 1 0 0 0 0 0 0 10 0 0 0 0 0 10 0 0 0 0 10 0 0 0 100 0 0 100 0 25",
    );
    assert_error(
        g2o::from_text(&mixed, "m.txt"),
        "m.txt",
        2,
        "EDGE3 is a line of the edge3 format, not g2o: read the file as edge3",
    );
    let short = with_line(
        &example,
        6,
        "EDGE_SE3:QUAT 0 1   1.001367 0.015390 0.004948   0.190253 0.283162 -0.392318 0.854230   10000 0 0",
    );
    assert_error(
        g2o::from_text(&short, "s.txt"),
        "s.txt",
        6,
        "line ends before an information entry (21 expected)",
    );
    let long = with_line(&example, 1, "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1 7");
    assert_error(
        g2o::from_text(&long, "l.txt"),
        "l.txt",
        1,
        "unexpected extra field `7`",
    );
}

#[test]
fn rotations_quaternions_and_information_are_checked_with_their_tolerances() {
    let balbianello = text("Balbianello.out");
    // Camera 0's first rotation row scaled by 1.001.
    let scaled = with_line(
        &balbianello,
        4,
        "1.0007271e+00 5.9814420798e-03 2.2592968394e-02",
    );
    assert_error(
        bundler::from_text(&scaled, "r.out"),
        "r.out",
        7,
        "camera 1 of 5: not a rotation matrix: max |RᵀR − I| = 2.000e-3",
    );
    // A reflection: the third row negated.
    let reflected = with_line(
        &balbianello,
        6,
        "2.2481435001e-02 1.4558592624e-02 -9.9964125188e-01",
    );
    assert_error(
        bundler::from_text(&reflected, "r.out"),
        "r.out",
        7,
        "det R = -1.000000",
    );
    // Within 1e-5 is accepted (the text of six significant digits is 1e-6 off).
    let example = text("pose3example.txt");
    let near = with_line(
        &example,
        2,
        "VERTEX_SE3:QUAT 1 1.001367 0.015390 0.004948 0.190254 0.283163 -0.392319 0.854232",
    );
    assert!(g2o::from_text(&near, "q.txt").is_ok());
    let far = with_line(
        &example,
        2,
        "VERTEX_SE3:QUAT 1 1.001367 0.015390 0.004948 0.190253 0.283162 -0.392318 0.85",
    );
    assert_error(
        g2o::from_text(&far, "q.txt"),
        "q.txt",
        2,
        "not a unit quaternion: norm 0.996",
    );
    let zero = with_line(
        &example,
        2,
        "VERTEX_SE3:QUAT 1 1.001367 0.015390 0.004948 0 0 0 0",
    );
    assert_error(
        g2o::from_text(&zero, "q.txt"),
        "q.txt",
        2,
        "not a unit quaternion: norm 0.000000000",
    );
    let sphere = text("sphere2500.txt");
    let indefinite = with_line(
        &sphere,
        3,
        "EDGE3 2 3 0.134845 -0.100952 -0.235999 -0.00238046 -0.00487134 0.120841 10 0 0 0 0 0 10 0 0 0 0 10 0 0 0 100 0 0 100 0 -25",
    );
    assert_error(
        edge3::from_text(&indefinite, "i.txt"),
        "i.txt",
        3,
        "information matrix is not positive definite",
    );
    let singular = with_line(
        &sphere,
        3,
        "EDGE3 2 3 0.134845 -0.100952 -0.235999 -0.00238046 -0.00487134 0.120841 10 0 0 0 0 0 10 0 0 0 0 10 0 0 0 100 0 0 100 0 0",
    );
    assert_error(
        edge3::from_text(&singular, "i.txt"),
        "i.txt",
        3,
        "information matrix is not positive definite",
    );
}

#[test]
fn truncated_files_are_errors_at_their_end() {
    let dubrovnik = text("dubrovnik-3-7-pre.txt");
    let cut = &dubrovnik[..dubrovnik.find("7.3030995682610689e-01").unwrap()];
    assert_error(
        bal::from_text(cut, "cut.txt"),
        "cut.txt",
        25,
        "camera 1 of 3: the file ends before a translation component",
    );
    let balbianello = text("Balbianello.out");
    let cut = &balbianello[..balbianello.len() / 2];
    let lines = cut.lines().count();
    let result = bundler::from_text(cut, "cut.out");
    assert_error(result, "cut.out", lines, "the file ends before");
    // Cut inside a record: a line-based file reports the short line.
    let sphere = text("sphere2500.txt");
    let line_3 = sphere.find("EDGE3 2 3").unwrap();
    let cut = &sphere[..line_3 + sphere[line_3..].find(" 10 0").unwrap()];
    assert_error(
        edge3::from_text(cut, "cut.txt"),
        "cut.txt",
        3,
        "line ends before",
    );
    for (name, empty) in [("e.txt", ""), ("e.txt", "\n\n  \n")] {
        assert_error(
            bal::from_text(empty, name),
            name,
            1.max(empty.lines().count()),
            "the file ends before the number of cameras",
        );
    }
    assert_error(
        bundler::from_text("", "e.out"),
        "e.out",
        1,
        "not a Bundler v0.3 file: the first line must be `# Bundle file v0.3`",
    );
}

#[test]
fn non_utf8_bytes_are_errors_at_their_line() {
    let mut bytes = text("sphere2500.txt").into_bytes();
    let line_4 = bytes
        .iter()
        .enumerate()
        .filter(|(_, b)| **b == b'\n')
        .nth(2)
        .unwrap()
        .0
        + 1;
    bytes[line_4 + 10] = 0xff;
    assert_error(
        edge3::read_from(&bytes[..], "bytes.txt"),
        "bytes.txt",
        4,
        "not UTF-8 text (invalid byte at column 11)",
    );
    let mut bytes = text("dubrovnik-3-7-pre.txt").into_bytes();
    bytes.splice(0..0, [0xc3, 0x28]);
    assert_error(
        bal::read_from(&bytes[..], "b.txt"),
        "b.txt",
        1,
        "not UTF-8 text",
    );
}

#[test]
fn files_over_the_size_cap_are_rejected_before_reading() {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("sparse.txt");
    let file = std::fs::File::create(&path).unwrap();
    file.set_len(MAX_FILE_BYTES + 1).unwrap(); // sparse: no data written
    let message = bal::read(&path).unwrap_err().to_string();
    let expected = format!(
        "{}: 4294967297 bytes is over the cap of 4294967296 bytes (4 GiB)",
        path.display()
    );
    assert_eq!(message, expected);
    let missing = folder.path().join("missing.txt");
    let message = Problem::read(&missing, Some(slam_data::Format::G2o))
        .unwrap_err()
        .to_string();
    assert!(
        message.starts_with(&format!("{}: cannot open: ", missing.display())),
        "{message}"
    );
}

#[test]
fn lines_over_the_line_cap_are_rejected() {
    let long = format!("3 7 19\n{}\n", "0".repeat(slam_data::MAX_LINE_BYTES + 1));
    assert_error(
        bal::from_text(&long, "long.txt"),
        "long.txt",
        2,
        "line longer than the cap of 67108864 bytes",
    );
}

#[test]
fn bundler_specific_defects() {
    let balbianello = text("Balbianello.out");
    let header = with_line(&balbianello, 1, "# Bundle file v0.4");
    assert_error(
        bundler::from_text(&header, "h.out"),
        "h.out",
        1,
        "the first line must be `# Bundle file v0.3`",
    );
    let colour = with_line(&balbianello, 29, "70 256 54");
    assert_error(
        bundler::from_text(&colour, "c.out"),
        "c.out",
        29,
        "point 1 of 544: colour channel 256 is over 255",
    );
    let mut unreconstructed = balbianello.clone();
    for line in 3..=7 {
        unreconstructed = with_line(&unreconstructed, line, "0 0 0");
    }
    assert_error(
        bundler::from_text(&unreconstructed, "z.out"),
        "z.out",
        7,
        "camera 1 of 5: not reconstructed (all zeros): not supported",
    );
}

#[test]
fn kitti_vo_specific_defects() {
    let calibration = text("VO_calibration.txt");
    let poses = text("VO_camera_poses_large.txt");
    let factors = text("VO_stereo_factors_large.txt");
    let read =
        |c: &str, p: &str, f: &str| kitti_vo::from_texts((c, "c.txt"), (p, "p.txt"), (f, "f.txt"));

    assert_error(
        read("721.5 721.5 0 609.5 172.8", &poses, &factors),
        "c.txt",
        1,
        "line ends before the baseline",
    );
    assert_error(
        read("721.5 721.5 0 609.5 172.8 -0.5", &poses, &factors),
        "c.txt",
        1,
        "baseline must be positive",
    );
    assert_error(
        read(&format!("{calibration}\n1 2 3 4 5 6\n"), &poses, &factors),
        "c.txt",
        2,
        "a calibration file has one line",
    );

    let unknown_pose = with_line(
        &factors,
        5,
        "27 7 394.391 382.151 5.65911 -9.4424 -7.33715 31.6638",
    );
    assert_error(
        read(&calibration, &poses, &unknown_pose),
        "f.txt",
        5,
        "pose 27 is not in the poses file",
    );
    let behind = with_line(
        &factors,
        5,
        "2 7 394.391 382.151 5.65911 -9.4424 -7.33715 -31.6638",
    );
    assert_error(
        read(&calibration, &poses, &behind),
        "f.txt",
        5,
        "the landmark must be in front of the camera, Z > 0",
    );

    let duplicate = with_line(&poses, 3, "2 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1");
    assert_error(
        read(&calibration, &duplicate, &factors),
        "p.txt",
        3,
        "pose 2 defined again (first at line 2)",
    );
    let last_row = with_line(&poses, 1, "1 1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1");
    assert_error(
        read(&calibration, &last_row, &factors),
        "p.txt",
        1,
        "the last row of the pose matrix must be 0 0 0 1",
    );
    let sheared = with_line(&poses, 1, "1 1 0.01 0 0 0 1 0 0 0 0 1 0 0 0 0 1");
    assert_error(
        read(&calibration, &sheared, &factors),
        "p.txt",
        1,
        "not a rotation matrix",
    );
    let short = with_line(&poses, 1, "1 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0");
    assert_error(
        read(&calibration, &short, &factors),
        "p.txt",
        1,
        "line ends before a pose matrix entry (16 expected)",
    );
}

#[test]
fn writers_refuse_problems_a_reader_would_reject() {
    let mut problem = BalProblem {
        cameras: bal::read(data("dubrovnik-3-7-pre.txt")).unwrap().cameras,
        points: vec![Vector3::new(1.0, 2.0, -3.0)],
        observations: vec![Observation {
            camera: 0,
            point: 1,
            pixel: Vector2::new(1.0, 2.0),
        }],
    };
    let mut out = Vec::new();
    let message = bal::write_to(&problem, &mut out, "o.txt")
        .unwrap_err()
        .to_string();
    assert_eq!(
        message,
        "o.txt: observation 1 of 1: camera index 0 or point index 1 out of range (3 cameras, 1 points)"
    );
    problem.observations[0].point = 0;
    problem.points[0].y = f64::NAN;
    let message = bal::write_to(&problem, &mut out, "o.txt")
        .unwrap_err()
        .to_string();
    assert_eq!(
        message,
        "o.txt: point 1 of 1: non-finite or too large coordinate"
    );
    assert!(out.is_empty(), "nothing is written");

    let mut graph = g2o::read(data("pose3example.txt")).unwrap();
    graph.edges[2].information[(0, 0)] = -1.0;
    let message = g2o::write_to(&graph, &mut out, "g.g2o")
        .unwrap_err()
        .to_string();
    assert_eq!(
        message,
        "g.g2o: edge 3 of 6: information matrix is not positive definite"
    );
}

#[test]
fn file_names_with_control_characters_stay_on_one_line() {
    let message = bal::from_text("x", "bad\nname").unwrap_err().to_string();
    assert_eq!(
        message,
        "bad\\nname:1: the number of cameras: expected a non-negative integer, found `x`"
    );
}

#[test]
fn g2o_line_graph_defects() {
    let lines = text("g2o-addons/line3d.g2o");
    let read = |text: &str| g2o::graph_from_text(text, "l.g2o");
    let cases = [
        (
            167,
            "EDGE_SE3_XYZ_PRIOR 5 0 0 0 0 1 0 0 1 0 1",
            "unsupported tag `EDGE_SE3_XYZ_PRIOR` (a g2o graph of lines, planes and points has \
             PARAMS_SE3OFFSET, VERTEX_SE3:QUAT, VERTEX_LINE3D, VERTEX_PLANE, VERTEX_TRACKXYZ, \
             EDGE_SE3:QUAT, EDGE_SE3_LINE3D, EDGE_SE3_PLANE_CALIB, EDGE_SE3_TRACKXYZ, \
             EDGE_SE3_PRIOR, FIX lines)",
        ),
        (
            167,
            "EDGE_SE3_LINE3D 5 1 7 2.25395 -4.45322 0.229167 -0.886898 -0.453441 -0.0883408 1000 0 0 0 1000 0 0 1000 0 10000",
            "parameter 7 is not defined",
        ),
        (
            167,
            "EDGE_SE3_LINE3D 5 6 0 2.25395 -4.45322 0.229167 -0.886898 -0.453441 -0.0883408 1000 0 0 0 1000 0 0 1000 0 10000",
            "vertex 6 is a VERTEX_SE3:QUAT, not a VERTEX_LINE3D",
        ),
        (
            167,
            "EDGE_SE3_LINE3D 5 1 0 2.25395 -4.45322 0.229167 0 0 0 1000 0 0 0 1000 0 0 1000 0 10000",
            "measurement: the line direction d is zero",
        ),
        (
            167,
            "EDGE_SE3_LINE3D 5 1 0 2.25395 -4.45322 0.229167 -0.886898 -0.453441 -0.0883408 1000 0 0 0 1000 0 0 1000 0",
            "line ends before an information entry (10 expected)",
        ),
        (
            167,
            "EDGE_SE3_LINE3D 5 1 0 2.25395 -4.45322 0.229167 -0.886898 -0.453441 -0.0883408 1000 0 0 0 1000 0 0 1000 0 -1",
            "information matrix is not positive definite",
        ),
        (
            2,
            "VERTEX_LINE3D 1 -5 0 0 0 0 0",
            "the line direction d is zero",
        ),
        (
            2,
            "VERTEX_LINE3D 1 -5 0 0 0.3 1 0",
            "not a Plücker line: the moment w and the direction d must be perpendicular (w · d \
             = 0), their cosine is -0.287348",
        ),
        (
            2,
            "VERTEX_LINE3D 1 -5 0 0 -1 0 0",
            "not a Plücker line: the moment w and the direction d must be perpendicular (w · d \
             = 0), their cosine is 1.000000",
        ),
        (
            167,
            "EDGE_SE3_LINE3D 5 1 0 2.25395 -4.45322 0.229167 0.886898 -0.453441 -0.0883408 1000 0 0 0 1000 0 0 1000 0 10000",
            "measurement: not a Plücker line",
        ),
        (
            2,
            "VERTEX_LINE3D 1 -5 0 0 0 1e-100 0",
            "the line is 5.0e100 from the origin (|w| / |d|), beyond the range of coordinates (at \
             most 1e100)",
        ),
        (
            2,
            "VERTEX_LINE3D 1 -5 0 0 0 1e-300 0",
            "the line is 5.0e300 from the origin",
        ),
        (
            2,
            "VERTEX_LINE3D 1 -5 0 nan 0 1 0",
            "expected a finite number, found `nan`",
        ),
        (
            2,
            "VERTEX_LINE3D 5 -5 0 0 0 1 0",
            "vertex id 5 defined again (first as a VERTEX_SE3:QUAT)",
        ),
        (806, "FIX 999", "fixed vertex 999 is not defined"),
        (806, "FIX", "FIX without a vertex id"),
        (806, "FIX 4 4", "vertex 4 is fixed twice"),
        (
            806,
            "FIX 4 -1",
            "a fixed vertex id: expected a non-negative integer, found `-1`",
        ),
        (
            1,
            "PARAMS_SE3OFFSET 0 0 0 0 0 0 0 2",
            "not a unit quaternion: norm 2.000000000",
        ),
        (
            166,
            "EDGE_SE3:QUAT 4 1 -0.0336686 -0.00756961 0.00344749 -0.00751927 0.0505648 0.16177 0.985503 10 0 0 0 0 0 200 0 0 0 0 1e+09 0 0 0 1000 0 0 1000 0 20",
            "vertex 1 is a VERTEX_LINE3D, not a VERTEX_SE3:QUAT",
        ),
        (
            166,
            "EDGE3 4 5 0 0 0 0 0 0 10 0 0 0 0 0 10 0 0 0 0 10 0 0 0 100 0 0 100 0 25",
            "EDGE3 is a line of the edge3 format, not g2o: read the file as edge3",
        ),
    ];
    for (line, replacement, what) in cases {
        assert_error(
            read(&with_line(&lines, line, replacement)),
            "l.g2o",
            line,
            what,
        );
    }
    // A second parameter with the same id, at its line.
    let twice = format!("PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1\n{lines}");
    assert_error(read(&twice), "l.g2o", 2, "parameter id 0 defined again");
}

#[test]
fn g2o_plane_graph_defects() {
    let planes = text("g2o-addons/plane3d.g2o");
    let read = |text: &str| g2o::graph_from_text(text, "p.g2o");
    let edge = |head: &str, info: &str| {
        format!("EDGE_SE3_PLANE_CALIB {head} 0.00900996 -0.995844 -0.0906258 6.15712 {info}")
    };
    let info = "33.3333 0 0 33.3333 0 200";
    let cases = [
        (
            edge("2 5 1", info),
            "EDGE_SE3_PLANE_CALIB joins 3 vertices (robot pose, plane, sensor offset), not 2",
        ),
        (
            edge("3 5 6 0", info),
            "vertex 6 is a VERTEX_SE3:QUAT, not a VERTEX_PLANE",
        ),
        (
            edge("3 5 1 2", info),
            "vertex 2 is a VERTEX_PLANE, not a VERTEX_SE3:QUAT",
        ),
        (
            edge("3 5 1 5", info),
            "the robot pose and the sensor offset are the same vertex 5",
        ),
        (edge("3 5 1 999", info), "vertex 999 is not defined"),
        (
            edge("3 5 1 0", "33.3333 0 0 33.3333 0 0"),
            "information matrix is not positive definite",
        ),
        (
            edge("3 5 1 0", "33.3333 40 0 33.3333 0 200"),
            "information matrix is not positive definite",
        ),
        (
            "EDGE_SE3_PLANE_CALIB 3 5 1 0 0 0 0 6.15712 33.3333 0 0 33.3333 0 200".into(),
            "measurement: the plane normal n is zero",
        ),
    ];
    for (replacement, what) in cases {
        assert_error(
            read(&with_line(&planes, 168, &replacement)),
            "p.g2o",
            168,
            what,
        );
    }
    assert_error(
        read(&with_line(&planes, 3, "VERTEX_PLANE 1 0 0 0 5")),
        "p.g2o",
        3,
        "the plane normal n is zero",
    );
    assert_error(
        read(&with_line(&planes, 3, "VERTEX_PLANE 1 0 0 1")),
        "p.g2o",
        3,
        "line ends before a plane coefficient (nx ny nz d)",
    );
    assert_error(
        read(&with_line(&planes, 3, "VERTEX_PLANE 1 0 0 1 5 6")),
        "p.g2o",
        3,
        "unexpected extra field `6`",
    );
}

#[test]
fn g2o_graph_writer_refuses_what_its_reader_rejects() {
    let mut graph = g2o::read_graph(data("g2o-addons/plane3d.g2o")).unwrap();
    graph.plane_edges[3].offset = graph.plane_edges[3].pose;
    let mut out = Vec::new();
    let message = g2o::write_graph_to(&graph, &mut out, "g.g2o")
        .unwrap_err()
        .to_string();
    assert_eq!(
        message,
        "g.g2o: plane edge 3: the robot pose and the sensor offset are the same vertex 6"
    );
    assert!(out.is_empty(), "nothing is written");
}

/// A graph of g2o's slam3d records: two sensor offsets, two poses, a point,
/// an odometry edge, a point edge through offset 1 and a planar prior
/// (g2o's `simulator_3d_plane --planar_motion=true` writes it so) through
/// offset 0.
const SLAM3D: &str = "\
PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1
PARAMS_SE3OFFSET 1 0 0 0.3 0.5 -0.5 0.5 -0.5
VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1
VERTEX_SE3:QUAT 1 1 0 0 0 0 0 1
VERTEX_TRACKXYZ 2 1 2 3
EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1
EDGE_SE3_TRACKXYZ 0 2 1 2 -1 2.7 100 0 0 100 0 100
EDGE_SE3_PRIOR 1 0 0 0 0 0 0 0 1 0 0 0 0 0 0 0 0 0 0 0 1e+09 0 0 0 0 0 0 0 0 0
FIX 0
";

#[test]
fn g2o_slam3d_records_are_read_and_their_defects_named_at_their_line() {
    let read = |text: &str| g2o::graph_from_text(text, "s.g2o");
    let graph = read(SLAM3D).unwrap();
    assert_eq!(graph.points.len(), 1);
    assert_eq!(graph.point_edges.len(), 1);
    assert_eq!(graph.priors.len(), 1);
    // The prior's information is g2o's [δt, δq] order swapped to [δω, δρ]:
    // the height z is its last coordinate.
    assert_eq!(graph.priors[0].information[(5, 5)], 1e9);
    let point_edge = |fields: &str| format!("EDGE_SE3_TRACKXYZ 0 2 {fields}");
    let prior = |fields: &str| format!("EDGE_SE3_PRIOR 1 {fields}");
    let planar = "0 0 0 0 0 0 0 0 0 0 0 1e+09 0 0 0 0 0 0 0 0 0";
    let cases = [
        (
            7,
            point_edge("1 2 -1 2.7 100 0 0 100 0"),
            "line ends before an information entry (6 expected)",
        ),
        (
            7,
            point_edge("1 2 -1 2.7 100 0 0 100 0 100 7"),
            "unexpected extra field `7`",
        ),
        (
            7,
            point_edge("1 2 nan 2.7 100 0 0 100 0 100"),
            "a point coordinate (x y z)",
        ),
        (
            7,
            point_edge("1 2 -1 2.7 100 0 0 100 0 inf"),
            "an information entry",
        ),
        (
            7,
            point_edge("5 2 -1 2.7 100 0 0 100 0 100"),
            "parameter 5 is not defined",
        ),
        (
            7,
            point_edge("1 2 -1 2.7 100 200 0 100 0 100"),
            "information matrix is not positive definite",
        ),
        (
            7,
            "EDGE_SE3_TRACKXYZ 0 1 1 2 -1 2.7 100 0 0 100 0 100".into(),
            "vertex 1 is a VERTEX_SE3:QUAT, not a VERTEX_TRACKXYZ",
        ),
        (
            7,
            "EDGE_SE3_TRACKXYZ 2 2 1 2 -1 2.7 100 0 0 100 0 100".into(),
            "vertex 2 is a VERTEX_TRACKXYZ, not a VERTEX_SE3:QUAT",
        ),
        (
            8,
            prior(&format!("0 0 0 0 0 0 0 1 {}", &planar[..planar.len() - 2])),
            "line ends before an information entry (21 expected)",
        ),
        (
            8,
            prior(&format!("0 0 0 0 0 0 0 1 {planar} 1")),
            "unexpected extra field `1`",
        ),
        (
            8,
            prior(&format!("0 0 0 nan 0 0 0 1 {planar}")),
            "a translation component",
        ),
        (
            8,
            prior(&format!("0 0 0 0 0 0 0 2 {planar}")),
            "measurement: not a unit quaternion",
        ),
        (
            8,
            prior(&format!("4 0 0 0 0 0 0 1 {planar}")),
            "parameter 4 is not defined",
        ),
        (
            8,
            prior("0 0 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 -1 0 0 0 1 0 0 1 0 1"),
            "information matrix is not positive semi-definite",
        ),
        (
            8,
            prior(&format!("0 0 0 0 0 0 0 1 {}", planar.replace("1e+09", "0"))),
            "information matrix has no positive eigenvalue",
        ),
        (
            8,
            "EDGE_SE3_PRIOR 2 0 0 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1".into(),
            "vertex 2 is a VERTEX_TRACKXYZ, not a VERTEX_SE3:QUAT",
        ),
        (
            5,
            "VERTEX_TRACKXYZ 2 1 2".into(),
            "line ends before a point coordinate (x y z)",
        ),
        (
            5,
            "VERTEX_TRACKXYZ 2 1 2 1e999".into(),
            "a point coordinate (x y z)",
        ),
        (
            5,
            "VERTEX_TRACKXYZ 1 1 2 3".into(),
            "vertex id 1 defined again (first as a VERTEX_SE3:QUAT)",
        ),
        (
            5,
            "VERTEX_POINTXYZ 2 1 2 3".into(),
            "unsupported tag `VERTEX_POINTXYZ`",
        ),
    ];
    for (line, replacement, what) in cases {
        assert_error(
            read(&with_line(SLAM3D, line, &replacement)),
            "s.g2o",
            line,
            what,
        );
    }
}

#[test]
fn g2o_slam3d_records_round_trip_and_a_pose_graph_with_a_prior_is_told_from_its_tags() {
    let graph = g2o::graph_from_text(SLAM3D, "s.g2o").unwrap();
    let mut out = Vec::new();
    g2o::write_graph_to(&graph, &mut out, "out").unwrap();
    let again = g2o::graph_from_text(std::str::from_utf8(&out).unwrap(), "out").unwrap();
    assert_eq!(again, graph);
    // Poses, odometry and a prior only: a g2o graph of its own, not a plain
    // pose graph, whatever the record the prior follows.
    let pose_graph_with_prior: String = SLAM3D
        .lines()
        .filter(|l| !l.contains("TRACKXYZ"))
        .map(|l| format!("{l}\n"))
        .collect();
    let read = Problem::read_from(pose_graph_with_prior.as_bytes(), "p.g2o", None).unwrap();
    let Problem::G2oAddons(read) = read else {
        panic!("read as {:?}", read.format());
    };
    assert_eq!(read.priors.len(), 1);
    assert!(read.points.is_empty());
}
