//! The synthetic BAL generator: seeded, the sizes asked for, the noise,
//! outliers and perturbations stated, every point in every image.

use nalgebra::Rotation3;
use slam_data::synthetic::{SyntheticConfig, generate, in_image};
use slam_data::{BalProblem, bal};

#[test]
fn the_same_seed_gives_the_same_problem() {
    let config = SyntheticConfig::with_observations(10_000, 42);
    assert_eq!(generate(&config).unwrap(), generate(&config).unwrap());
    let other = SyntheticConfig { seed: 43, ..config };
    assert_ne!(
        generate(&other).unwrap().problem,
        generate(&SyntheticConfig::with_observations(10_000, 42))
            .unwrap()
            .problem
    );
}

#[test]
fn sizes_are_as_asked_and_the_problem_writes_as_bal() {
    let config = SyntheticConfig::with_observations(10_000, 1);
    let s = generate(&config).unwrap();
    let p = &s.problem;
    assert_eq!(
        (p.cameras.len(), p.points.len(), p.observations.len()),
        (10, 2_000, 10_000)
    );
    assert_eq!(config.observations(), Some(10_000));
    let config = SyntheticConfig::with_observations(100_000, 1);
    assert_eq!(
        (config.cameras, config.points, config.views_per_point),
        (100, 20_000, 5)
    );
    let mut out = Vec::new();
    bal::write_to(p, &mut out, "synthetic.txt").unwrap();
    let back: BalProblem =
        bal::from_text(std::str::from_utf8(&out).unwrap(), "synthetic.txt").unwrap();
    assert_eq!(&back, p);
}

#[test]
fn each_point_is_seen_by_distinct_cameras_inside_their_images() {
    let config = SyntheticConfig {
        cameras: 37,
        points: 3_000,
        views_per_point: 6,
        ..SyntheticConfig::with_observations(0, 5)
    };
    let s = generate(&config).unwrap();
    for (j, views) in s.problem.observations.chunks(6).enumerate() {
        let mut cameras: Vec<usize> = views.iter().map(|o| o.camera).collect();
        cameras.sort_unstable();
        cameras.dedup();
        assert_eq!(cameras.len(), 6, "point {j}");
        for o in views {
            assert_eq!(o.point, j);
            let exact = s.true_cameras[o.camera].camera().project(&s.true_points[j]);
            assert!(
                exact.is_some_and(|pixel| in_image(&pixel)),
                "point {j} in camera {}",
                o.camera
            );
        }
    }
}

#[test]
fn noise_and_outliers_have_the_stated_sizes() {
    let config = SyntheticConfig::with_observations(100_000, 9);
    let s = generate(&config).unwrap();
    let n = s.problem.observations.len();
    // Outliers: Binomial(100 000, 0.05), standard deviation 69.
    let fraction = s.outliers.len() as f64 / n as f64;
    assert!(
        (0.047..0.053).contains(&fraction),
        "outlier fraction {fraction}"
    );
    let mut is_outlier = vec![false; n];
    for &k in &s.outliers {
        is_outlier[k] = true;
        assert!(in_image(&s.problem.observations[k].pixel));
    }
    // Inlier residuals against the truth: mean 0, standard deviation 1 px
    // (190 000 samples: the estimate's own spread is 0.2%).
    let models: Vec<_> = s.true_cameras.iter().map(|c| c.camera()).collect();
    let residuals: Vec<f64> = s
        .problem
        .observations
        .iter()
        .zip(&is_outlier)
        .filter(|(_, outlier)| !**outlier)
        .flat_map(|(o, _)| {
            let exact = models[o.camera].project(&s.true_points[o.point]).unwrap();
            let r = o.pixel - exact;
            [r.x, r.y]
        })
        .collect();
    let mean = residuals.iter().sum::<f64>() / residuals.len() as f64;
    let sigma = (residuals.iter().map(|r| r * r).sum::<f64>() / residuals.len() as f64).sqrt();
    assert!(mean.abs() < 0.01, "mean {mean}");
    assert!((0.99..1.01).contains(&sigma), "sigma {sigma}");
}

#[test]
fn initial_values_are_perturbed_by_the_stated_amounts() {
    let config = SyntheticConfig {
        cameras: 2_000,
        ..SyntheticConfig::with_observations(100_000, 3)
    };
    let s = generate(&config).unwrap();
    let rms =
        |values: &[f64]| (values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64).sqrt();
    // Rotation: exp(δ) R with δ ~ N(0, 0.01² I): per-axis RMS of δ is 0.01
    // (6 000 samples: the estimate's own spread is 0.9%).
    let deltas: Vec<f64> = s
        .problem
        .cameras
        .iter()
        .zip(&s.true_cameras)
        .flat_map(|(initial, truth)| {
            let delta = Rotation3::new(initial.rotation) * Rotation3::new(truth.rotation).inverse();
            let axis_angle = delta.scaled_axis();
            [axis_angle.x, axis_angle.y, axis_angle.z]
        })
        .collect();
    let r = rms(&deltas);
    assert!((0.0095..0.0105).contains(&r), "rotation {r}");
    let shifts: Vec<f64> = s
        .problem
        .points
        .iter()
        .zip(&s.true_points)
        .flat_map(|(a, b)| (a - b).iter().copied().collect::<Vec<_>>())
        .collect();
    // 60 000 samples: 0.3%.
    let r = rms(&shifts);
    assert!((0.049..0.051).contains(&r), "points {r}");
    let focal: Vec<f64> = s
        .problem
        .cameras
        .iter()
        .zip(&s.true_cameras)
        .map(|(a, b)| a.intrinsics.focal / b.intrinsics.focal - 1.0)
        .collect();
    // 2 000 samples: the RMS estimate's own spread is 1.6%.
    let r = rms(&focal);
    assert!((0.009..0.011).contains(&r), "focal {r}");
}

#[test]
fn impossible_settings_are_refused() {
    let base = SyntheticConfig::with_observations(1_000, 0);
    let cases = [
        (
            SyntheticConfig {
                views_per_point: 1,
                ..base.clone()
            },
            "views per point must be from 2 to the 10 cameras, not 1",
        ),
        (
            SyntheticConfig {
                views_per_point: 11,
                ..base.clone()
            },
            "views per point must be from 2 to the 10 cameras, not 11",
        ),
        (
            SyntheticConfig {
                cameras: 1,
                ..base.clone()
            },
            "the number of cameras must be from 2 to 1000000, not 1",
        ),
        (
            SyntheticConfig {
                outlier_fraction: 1.5,
                ..base.clone()
            },
            "the outlier fraction must be in [0, 1], not 1.5",
        ),
        (
            SyntheticConfig {
                pixel_sigma: f64::NAN,
                ..base.clone()
            },
            "pixel sigma must be finite and not negative, not NaN",
        ),
        (
            SyntheticConfig {
                points: usize::MAX,
                ..base.clone()
            },
            "more than 100000000 observations asked for",
        ),
    ];
    for (config, message) in cases {
        assert_eq!(
            generate(&config).unwrap_err().to_string(),
            format!("synthetic BAL: {message}")
        );
    }
}

/// Local visibility: each point seen by consecutive cameras, inside their
/// images, so that a camera shares points only with its `views − 1`
/// neighbours on either side (around the ring).
#[test]
fn local_visibility_sees_each_point_from_consecutive_cameras() {
    use slam_data::synthetic::Visibility;
    for cameras in [10, 200] {
        let config = SyntheticConfig {
            cameras,
            points: 2_000,
            views_per_point: 4,
            visibility: Visibility::Local,
            outlier_fraction: 0.0,
            ..SyntheticConfig::with_observations(0, 8)
        };
        let s = generate(&config).unwrap();
        for (j, views) in s.problem.observations.chunks(4).enumerate() {
            let first = views[0].camera;
            for (v, o) in views.iter().enumerate() {
                assert_eq!(o.camera, (first + v) % cameras, "point {j}");
                let exact = s.true_cameras[o.camera].camera().project(&s.true_points[j]);
                assert!(
                    exact.is_some_and(|p| in_image(&p)),
                    "point {j} in camera {}",
                    o.camera
                );
            }
        }
        assert_ne!(
            s,
            generate(&SyntheticConfig {
                visibility: Visibility::Ring,
                ..config
            })
            .unwrap()
        );
    }
}
