//! The point-line-plane scene generator: deterministic per seed, measuring
//! what its cameras see, and without noise its measurements reproduce the
//! ground truth through the shipped factors with zero residual.

use factor_core::geometry::{InfinitePlane, Intrinsics, OrthonormalLine};
use factor_core::lie::{Quaternion, Se3, So3};
use nalgebra::{Isometry3, Unit};
use slam_data::plp_scene::{PlpConfig, PlpScene, generate};
use slam_factors::{LineReprojection, PlaneFactor, PointReprojection};

fn se3(pose: &Isometry3<f64>) -> Se3<f64> {
    let q = pose.rotation;
    Se3::new(
        So3::from_quaternion(Quaternion::new(q.i, q.j, q.k, q.w)),
        pose.translation.vector,
    )
}

/// The largest residual of each kind over all measurements (px, px, rad).
fn worst_residuals(scene: &PlpScene) -> [f64; 3] {
    let [fu, fv, cu, cv] = scene.config.intrinsics;
    let intrinsics = Intrinsics::new(fu, fv, cu, cv);
    let truth = &scene.truth;
    let poses: Vec<Se3<f64>> = truth.cameras.iter().map(se3).collect();
    let mut worst = [0.0_f64; 3];
    for o in &scene.point_observations {
        let f = PointReprojection {
            intrinsics,
            observed: o.pixel,
            pose: poses[o.camera],
            point: truth.points[o.point],
        };
        worst[0] = worst[0].max(f.residual().unwrap().amax());
    }
    for o in &scene.segment_observations {
        let s = &truth.segments[o.segment];
        let f = LineReprojection {
            intrinsics,
            start: o.start,
            end: o.end,
            pose: poses[o.camera],
            line: OrthonormalLine::try_from_points(&s.start, &s.end).unwrap(),
        };
        worst[1] = worst[1].max(f.residual().unwrap().amax());
    }
    for o in &scene.plane_observations {
        let f = PlaneFactor {
            measured: Unit::new_normalize(o.measured),
            pose: poses[o.camera],
            plane: InfinitePlane::from_coefficients(&truth.planes[o.plane]),
        };
        worst[2] = worst[2].max(f.residual().unwrap().amax());
    }
    worst
}

#[test]
fn noise_free_measurements_reproduce_the_truth_through_the_shipped_factors() {
    for config in [PlpConfig::room(1), PlpConfig::corridor(2)] {
        let scene = generate(&config.noise_free()).unwrap();
        let worst = worst_residuals(&scene);
        println!("{:?}: worst residuals {worst:?}", scene.config.layout);
        assert!(
            worst[0] <= 1e-9 && worst[1] <= 1e-9 && worst[2] <= 1e-12,
            "{worst:?}"
        );
    }
}

#[test]
fn noisy_measurements_are_off_by_their_noise() {
    let scene = generate(&PlpConfig::room(3)).unwrap();
    let worst = worst_residuals(&scene);
    // Gaussian noise of 1 px: over about 2000 coordinates the largest is
    // 3–5 σ; the plane residual is a log-quaternion of 0.01 rad noise.
    assert!((2.0..6.0).contains(&worst[0]), "{worst:?}");
    assert!((1.0..6.0).contains(&worst[1]), "{worst:?}");
    assert!(worst[2] > 1e-3 && worst[2] < 0.1, "{worst:?}");
}

#[test]
fn scenes_are_deterministic_and_every_camera_sees_each_kind() {
    let config = PlpConfig::room(7);
    let (a, b) = (generate(&config).unwrap(), generate(&config).unwrap());
    assert_eq!(a, b);
    assert_ne!(a, generate(&PlpConfig::room(8)).unwrap());
    assert_ne!(a.initial, a.truth);
    let truth = &a.truth;
    assert_eq!(
        (
            truth.cameras.len(),
            truth.points.len(),
            truth.segments.len(),
            truth.planes.len()
        ),
        (15, 300, 30, 6)
    );
    for scene in [a, generate(&PlpConfig::corridor(9)).unwrap()] {
        for camera in 0..scene.truth.cameras.len() {
            let points = scene
                .point_observations
                .iter()
                .filter(|o| o.camera == camera)
                .count();
            let segments = scene
                .segment_observations
                .iter()
                .filter(|o| o.camera == camera)
                .count();
            let planes = scene
                .plane_observations
                .iter()
                .filter(|o| o.camera == camera)
                .count();
            assert!(
                points >= 20 && segments >= 3 && planes >= 2,
                "{:?} camera {camera}: {points} points, {segments} segments, {planes} planes",
                scene.config.layout
            );
        }
    }
}

#[test]
fn impossible_settings_are_refused() {
    let mut config = PlpConfig::room(1);
    config.cameras = 1;
    assert!(
        generate(&config)
            .unwrap_err()
            .to_string()
            .contains("at least 2 cameras")
    );
    let mut config = PlpConfig::room(1);
    config.eye_height = 5.0;
    assert!(
        generate(&config)
            .unwrap_err()
            .to_string()
            .contains("eye height")
    );
    let mut config = PlpConfig::room(1);
    config.pixel_sigma = f64::NAN;
    assert!(
        generate(&config)
            .unwrap_err()
            .to_string()
            .contains("noise levels")
    );
}
