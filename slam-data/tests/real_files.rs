//! The readers against the shipped files: counts, values read off the file
//! text by hand, and values GTSAM 4.3.0 computes from the same files
//! (printed by its Python wheel: `SfmData.FromBalFile`, `FromBundlerFile`,
//! `readG2o`, `Pose3.compose`, `StereoCamera.project`).

// Literals are the file's text, digit for digit, even where a double needs fewer.
#![allow(clippy::excessive_precision)]

use crate::common;

use common::data;
use nalgebra::{Matrix3, Matrix6, Vector2, Vector3};
use slam_data::{
    Format, Problem, Rotation, StereoCalibration, VoFiles, bal, bundler, edge3, g2o, kitti_vo,
};

fn assert_close(actual: &[f64], expected: &[f64], tolerance: f64, what: &str) {
    assert_eq!(actual.len(), expected.len(), "{what}: lengths");
    for (k, (a, e)) in actual.iter().zip(expected).enumerate() {
        assert!(
            (a - e).abs() <= tolerance,
            "{what}[{k}]: {a} vs {e} (tolerance {tolerance})"
        );
    }
}

/// A row-major 3×3 matrix as GTSAM prints it.
fn rows(m: [[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|r, c| m[r][c])
}

#[test]
fn dubrovnik_counts_and_values_read_off_the_text() {
    let p = bal::read(data("dubrovnik-3-7-pre.txt")).unwrap();
    assert_eq!(
        (p.cameras.len(), p.points.len(), p.observations.len()),
        (3, 7, 19)
    );
    // Line 3: `0 0     -3.859900e+02 3.871200e+02`; line 21: `2 6     -5.841998e+01 1.108300e+02`.
    let first = p.observations[0];
    assert_eq!(
        (first.camera, first.point, first.pixel),
        (0, 0, Vector2::new(-385.99, 387.12))
    );
    let last = p.observations[18];
    assert_eq!(
        (last.camera, last.point, last.pixel),
        (2, 6, Vector2::new(-58.41998, 110.83))
    );
    // Lines 23–31: camera 0.
    let c = p.cameras[0];
    assert_eq!(
        c.rotation,
        Vector3::new(
            -1.6943983532198115e-02,
            1.1171804676513932e-02,
            2.4643508831711991e-03
        )
    );
    assert_eq!(
        c.translation,
        Vector3::new(
            7.3030995682610689e-01,
            -2.6490818471043420e-01,
            -1.7127892627337182e+00
        )
    );
    assert_eq!(
        (c.intrinsics.focal, c.intrinsics.k1, c.intrinsics.k2),
        (
            1.4300319432711681e+03,
            -7.5572758535864072e-08,
            3.2377569465570913e-14
        )
    );
    // The last three lines with numbers: point 6.
    assert_eq!(
        p.points[6],
        Vector3::new(
            7.6465738085189585e+00,
            1.4185331909846619e+01,
            -5.2070299568846060e+01
        )
    );
}

#[test]
fn dubrovnik_cameras_and_projections_agree_with_gtsam() {
    let p = bal::read(data("dubrovnik-3-7-pre.txt")).unwrap();
    // GTSAM: SfmData.FromBalFile(...).camera(0).pose(), world from camera.
    let pose = p.cameras[0].camera().world_from_camera_cv();
    let expected_r = rows([
        [
            0.9999345611568933,
            -0.0023695350709806327,
            0.011191903659278933,
        ],
        [
            -0.002558823352067332,
            -0.9998534193041593,
            0.01692903803628309,
        ],
        [
            0.011150149192907837,
            -0.01695656832405654,
            -0.999794053274797,
        ],
    ]);
    let r = pose.rotation.to_rotation_matrix().into_inner();
    assert_close(
        r.as_slice(),
        expected_r.as_slice(),
        1e-14,
        "camera 0 rotation",
    );
    let expected_t = [-0.748803829370325, 0.23774221387920297, 1.7087853881520625];
    assert_close(
        pose.translation.vector.as_slice(),
        &expected_t,
        1e-12,
        "camera 0 translation",
    );
    // GTSAM: camera(i).project(track(j).point3()), in its (u, −v) pixels.
    let gtsam_projections = [
        (0, 0, [-394.00341727035317, -395.02050542459807]),
        (0, 1, [-39.06487170078452, -500.5190995808654]),
        (0, 2, [-679.4382073448191, -122.37457534662687]),
        (6, 0, [205.1149028007031, -345.057739920705]),
        (6, 1, [556.6113722019536, -302.04117540188525]),
        (6, 2, [-66.52902810324069, -110.1724324403066]),
    ];
    for (point, camera, [u, minus_v]) in gtsam_projections {
        let pixel = p.cameras[camera]
            .camera()
            .project(&p.points[point])
            .unwrap();
        let what = format!("point {point} in camera {camera}");
        assert_close(pixel.as_slice(), &[u, -minus_v], 1e-9, &what);
    }
    // GTSAM: the largest |project − measured| over the 19 observations.
    let largest = p
        .observations
        .iter()
        .map(|o| {
            (p.cameras[o.camera]
                .camera()
                .project(&p.points[o.point])
                .unwrap()
                - o.pixel)
                .norm()
        })
        .fold(0.0, f64::max);
    assert_close(
        &[largest],
        &[38.350604302144845],
        1e-9,
        "largest reprojection error",
    );
}

#[test]
fn balbianello_counts_and_values_read_off_the_text() {
    let p = bundler::read(data("Balbianello.out")).unwrap();
    assert_eq!(
        (p.cameras.len(), p.points.len(), p.observations.len()),
        (5, 544, 1417)
    );
    // Lines 3–7: camera 0.
    let c = p.cameras[0];
    assert_eq!(
        (c.intrinsics.focal, c.intrinsics.k1, c.intrinsics.k2),
        (5.1869203975e+02, -1.1457014134e-01, -3.4479818947e-02)
    );
    assert_eq!(
        c.rotation.row(0).transpose(),
        Vector3::new(9.9972739831e-01, 5.9754666132e-03, 2.2570397996e-02)
    );
    assert_eq!(
        c.translation,
        Vector3::new(7.1074927420e-02, 4.4169219329e-02, 5.6191022645e-01)
    );
    // Lines 28–30: point 0, colour 70 74 54, views `3 0 27 45.2700 -38.3700 3 20 … 1 17 …`.
    assert_eq!(
        p.points[0].position,
        Vector3::new(1.0348687869e-01, -1.2489429393e-01, -2.0153888320e+00)
    );
    assert_eq!(p.points[0].colour, [70, 74, 54]);
    let views: Vec<_> = p.observations[..3]
        .iter()
        .map(|o| (o.camera, o.point, o.key, o.pixel))
        .collect();
    assert_eq!(
        views,
        [
            (0, 0, 27, Vector2::new(45.27, -38.37)),
            (3, 0, 20, Vector2::new(0.55, -13.81)),
            (1, 0, 17, Vector2::new(48.38, -57.55)),
        ]
    );
    // The last three lines: point 543.
    assert_eq!(p.points[543].colour, [211, 191, 164]);
    let last = p.observations[1416];
    assert_eq!(
        (last.camera, last.point, last.key, last.pixel),
        (4, 543, 1097, Vector2::new(245.33, 1.89))
    );
}

#[test]
fn balbianello_cameras_and_projections_agree_with_gtsam() {
    let p = bundler::read(data("Balbianello.out")).unwrap();
    // GTSAM keeps the written matrix, this the nearest rotation: they differ
    // by about the file's 11 digits.
    let expected = [
        (
            0,
            rows([
                [0.99972739831, 0.0063019161555, 0.022481435001],
                [0.0059754666132, -0.99987616292, 0.014558592624],
                [0.022570397996, -0.014420286863, -0.99964125188],
            ]),
            [
                -0.05814465332547057,
                -0.036407833319541096,
                -0.5639497644252974,
            ],
        ),
        (
            4,
            rows([
                [0.8269180324, -0.082265309276, -0.55627240322],
                [-0.10052089965, -0.99493231048, -0.0022904791136],
                [-0.55326496042, 0.057811040902, -0.83099685145],
            ]),
            [
                1.1048174952010383,
                -0.018300347736133576,
                -0.5346464208908175,
            ],
        ),
    ];
    for (i, expected_r, expected_t) in expected {
        let pose = p.cameras[i].camera().world_from_camera_cv();
        let r = pose.rotation.to_rotation_matrix().into_inner();
        assert_close(
            r.as_slice(),
            expected_r.as_slice(),
            1e-10,
            &format!("camera {i} rotation"),
        );
        let t = pose.translation.vector;
        assert_close(
            t.as_slice(),
            &expected_t,
            1e-10,
            &format!("camera {i} translation"),
        );
    }
    let gtsam_projections = [
        (0, 0, [45.72045912203884, 39.350589565024244]),
        (0, 3, [0.7720390205824759, 12.78693425402226]),
        (0, 1, [47.7098693852174, 57.464894275056864]),
        (543, 2, [286.4793064419665, -19.947890195185533]),
        (543, 4, [245.3341942247908, -1.854250104219618]),
    ];
    for (point, camera, [u, minus_v]) in gtsam_projections {
        let pixel = p.cameras[camera]
            .camera()
            .project(&p.points[point].position)
            .unwrap();
        let what = format!("point {point} in camera {camera}");
        assert_close(pixel.as_slice(), &[u, -minus_v], 1e-8, &what);
    }
}

#[test]
fn balbianello_as_bal_keeps_the_cameras() {
    let bundler = bundler::read(data("Balbianello.out")).unwrap();
    let bal = bundler.to_bal();
    assert_eq!(bal.observations.len(), 1417);
    for (b, c) in bundler.cameras.iter().zip(&bal.cameras) {
        let r = c.camera().rotation.into_inner();
        assert_close(r.as_slice(), b.rotation.as_slice(), 1e-10, "rotation");
        assert_eq!((c.translation, c.intrinsics), (b.translation, b.intrinsics));
    }
}

#[test]
fn pose3example_counts_values_and_gtsam_rotations() {
    let g = g2o::read(data("pose3example.txt")).unwrap();
    assert_eq!((g.vertices.len(), g.edges.len()), (5, 6));
    // Line 2: `VERTEX_SE3:QUAT 1 1.001367 0.015390 0.004948 0.190253 0.283162 -0.392318 0.854230`.
    let v = g.vertices[1];
    assert_eq!(v.id, 1);
    assert_eq!(
        v.pose.translation,
        Vector3::new(1.001367, 0.015390, 0.004948)
    );
    assert_eq!(
        v.pose.rotation,
        Rotation::Quaternion([0.190253, 0.283162, -0.392318, 0.854230])
    );
    // Line 11: `EDGE_SE3:QUAT 3 0 -0.623267 0.086928 0.773222 0.104639 0.627755 0.766795 0.083672 10000 …`.
    let e = g.edges[5];
    assert_eq!((e.from, e.to), (3, 0));
    assert_eq!(
        e.measurement.translation,
        Vector3::new(-0.623267, 0.086928, 0.773222)
    );
    assert_eq!(e.information, Matrix6::identity() * 10000.0);
    // GTSAM: readG2o(...)[0].at(5).measured().rotation().matrix() and vertex 4.
    let expected = rows([
        [
            -0.9640993965615299,
            0.003056764631976433,
            0.2655240285542493,
        ],
        [0.2596935324004801, -0.19784630420787108, 0.9452069134007892],
        [
            0.055422222790626655,
            0.9802282877479465,
            0.18994968049374295,
        ],
    ]);
    let r = e
        .measurement
        .rotation
        .unit_quaternion()
        .to_rotation_matrix()
        .into_inner();
    assert_close(r.as_slice(), expected.as_slice(), 1e-15, "edge 5 rotation");
    let expected = rows([
        [
            0.17449301901219405,
            -0.6496941029104922,
            -0.7398984788194534,
        ],
        [0.7157321650137652, 0.599738725062609, -0.35782807271786937],
        [0.6762245590635692, -0.46713063943998284, 0.5696571876275014],
    ]);
    let r = g.vertices[4]
        .pose
        .rotation
        .unit_quaternion()
        .to_rotation_matrix()
        .into_inner();
    assert_close(
        r.as_slice(),
        expected.as_slice(),
        1e-15,
        "vertex 4 rotation",
    );
}

#[test]
fn g2o_information_blocks_are_swapped_to_rotation_first() {
    // Upper triangle of a g2o-order ([δt, δq]) matrix with distinct entries.
    let text = "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 0 0 0 0 0 0 1\n\
                EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 \
                100 0.12 0.13 0.14 0.15 0.16 101 0.23 0.24 0.25 0.26 \
                102 0.34 0.35 0.36 103 0.45 0.46 104 0.56 105\n";
    let g = g2o::from_text(text, "swap.g2o").unwrap();
    // Written out by hand: rows and columns in the order q1 q2 q3 t1 t2 t3.
    #[rustfmt::skip]
    let expected = Matrix6::new(
        103.0, 0.45, 0.46, 0.14, 0.24, 0.34,
        0.45, 104.0, 0.56, 0.15, 0.25, 0.35,
        0.46, 0.56, 105.0, 0.16, 0.26, 0.36,
        0.14, 0.15, 0.16, 100.0, 0.12, 0.13,
        0.24, 0.25, 0.26, 0.12, 101.0, 0.23,
        0.34, 0.35, 0.36, 0.13, 0.23, 102.0,
    );
    assert_eq!(g.edges[0].information, expected);
    // And back: the written line has the file's 21 numbers in order.
    let mut out = Vec::new();
    g2o::write_to(&g, &mut out, "out.g2o").unwrap();
    let written = String::from_utf8(out).unwrap();
    let edge_line = written.lines().nth(2).unwrap();
    assert!(edge_line.ends_with(
        " 100 0.12 0.13 0.14 0.15 0.16 101 0.23 0.24 0.25 0.26 102 0.34 0.35 0.36 103 0.45 0.46 104 0.56 105"
    ));
}

#[test]
fn sphere2500_counts_values_and_gtsam_rotation() {
    let g = edge3::read(data("sphere2500.txt")).unwrap();
    assert_eq!((g.vertices.len(), g.edges.len()), (0, 4949));
    // Line 1: `EDGE3 0 1 0.341895 -0.0416997 0.0330394 -0.00305942 0.00822248 0.1802 10 0 … 25`.
    let e = g.edges[0];
    assert_eq!((e.from, e.to), (0, 1));
    assert_eq!(
        e.measurement.translation,
        Vector3::new(0.341895, -0.0416997, 0.0330394)
    );
    assert_eq!(
        e.measurement.rotation,
        Rotation::RollPitchYaw([-0.00305942, 0.00822248, 0.1802])
    );
    let diagonal = Matrix6::from_diagonal(&[10.0, 10.0, 10.0, 100.0, 100.0, 25.0].into());
    assert_eq!(e.information, diagonal);
    // Line 4949: `EDGE3 2449 2499 …`.
    assert_eq!((g.edges[4948].from, g.edges[4948].to), (2449, 2499));
    // GTSAM: Rot3::Ypr(yaw, pitch, roll) of edges 0 and 4948.
    let expected = rows([
        [
            0.9837746101638892,
            -0.17925024817199053,
            0.007540883712648502,
        ],
        [0.1792202799439581, 0.9837987543911387, 0.004483538251573094],
        [
            -0.008222387347795112,
            -0.0030593118055905087,
            0.9999615157382704,
        ],
    ]);
    let r = e
        .measurement
        .rotation
        .unit_quaternion()
        .to_rotation_matrix()
        .into_inner();
    assert_close(r.as_slice(), expected.as_slice(), 1e-15, "edge 0 rotation");
    let expected = rows([
        [
            0.9999422713304001,
            -0.01038526862058995,
            0.002756846437258217,
        ],
        [
            0.010546982221228357,
            0.9976870752504566,
            -0.06715103159456774,
        ],
        [
            -0.0020530885576434833,
            0.06717623146521196,
            0.9977390133464296,
        ],
    ]);
    let r = g.edges[4948]
        .measurement
        .rotation
        .unit_quaternion()
        .to_rotation_matrix()
        .into_inner();
    assert_close(
        r.as_slice(),
        expected.as_slice(),
        1e-15,
        "edge 4948 rotation",
    );
}

#[test]
fn sphere2500_odometry_chain_agrees_with_gtsam_compose() {
    let g = edge3::read(data("sphere2500.txt")).unwrap();
    let initial = g.odometry_initial_values().unwrap();
    assert_eq!(initial.len(), 2500);
    assert!(initial.iter().enumerate().all(|(k, v)| v.id == k));
    // GTSAM: pose[j] = pose[i].compose(measured) along the i → i+1 edges from Pose3().
    let expected = [
        (1, [0.341895, -0.0416997, 0.0330394]),
        (
            1250,
            [-24.888013639011206, -29.25419269583691, -49.78487424028856],
        ),
        (
            2499,
            [44.47271669437423, 49.38025886427466, -86.23808379481387],
        ),
    ];
    for (k, t) in expected {
        let pose = initial[k].pose.isometry();
        assert_close(
            pose.translation.vector.as_slice(),
            &t,
            1e-9,
            &format!("pose {k}"),
        );
    }
    let expected_r = rows([
        [0.3855265878625836, -0.18424716111476985, 0.9041140601009322],
        [-0.8007912144935507, 0.4199546150615777, 0.4270498238829162],
        [-0.4583695897864385, -0.8886456576778181, 0.0143601618857491],
    ]);
    let r = initial[2499]
        .pose
        .isometry()
        .rotation
        .to_rotation_matrix()
        .into_inner();
    assert_close(
        r.as_slice(),
        expected_r.as_slice(),
        1e-11,
        "pose 2499 rotation",
    );
}

#[test]
fn kitti_vo_counts_and_values_read_off_the_text() {
    let vo =
        kitti_vo::read(&VoFiles::beside(&data("VO_stereo_factors_large.txt")).unwrap()).unwrap();
    assert_eq!(
        vo.calibration,
        StereoCalibration {
            fx: 721.5377,
            fy: 721.5377,
            skew: 0.0,
            u0: 609.5593,
            v0: 172.854,
            baseline: 0.537150588,
        }
    );
    // 8189 lines of observations (GTSAM's example graph has 8190 factors:
    // these and one NonlinearEquality on pose 1).
    assert_eq!((vo.poses.len(), vo.observations.len()), (26, 8189));
    assert_eq!(vo.poses[0].id, 1);
    assert_eq!(vo.poses[0].rotation, Matrix3::identity());
    assert_eq!(vo.poses[0].translation, Vector3::zeros());
    // Last line: `26    0.999474  -0.0145772  -0.0289811   -0.347714 …     22.9037           0 0 0 1`.
    let last = vo.poses[25];
    assert_eq!(last.id, 26);
    assert_eq!(
        last.rotation.row(0).transpose(),
        Vector3::new(0.999474, -0.0145772, -0.0289811)
    );
    assert_eq!(last.translation, Vector3::new(-0.347714, 0.131533, 22.9037));
    // First and last lines of the factors.
    let o = vo.observations[0];
    assert_eq!(
        (o.pose, o.landmark, o.u_left, o.u_right, o.v),
        (1, 3, 209.979, 185.87, 61.5418)
    );
    assert_eq!(
        o.landmark_in_camera,
        Vector3::new(-8.90263, -2.48003, 16.0758)
    );
    let o = vo.observations[8188];
    assert_eq!(
        (o.pose, o.landmark, o.u_left, o.u_right, o.v),
        (26, 9897, 1105.84, 1022.96, 289.994)
    );
    assert_eq!(
        o.landmark_in_camera,
        Vector3::new(3.21647, 0.759204, 4.67639)
    );
}

#[test]
fn kitti_vo_observations_fit_the_stereo_model_and_landmarks_agree_with_gtsam() {
    let vo = kitti_vo::read(&VoFiles::beside(&data("VO_camera_poses_large.txt")).unwrap()).unwrap();
    // The text's six significant digits leave the triangulated points a few
    // thousandths of a pixel off their measurements (GTSAM's
    // StereoCamera.project agrees: at most 0.0070 px); a swapped field
    // would be tens of pixels off.
    for o in &vo.observations {
        let projected = vo.calibration.project(&o.landmark_in_camera).unwrap();
        assert_close(
            &projected,
            &[o.u_left, o.u_right, o.v],
            0.01,
            "stereo projection",
        );
    }
    let landmarks = vo.initial_landmarks();
    assert_eq!(landmarks.len(), 2634);
    assert_eq!(landmarks[0], (3, Vector3::new(-8.90263, -2.48003, 16.0758)));
    // GTSAM (StereoVOExample_large): Pose3(matrix).transformFrom(X, Y, Z) at
    // the first observation; the written matrix against the nearest rotation.
    let (id, position) = landmarks[2633];
    assert_eq!(id, 9897);
    let expected = [2.7195084828497995, 0.9710608086502, 27.654800553614102];
    assert_close(position.as_slice(), &expected, 1e-4, "landmark 9897");
}

#[test]
fn formats_are_detected_from_names_and_content() {
    let expected = [
        ("dubrovnik-3-7-pre.txt", Format::Bal),
        ("Balbianello.out", Format::Bundler),
        ("pose3example.txt", Format::G2o),
        ("sphere2500.txt", Format::Edge3),
        ("VO_calibration.txt", Format::KittiVo),
        ("VO_camera_poses_large.txt", Format::KittiVo),
        ("VO_stereo_factors_large.txt", Format::KittiVo),
    ];
    for (name, format) in expected {
        assert_eq!(Format::detect(&data(name)).unwrap(), format, "{name}");
        let problem = Problem::read(data(name), None).unwrap();
        assert_eq!(problem.format(), format, "{name}");
    }
    for format in Format::ALL {
        assert_eq!(format.name().parse::<Format>().unwrap(), format);
    }
    let unknown = "ply".parse::<Format>().unwrap_err().to_string();
    assert_eq!(
        unknown,
        "unknown format `ply` (one of bal, bundler, g2o, g2o-addons, edge3, kitti-vo)"
    );
}

/// g2o's line and plane graphs are told from plain pose graphs by their
/// tags, whether named `.g2o` or told by their content.
#[test]
fn g2o_line_and_plane_graphs_are_detected() {
    let addons = |name: &str| {
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../data/g2o-addons")
            .join(name)
    };
    for name in ["line3d.g2o", "plane3d.g2o", "plane3d_calib.g2o"] {
        assert_eq!(Format::detect(&addons(name)).unwrap(), Format::G2oAddons);
        let Problem::G2oAddons(graph) = Problem::read(addons(name), None).unwrap() else {
            panic!("{name}: read as a line and plane graph");
        };
        assert_eq!(graph.pose_edges.len(), 160, "{name}");
    }
    // Content alone: the same text under a name that says nothing.
    let dir = std::env::temp_dir().join(format!("slam-data-detect-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let plain = dir.join("line3d.txt");
    std::fs::copy(addons("line3d.g2o"), &plain).unwrap();
    assert_eq!(Format::detect(&plain).unwrap(), Format::G2oAddons);
    let posed = dir.join("poses.g2o");
    std::fs::write(
        &posed,
        "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n",
    )
    .unwrap();
    assert_eq!(Format::detect(&posed).unwrap(), Format::G2o);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn vo_files_are_found_beside_any_of_them() {
    // GTSAM's shared calibration serves the `_large` set, the only set
    // shipped: naming it names that set.
    for name in [
        "VO_stereo_factors_large.txt",
        "VO_camera_poses_large.txt",
        "VO_calibration.txt",
    ] {
        let files = VoFiles::beside(&data(name)).unwrap();
        assert_eq!(files.calibration, data("VO_calibration.txt"), "{name}");
        assert_eq!(files.poses, data("VO_camera_poses_large.txt"), "{name}");
        assert_eq!(files.factors, data("VO_stereo_factors_large.txt"), "{name}");
    }
    // A problem is written with a calibration of its own suffix.
    let written = VoFiles::named(&data("VO_camera_poses_opt.txt")).unwrap();
    assert_eq!(written.calibration, data("VO_calibration_opt.txt"));
    assert_eq!(written.factors, data("VO_stereo_factors_opt.txt"));
    let err = VoFiles::beside(&data("sphere2500.txt"))
        .unwrap_err()
        .to_string();
    assert!(
        err.ends_with(
            "sphere2500.txt: a KITTI VO problem is named by one of its files: \
                           VO_calibration*.txt, VO_camera_poses*.txt or VO_stereo_factors*.txt"
        ),
        "{err}"
    );
}
