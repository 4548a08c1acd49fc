//! Pose-only solves of the frames of a seeded point-line-plane scene
//! (`slam_data::plp_scene`) against its true map: noise-free measurements
//! give the true poses back, noisy ones poses within the spread the noise
//! predicts; the normal equations agree with dual numbers; a pose its
//! observations do not determine is refused.

use factor_core::geometry::{InfinitePlane, Intrinsics, OrthonormalLine};
use factor_core::lie::{Quaternion, Se3, So3};
use factor_core::nalgebra::{DMatrix, Isometry3, Matrix6, Unit, Vector6};
use factor_core::{Factor, Storage};
use factor_tracking::{Noise, Options, PoseError, PoseProblem, SolveOptions, Verdict};
use slam_data::plp_scene::{PlpConfig, PlpScene, generate};
use slam_factors::{LineReprojection, PlaneFactor, PointReprojection};

fn se3(pose: &Isometry3<f64>) -> Se3<f64> {
    let q = pose.rotation.coords;
    Se3::new(
        So3::from_quaternion(Quaternion::new(q.x, q.y, q.z, q.w)),
        pose.translation.vector,
    )
}

/// The pose error `Log(T T_true⁻¹)`: `[δω, δρ]` on the left, the tangent
/// the documents' factors perturb.
fn error(pose: &Se3<f64>, truth: &Se3<f64>) -> Vector6<f64> {
    pose.compose(&truth.inverse()).log()
}

/// Camera `camera`'s point and line observations (σ = 1 px) and, with
/// `planes`, its plane observations (unit whitening) against the true map.
fn problem(scene: &PlpScene, camera: usize, planes: bool) -> PoseProblem {
    let [fu, fv, cu, cv] = scene.config.intrinsics;
    let intrinsics = Intrinsics::new(fu, fv, cu, cv);
    let truth = &scene.truth;
    // The pose a factor carries is not used: any pose.
    let pose = Se3::identity();
    let mut problem = PoseProblem::new();
    for o in scene
        .point_observations
        .iter()
        .filter(|o| o.camera == camera)
    {
        let factor = PointReprojection {
            intrinsics,
            observed: o.pixel,
            pose,
            point: truth.points[o.point],
        };
        problem.add(&factor, &Noise::Sigma(1.0)).unwrap();
    }
    for o in scene
        .segment_observations
        .iter()
        .filter(|o| o.camera == camera)
    {
        let s = &truth.segments[o.segment];
        let factor = LineReprojection {
            intrinsics,
            start: o.start,
            end: o.end,
            pose,
            line: OrthonormalLine::try_from_points(&s.start, &s.end).unwrap(),
        };
        problem.add(&factor, &Noise::Sigma(1.0)).unwrap();
    }
    if planes {
        for o in scene
            .plane_observations
            .iter()
            .filter(|o| o.camera == camera)
        {
            let p = truth.planes[o.plane];
            let factor = PlaneFactor {
                measured: Unit::new_normalize(o.measured),
                pose,
                plane: InfinitePlane::from_normal_offset(&p.xyz(), p.w),
            };
            problem.add(&factor, &Noise::Unit).unwrap();
        }
    }
    problem
}

/// The shared minimizer's tolerances at the level of rounding.
fn tight() -> Options {
    Options {
        solve: SolveOptions::converged(100),
        ..Options::default()
    }
}

/// Noise-free: every camera, started from the scene's perturbed initial
/// pose (0.02 rad, 0.05 m off), comes back to its true pose to rounding.
#[test]
fn noise_free_frames_recover_the_true_poses() {
    let scene = generate(&PlpConfig::room(3).noise_free()).unwrap();
    for camera in 0..scene.truth.cameras.len() {
        let truth = se3(&scene.truth.cameras[camera]);
        let mut problem = problem(&scene, camera, true);
        let initial = se3(&scene.initial.cameras[camera]);
        let solution = problem.solve(&initial, &tight()).unwrap();
        assert!(
            solution.verdict.is_converged(),
            "camera {camera}: {solution:?}"
        );
        let e = error(&solution.pose, &truth).norm();
        assert!(e < 1e-9, "camera {camera}: error {e}");
        assert!(solution.cost < 1e-16, "camera {camera}: {solution:?}");
    }
}

/// With 1 px noise on points and lines and the true map, the pose error
/// `e` is, to first order, Gaussian with covariance `H⁻¹` (the whitened
/// Gauss–Newton matrix at the solution), so `eᵀ H e` follows χ² with 6
/// degrees of freedom: every camera of two seeds must stay below its
/// 99.99% quantile, 27.86, and the mean over the cameras near 6.
#[test]
fn noisy_frames_are_within_the_noise() {
    let mut distances = Vec::new();
    for seed in [1, 2] {
        let scene = generate(&PlpConfig::room(seed)).unwrap();
        for camera in 0..scene.truth.cameras.len() {
            let truth = se3(&scene.truth.cameras[camera]);
            let mut problem = problem(&scene, camera, false);
            let initial = se3(&scene.initial.cameras[camera]);
            let solution = problem.solve(&initial, &tight()).unwrap();
            assert!(
                solution.verdict.is_converged(),
                "seed {seed} camera {camera}"
            );
            let h = problem.normal(&solution.pose).unwrap().hessian;
            let e = error(&solution.pose, &truth);
            let d2 = (e.transpose() * h * e)[0];
            assert!(d2 < 27.86, "seed {seed} camera {camera}: eᵀHe = {d2}");
            distances.push(d2);
        }
    }
    let mean = distances.iter().sum::<f64>() / distances.len() as f64;
    // 30 draws of χ²₆ (variance 12): the mean's deviation is 0.63.
    assert!((3.5..8.5).contains(&mean), "mean eᵀHe = {mean}");
}

/// `H` and `g` are the sums of `JᵀSᵀSJ` and `JᵀSᵀS r` over the
/// observations, each linearized by dual numbers (an independent path:
/// no generated kernel), with a full whitening matrix on the planes.
#[test]
fn normal_equations_agree_with_dual_numbers() {
    let scene = generate(&PlpConfig::room(5)).unwrap();
    let camera = 4;
    let pose = se3(&scene.initial.cameras[camera]);
    let s = DMatrix::from_row_slice(3, 3, &[2.0, 0.5, -0.3, 0.0, 1.5, 0.2, 0.0, 0.0, 3.0]);
    let mut problem = problem(&scene, camera, false);
    let (mut h, mut g, mut cost) = (Matrix6::zeros(), Vector6::zeros(), 0.0);
    let mut add = |j: &DMatrix<f64>, r: &factor_core::nalgebra::DVector<f64>, w: &DMatrix<f64>| {
        let (j, r) = (w * j, w * r);
        h += (j.transpose() * &j).fixed_view::<6, 6>(0, 0);
        g += (j.transpose() * &r).fixed_view::<6, 1>(0, 0);
        cost += 0.5 * r.norm_squared();
    };
    for o in scene
        .point_observations
        .iter()
        .filter(|o| o.camera == camera)
    {
        let [fu, fv, cu, cv] = scene.config.intrinsics;
        let factor = PointReprojection {
            intrinsics: Intrinsics::new(fu, fv, cu, cv),
            observed: o.pixel,
            pose,
            point: scene.truth.points[o.point],
        };
        let l = factor.linearize_dual_dyn().unwrap();
        add(&l.jacobians[0], &l.residual, &DMatrix::identity(2, 2));
    }
    for o in scene
        .segment_observations
        .iter()
        .filter(|o| o.camera == camera)
    {
        let [fu, fv, cu, cv] = scene.config.intrinsics;
        let segment = &scene.truth.segments[o.segment];
        let factor = LineReprojection {
            intrinsics: Intrinsics::new(fu, fv, cu, cv),
            start: o.start,
            end: o.end,
            pose,
            line: OrthonormalLine::try_from_points(&segment.start, &segment.end).unwrap(),
        };
        let l = factor.linearize_dual_dyn().unwrap();
        add(&l.jacobians[0], &l.residual, &DMatrix::identity(2, 2));
    }
    for o in scene
        .plane_observations
        .iter()
        .filter(|o| o.camera == camera)
    {
        let p = scene.truth.planes[o.plane];
        let factor = PlaneFactor {
            measured: Unit::new_normalize(o.measured),
            pose,
            plane: InfinitePlane::from_normal_offset(&p.xyz(), p.w),
        };
        problem
            .add(&factor, &Noise::SqrtInformation(s.clone()))
            .unwrap();
        let l = factor.linearize_dual_dyn().unwrap();
        add(&l.jacobians[0], &l.residual, &s);
    }
    let normal = problem.normal(&pose).unwrap();
    assert!(
        (normal.cost - cost).abs() <= 1e-12 * cost,
        "{} vs {cost}",
        normal.cost
    );
    assert!((normal.gradient - g).norm() <= 1e-11 * g.norm());
    assert!((normal.hessian - h).norm() <= 1e-11 * h.norm());
}

/// Two points leave the pose free along 2 of its 6 directions: refused at
/// the start, naming the counts; no observations at all is its own error;
/// a factor without a pose, or perturbing it on the other side, is refused
/// when added.
#[test]
fn an_undetermined_pose_is_refused() {
    let scene = generate(&PlpConfig::room(1).noise_free()).unwrap();
    let [fu, fv, cu, cv] = scene.config.intrinsics;
    let mut problem = PoseProblem::new();
    let initial = se3(&scene.initial.cameras[0]);
    for o in scene
        .point_observations
        .iter()
        .filter(|o| o.camera == 0)
        .take(2)
    {
        let factor = PointReprojection {
            intrinsics: Intrinsics::new(fu, fv, cu, cv),
            observed: o.pixel,
            pose: initial,
            point: scene.truth.points[o.point],
        };
        problem.add(&factor, &Noise::Sigma(1.0)).unwrap();
    }
    match problem.solve(&initial, &Options::default()) {
        Err(PoseError::Underdetermined {
            observations: 2,
            rows: 4,
            ratio,
        }) => assert!(ratio < 1e-12, "{ratio}"),
        other => panic!("{other:?}"),
    }
    let error = PoseProblem::new()
        .solve(&initial, &Options::default())
        .unwrap_err();
    assert_eq!(error, PoseError::NoObservations);
    // `between` relates two `Se3RhoTheta` poses: no `Se3` pose.
    let between = slam_factors::BetweenFactor::from_scalars(
        &[0.0; <slam_factors::BetweenFactor as Storage<f64>>::SCALARS],
    );
    let error = PoseProblem::new().add(&between, &Noise::Unit).unwrap_err();
    assert_eq!(
        error,
        PoseError::NoPose {
            factor: "between",
            found: 0
        }
    );
    // Every observation undefined at the initial pose (its point behind
    // the camera): the first one's error, not a singular matrix of none.
    let mut behind = PoseProblem::new();
    for k in 0..3 {
        let factor = PointReprojection {
            intrinsics: Intrinsics::new(fu, fv, cu, cv),
            observed: nalgebra::Vector2::new(320.0, 240.0),
            pose: Se3::identity(),
            point: nalgebra::Vector3::new(f64::from(k), 0.0, -5.0),
        };
        behind.add(&factor, &Noise::Unit).unwrap();
    }
    match behind.solve(&Se3::identity(), &Options::default()) {
        Err(PoseError::Observation { observation: 0, .. }) => {}
        other => panic!("{other:?}"),
    }
    // A noise model that does not fit the residual, named by the model's
    // own check; nothing is added.
    let point = slam_factors::PointReprojection::from_scalars(
        &[0.5; <slam_factors::PointReprojection as Storage<f64>>::SCALARS],
    );
    let before = problem.len();
    for (noise, reason) in [
        (
            Noise::Sigmas(vec![1.0; 3]),
            "3 standard deviations for a residual of 2",
        ),
        (
            Noise::Sigma(-1.0),
            "standard deviation -1 is not a finite number above 0",
        ),
    ] {
        let error = problem.add(&point, &noise).unwrap_err();
        assert_eq!(
            error,
            PoseError::Noise {
                factor: "point_reprojection",
                reason: reason.into()
            }
        );
    }
    assert_eq!(problem.len(), before);
    // The free line's body pose is perturbed on the right, the point
    // reprojection's pose on the left.
    let free_line = slam_factors::FreeLineFactor::from_scalars(
        &[0.5; <slam_factors::FreeLineFactor as Storage<f64>>::SCALARS],
    );
    let error = problem.add(&free_line, &Noise::Unit).unwrap_err();
    assert_eq!(
        error,
        PoseError::MixedSides {
            factor: "free_line"
        }
    );
}

/// Ten cameras 36° apart, each started from the previous camera's true
/// pose (noise-free): landmarks behind the starting camera are deferred to
/// a second solve, and every camera still comes back to its true pose.
#[test]
fn observations_behind_the_start_are_deferred() {
    let scene = generate(&PlpConfig {
        cameras: 10,
        ..PlpConfig::room(2).noise_free()
    })
    .unwrap();
    let mut deferred = 0;
    for camera in 1..scene.truth.cameras.len() {
        let truth = se3(&scene.truth.cameras[camera]);
        let mut problem = problem(&scene, camera, true);
        let start = se3(&scene.truth.cameras[camera - 1]);
        let solution = problem.solve(&start, &tight()).unwrap();
        assert!(
            solution.verdict.is_converged(),
            "camera {camera}: {solution:?}"
        );
        let e = error(&solution.pose, &truth).norm();
        assert!(e < 1e-9, "camera {camera}: error {e}");
        deferred += solution.deferred;
        if solution.deferred > 0 {
            assert!(solution.initial_cost.is_nan());
        }
    }
    assert!(deferred > 0, "no observation was behind a starting camera");
}

/// How well the observations determine the pose does not depend on their
/// weights: one observation of σ = 1e-90 among the frame's others (which
/// made the Gauss–Newton matrix itself look singular, its smallest
/// eigenvalue 1e-17 of its largest) does not make the frame undetermined.
#[test]
fn a_heavily_weighted_observation_leaves_the_pose_determined() {
    let scene = generate(&PlpConfig::room(1).noise_free()).unwrap();
    let [fu, fv, cu, cv] = scene.config.intrinsics;
    let initial = se3(&scene.initial.cameras[0]);
    let mut problem = PoseProblem::new();
    let seen = scene.point_observations.iter().filter(|o| o.camera == 0);
    for (k, o) in seen.enumerate() {
        let factor = PointReprojection {
            intrinsics: Intrinsics::new(fu, fv, cu, cv),
            observed: o.pixel,
            pose: initial,
            point: scene.truth.points[o.point],
        };
        let sigma = if k == 0 { 1e-90 } else { 1.0 };
        problem.add(&factor, &Noise::Sigma(sigma)).unwrap();
    }
    let solution = problem.solve(&initial, &Options::default()).unwrap();
    // In `H` itself the other rows are below the rounding of that one's
    // (1e180 times theirs): f64 cannot solve for the steps, and the
    // verdict says so rather than calling the pose undetermined.
    assert!(
        matches!(&solution.verdict, Verdict::Failed(why) if why.contains("cannot be factorized")),
        "{solution:?}"
    );
}
