//! A user's factors over manifolds of their own, solved by apex-solver end
//! to end through the public problem API (`factor_apex::builder`): the
//! factors of the example crate `user-factors` over its `Sim3` (served as
//! apex's `SE3 × Rn(1)`) and its S² `UnitVector3` (served as `Rn(3)`),
//! through their generated apex kernels, and a factor written here over a
//! calibration manifold of this file's own, `SE(3) × ℝ`, through dual
//! numbers.

use factor_apex::builder::{Noise, ProblemBuilder};
use factor_apex::solve::{SolveOptions, Verdict, solve};
use factor_core::host::{Apex, ApexManifold, HostMap, HostPart};
use factor_core::lie::{Se3, So3};
use factor_core::{Factor, Layout, Manifold, Perturbation, Scalar, Storage};
use nalgebra::Vector3;
use user_factors::manifold_factors::{Direction, RelativeSim3};
use user_factors::sim3::Sim3;
use user_factors::unit_vector::UnitVector3;

fn sim3(rotation: [f64; 3], translation: [f64; 3], log_scale: f64) -> Sim3<f64> {
    Sim3::new(
        So3::exp(&Vector3::from(rotation)),
        Vector3::from(translation),
        log_scale,
    )
}

/// A loop of five similarity transforms with scale drift, measured without
/// noise (four odometry edges and a loop closure), started from perturbed
/// values with the first held fixed: the solve recovers every transform.
#[test]
fn a_sim3_loop_is_solved_in_apex_through_the_generated_kernels() {
    let truth: Vec<Sim3<f64>> = (0..5)
        .map(|k| {
            let a = k as f64;
            sim3(
                [0.1 * a, -0.05 * a, 0.3 * a],
                [a, 0.5 * a * a, -0.2 * a],
                0.05 * a,
            )
        })
        .collect();
    let perturbation = sim3([0.03, -0.02, 0.04], [0.1, -0.1, 0.05], 0.02);
    let mut problem = ProblemBuilder::new();
    let variables: Vec<_> = truth
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let start = if k == 0 { *s } else { s.compose(&perturbation) };
            problem.add_variable(&start)
        })
        .collect();
    problem.fix_variable(&variables[0]).expect("fixable");
    let edges = [(0, 1), (1, 2), (2, 3), (3, 4), (4, 0)];
    for (i, j) in edges {
        let factor = RelativeSim3 {
            measured: truth[i].inverse().compose(&truth[j]),
            sim_i: truth[i].compose(&perturbation),
            sim_j: truth[j].compose(&perturbation),
        };
        problem
            .add_factor(
                &factor,
                &[variables[i].erase(), variables[j].erase()],
                &Noise::Unit,
                None,
            )
            .expect("servable");
    }
    let mut built = problem.build().expect("built");
    assert!(built.initial_cost > 1e-3, "{}", built.initial_cost);
    let outcome = solve(&mut built, &SolveOptions::converged(100), |_| {}).expect("solved");
    assert!(matches!(outcome.verdict(), Verdict::Converged(_)));
    assert!(outcome.final_cost < 1e-20, "{}", outcome.final_cost);
    for (variable, expected) in variables.iter().zip(&truth) {
        let estimate: Sim3<f64> = outcome.value(variable);
        let error = expected.inverse().compose(&estimate).log().norm();
        assert!(error < 1e-9, "{error:e}");
    }
}

/// A world direction (S²) seen by three sensors of known orientation,
/// started 0.3 rad away: the solve recovers it.
#[test]
fn a_direction_on_s2_is_solved_in_apex_through_the_generated_kernel() {
    let truth = UnitVector3::from_direction(&Vector3::new(0.3, -0.5, 0.8));
    let start = UnitVector3::from_direction(&Vector3::new(0.5, -0.4, 0.8));
    let mut problem = ProblemBuilder::new();
    let direction = problem.add_variable(&start);
    for angles in [[0.1, 0.2, -0.3], [-0.4, 0.1, 0.2], [0.3, -0.3, 0.5]] {
        let orientation = So3::exp(&Vector3::from(angles));
        let sensor = problem.add_variable(&orientation);
        problem.fix_variable(&sensor).expect("fixable");
        let factor = Direction {
            measured: UnitVector3::from_direction(&orientation.rotate(&truth.vector())),
            orientation,
            direction: start,
        };
        problem
            .add_factor(
                &factor,
                &[sensor.erase(), direction.erase()],
                &Noise::Sigma(0.01),
                None,
            )
            .expect("servable");
    }
    let mut built = problem.build().expect("built");
    let outcome = solve(&mut built, &SolveOptions::converged(100), |_| {}).expect("solved");
    let estimate: UnitVector3<f64> = outcome.value(&direction);
    assert!(
        (estimate.vector() - truth.vector()).norm() < 1e-9,
        "{:?}",
        estimate.vector()
    );
}

/// A camera–IMU calibration: the extrinsic pose and a time offset, a
/// manifold `SE(3) × ℝ` written in this file, as a user would.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Calibration<S> {
    extrinsics: Se3<S>,
    time_offset: S,
}

impl<S: Scalar> Storage<S> for Calibration<S> {
    type With<T: Scalar> = Calibration<T>;
    const SCALARS: usize = 8;
    fn layout() -> Layout {
        Layout::Record(vec![
            ("extrinsics", Se3::<S>::layout()),
            ("time_offset", Layout::Scalar),
        ])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Calibration<T> {
        let extrinsics = self.extrinsics.map_scalars(f);
        Calibration {
            extrinsics,
            time_offset: f(self.time_offset),
        }
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        let extrinsics = Se3::read_scalars(next);
        Calibration {
            extrinsics,
            time_offset: next(),
        }
    }
}

/// Tangent `[δω, δρ, δτ]`: the pose's (on the factor's side) and the offset's.
impl<S: Scalar> Manifold<S> for Calibration<S> {
    const DIM: usize = 7;
    fn retract(&self, delta: &[S], side: Perturbation) -> Self {
        Calibration {
            extrinsics: self.extrinsics.retract(&delta[..6], side),
            time_offset: self.time_offset + delta[6],
        }
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "[δω, δρ] of the extrinsic pose, then δτ of the time offset"
    }
}

/// Served to apex as its `SE3` and an `Rn(1)`.
impl<S: Scalar> HostMap<Apex> for Calibration<S> {
    const PARTS: &'static [HostPart<ApexManifold>] = &[
        HostPart::named("extrinsics", ApexManifold::Se3),
        HostPart::named("time_offset", ApexManifold::Rn(1)),
    ];
    fn stored_from_host<T: Scalar>(host: &[T], stored: &mut [T]) {
        <Se3<S> as HostMap<Apex>>::stored_from_host(&host[..7], &mut stored[..7]);
        stored[7] = host[7];
    }
    fn host_from_stored(stored: &[f64], host: &mut [f64]) {
        <Se3<S> as HostMap<Apex>>::host_from_stored(&stored[..7], &mut host[..7]);
        host[7] = stored[7];
    }
}

/// A point seen in the IMU frame at time `t`, moving with velocity `v`:
/// predicted in the camera frame through the extrinsics at `t + τ`,
/// `r = T_CI (p + (t + τ) v) − observed`.
#[derive(Debug, Clone, Factor)]
#[factor(residual = timed_point_residual, dim = 3)]
struct TimedPoint<S: Scalar = f64> {
    point: Vector3<S>,
    velocity: Vector3<S>,
    time: S,
    observed: Vector3<S>,
    #[variable(left)]
    calibration: Calibration<S>,
}

fn timed_point_residual<S: Scalar>(f: &TimedPoint<S>) -> Vector3<S> {
    let t = f.time + f.calibration.time_offset;
    let moved = f.point + f.velocity.map(|v| v * t);
    f.calibration.extrinsics.transform_point(&moved) - f.observed
}

/// The calibration recovered from noise-free observations of moving
/// points, through dual numbers in apex's chart (no generated kernel).
#[test]
fn a_custom_calibration_manifold_is_solved_in_apex_through_dual_numbers() {
    let truth = Calibration {
        extrinsics: Se3::new(
            So3::exp(&Vector3::new(0.05, -0.1, 0.2)),
            Vector3::new(0.1, 0.02, -0.05),
        ),
        time_offset: 0.013,
    };
    let start = Calibration {
        extrinsics: Se3::new(So3::identity(), Vector3::zeros()),
        time_offset: 0.0,
    };
    let mut problem = ProblemBuilder::new();
    let calibration = problem.add_variable(&start);
    for k in 0..12 {
        let a = k as f64;
        let (point, velocity, time) = (
            Vector3::new(a.sin(), a.cos(), 2.0 + 0.1 * a),
            Vector3::new(0.5 * a.cos(), 0.2, -0.3 * a.sin()),
            0.05 * a,
        );
        let mut factor = TimedPoint {
            point,
            velocity,
            time,
            observed: Vector3::zeros(),
            calibration: truth,
        };
        factor.observed =
            Vector3::from_column_slice(factor.residual_dyn().expect("valid").as_slice());
        factor.calibration = start;
        problem
            .add_factor_dual(&factor, &[calibration.erase()], &Noise::Unit, None)
            .expect("servable");
    }
    let mut built = problem.build().expect("built");
    let outcome = solve(&mut built, &SolveOptions::converged(100), |_| {}).expect("solved");
    let estimate: Calibration<f64> = outcome.value(&calibration);
    let pose_error = truth.extrinsics.inverse().compose(&estimate.extrinsics);
    assert!(pose_error.translation.norm() < 1e-9, "{pose_error:?}");
    assert!(
        So3::log(&pose_error.rotation).norm() < 1e-9,
        "{pose_error:?}"
    );
    assert!((estimate.time_offset - truth.time_offset).abs() < 1e-9);
}

/// A variable of another type than the factor's is refused, naming both.
#[test]
fn a_variable_of_the_wrong_type_is_refused() {
    let mut problem = ProblemBuilder::new();
    let wrong = problem.add_variable(&Vector3::new(0.0, 0.0, 1.0));
    let sensor = problem.add_variable(&So3::<f64>::identity());
    let factor = Direction {
        measured: UnitVector3::from_direction(&Vector3::new(0.0, 0.0, 1.0)),
        orientation: So3::identity(),
        direction: UnitVector3::from_direction(&Vector3::new(0.0, 0.0, 1.0)),
    };
    let error = problem
        .add_factor(
            &factor,
            &[sensor.erase(), wrong.erase()],
            &Noise::Unit,
            None,
        )
        .expect_err("a Vector3 is not a UnitVector3");
    let message = error.to_string();
    assert!(
        message.contains("`direction`")
            && message.contains("UnitVector3")
            && message.contains("Matrix"),
        "{message}"
    );
}
