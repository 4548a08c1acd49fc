//! Per-factor noise models and losses (`Problem::add_weighted`), checked
//! against what they mean rather than against this solver's other paths
//! alone:
//!
//! - the initial cost is `Σ ½ ρ(‖S r‖²)` computed here from each factor's
//!   own residual (`Factor::residual_dyn`);
//! - an isotropic `σ` scales the cost by `1/σ²` and leaves the optimum
//!   where it was;
//! - a square-root information `R/σ` with `R` a rotation, and deviations
//!   `[σ, σ]`, are the same noise as `σ` (`‖R r‖ = ‖r‖`), but take the
//!   whitened path (the Jacobian kernel, `S r` and `S J`) rather than the
//!   fused kernel's scalar weight: the same optimum and the same values;
//! - a loss given per factor is the problem's loss for that factor;
//! - mixed per-factor noise and losses reach apex-solver's optimum under
//!   the same models (`factor_apex::builder`, an independent solver);
//! - factors linearized one at a time (`Problem::add_linearized`, through
//!   the factor's kernel or by dual numbers) give the batch kernels' costs
//!   and optimum under every model.

use factor_apex::builder::ProblemBuilder;
use factor_core::Factor;
use factor_core::Storage;
use factor_core::lie::Se3RhoTheta;
use factor_core::noise::Noise;
use factor_minimizer::{SolveOptions, Verdict};
use factor_schur::{Jacobians, Problem, SchurError, Solver, VariableId};
use nalgebra::{DMatrix, Rotation2};
use slam_data::BalProblem;
use slam_data::synthetic::{SyntheticConfig, generate};
use slam_problems::Robust;
use slam_problems::bundle::{camera_pose, factor_of};

fn bal() -> BalProblem {
    let config = SyntheticConfig {
        cameras: 8,
        points: 90,
        views_per_point: 4,
        outlier_fraction: 0.0,
        ..SyntheticConfig::with_observations(360, 3)
    };
    generate(&config).expect("valid settings").problem
}

/// Bundle adjustment of `bal` with observation `k`'s noise `noise(k)` and
/// loss `robust(k)`: camera 0's pose and every camera's intrinsics fixed,
/// the points eliminated. Returns the problem, the points' ids and each
/// observation's variables.
fn problem(
    bal: &BalProblem,
    noise: impl Fn(usize) -> Noise,
    robust: impl Fn(usize) -> Option<Robust>,
) -> (Problem, Vec<VariableId>, Vec<[VariableId; 3]>) {
    problem_by(bal, noise, robust, None)
}

/// [`problem`] with its factors added by `jacobians`: the batch kernels
/// (`None`) or one at a time.
fn problem_by(
    bal: &BalProblem,
    noise: impl Fn(usize) -> Noise,
    robust: impl Fn(usize) -> Option<Robust>,
    jacobians: Option<Jacobians>,
) -> (Problem, Vec<VariableId>, Vec<[VariableId; 3]>) {
    let mut problem = Problem::new();
    let mut cameras = Vec::new();
    for camera in &bal.cameras {
        let pose = problem.add_variable(&Se3RhoTheta::new(camera_pose(camera)).to_scalars());
        let i = &camera.intrinsics;
        let intrinsics = problem.add_variable(&[i.focal, i.k1, i.k2]);
        problem.fix(intrinsics);
        cameras.push((pose, intrinsics));
    }
    problem.fix(cameras[0].0);
    let points: Vec<VariableId> = bal
        .points
        .iter()
        .map(|p| {
            let id = problem.add_variable(p.as_slice());
            problem.eliminate(id);
            id
        })
        .collect();
    let mut variables = Vec::with_capacity(bal.observations.len());
    for (k, o) in bal.observations.iter().enumerate() {
        let (pose, intrinsics) = cameras[o.camera];
        let ids = [pose, intrinsics, points[o.point]];
        let factor = factor_of(bal, k);
        match jacobians {
            None => problem.add_weighted(&factor, &ids, &noise(k), robust(k)),
            Some(j) => problem.add_linearized(&factor, &ids, &noise(k), robust(k), j),
        }
        .expect("fits");
        variables.push(ids);
    }
    (problem, points, variables)
}

/// `Σ ½ ρ(‖S r‖²)` over the observations of `bal` at its values.
fn cost(
    bal: &BalProblem,
    s: impl Fn(usize) -> DMatrix<f64>,
    robust: impl Fn(usize) -> Option<Robust>,
) -> f64 {
    (0..bal.observations.len())
        .map(|k| {
            let r = factor_of(bal, k).residual_dyn().expect("valid");
            let q = (s(k) * r).norm_squared();
            let rho = match robust(k) {
                None => q,
                Some(Robust::Huber(d)) if q > d * d => 2.0 * d * q.sqrt() - d * d,
                Some(Robust::Huber(_)) => q,
                Some(Robust::Cauchy(d)) => d * d * (q / (d * d)).ln_1p(),
            };
            0.5 * rho
        })
        .sum()
}

/// `(initial, final)` costs of apex-solver's solve of the same problem as
/// [`problem`]'s, each factor with the same noise and loss.
fn apex(
    bal: &BalProblem,
    noise: impl Fn(usize) -> Noise,
    robust: impl Fn(usize) -> Option<Robust>,
) -> (f64, f64) {
    let mut builder = ProblemBuilder::new();
    // Each camera's variables, from its first observation's factor.
    let mut cameras = vec![None; bal.cameras.len()];
    let mut points = vec![None; bal.points.len()];
    for (k, o) in bal.observations.iter().enumerate() {
        let factor = factor_of(bal, k);
        if cameras[o.camera].is_none() {
            let pose = builder.add_variable_of(&factor, 0);
            let intrinsics = builder.add_variable_of(&factor, 1);
            builder.fix_any(&intrinsics).expect("fixes");
            if o.camera == 0 {
                builder.fix_any(&pose).expect("fixes");
            }
            cameras[o.camera] = Some((pose, intrinsics));
        }
        let point = points[o.point]
            .get_or_insert_with(|| builder.add_variable_of(&factor, 2))
            .clone();
        let (pose, intrinsics) = cameras[o.camera].clone().expect("added");
        builder
            .add_factor(&factor, &[pose, intrinsics, point], &noise(k), robust(k))
            .expect("fits");
    }
    let mut built = builder.build().expect("builds");
    let outcome = factor_apex::solve::solve(&mut built, &SolveOptions::converged(500), |_| {})
        .expect("solves");
    assert!(
        matches!(outcome.verdict(), Verdict::Converged(_)),
        "{:?}",
        outcome.verdict()
    );
    (outcome.initial_cost, outcome.final_cost)
}

/// Solves to convergence; `(initial, final)` costs.
fn solve(problem: &mut Problem) -> (f64, f64) {
    let solver = Solver::new(problem).expect("starts");
    let outcome = solver.run(&SolveOptions::converged(500), |_| {});
    assert!(
        matches!(outcome.verdict, Verdict::Converged(_)),
        "{:?}",
        outcome.verdict
    );
    (outcome.initial_cost, outcome.final_cost)
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

/// The largest difference between the points of two solved problems.
fn point_gap(
    a: &(Problem, Vec<VariableId>, Vec<[VariableId; 3]>),
    b: &(Problem, Vec<VariableId>, Vec<[VariableId; 3]>),
) -> f64 {
    a.1.iter()
        .zip(&b.1)
        .flat_map(|(&x, &y)| {
            a.0.value(x)
                .iter()
                .zip(b.0.value(y))
                .map(|(p, q)| (p - q).abs())
                .collect::<Vec<_>>()
        })
        .fold(0.0, f64::max)
}

#[test]
fn isotropic_rotated_and_per_component_noise_of_one_sigma_agree() {
    let bal = bal();
    let sigma = 2.0;
    let rotation = |k: usize| {
        let r = Rotation2::new(0.37 * k as f64 + 0.1);
        DMatrix::from_fn(2, 2, |i, j| r[(i, j)] / sigma)
    };
    let none = |_| None;
    let mut unit = problem(&bal, |_| Noise::Unit, none);
    let mut isotropic = problem(&bal, |_| Noise::Sigma(sigma), none);
    let mut rotated = problem(&bal, |k| Noise::SqrtInformation(rotation(k)), none);
    let mut deviations = problem(&bal, |_| Noise::Sigmas(vec![sigma, sigma]), none);
    let expected = cost(&bal, rotation, none);
    let unit_costs = solve(&mut unit.0);
    assert!(relative(unit_costs.0 / (sigma * sigma), expected) <= 1e-12);
    for (what, p) in [
        ("sigma", &mut isotropic),
        ("rotated sqrt_information", &mut rotated),
        ("sigmas", &mut deviations),
    ] {
        let (initial, last) = solve(&mut p.0);
        assert!(
            relative(initial, expected) <= 1e-12,
            "{what}: initial {initial} vs {expected}"
        );
        // The same optimum, scaled by 1/σ², at the same points.
        assert!(
            relative(last, unit_costs.1 / (sigma * sigma)) <= 1e-9,
            "{what}: final {last} vs {}",
            unit_costs.1 / (sigma * sigma)
        );
    }
    for (what, p) in [("rotated", &rotated), ("sigmas", &deviations)] {
        let gap = point_gap(p, &unit);
        assert!(gap <= 1e-6, "{what}: points {gap} from the unit solve's");
    }
}

#[test]
fn per_component_and_mixed_noise_weigh_each_component() {
    let bal = bal();
    // Every third factor isotropic, the others per component: one group,
    // turned from scales into full matrices part-way through.
    let noise = |k: usize| {
        if k.is_multiple_of(3) {
            Noise::Sigma(0.5)
        } else {
            Noise::Sigmas(vec![1.0, 4.0])
        }
    };
    let s = |k: usize| match noise(k) {
        Noise::Sigma(x) => DMatrix::identity(2, 2) / x,
        Noise::Sigmas(x) => DMatrix::from_diagonal(&nalgebra::DVector::from_vec(
            x.iter().map(|v| 1.0 / v).collect(),
        )),
        _ => unreachable!(),
    };
    let none = |_| None;
    let expected = cost(&bal, s, none);
    let mut p = problem(&bal, noise, none);
    let (initial, last) = solve(&mut p.0);
    assert!(
        relative(initial, expected) <= 1e-12,
        "initial {initial} vs {expected}"
    );
    let (apex_initial, apex_last) = apex(&bal, noise, none);
    assert!(
        relative(apex_initial, expected) <= 1e-12,
        "apex initial {apex_initial}"
    );
    assert!(
        relative(last, apex_last) <= 1e-9,
        "final {last} vs apex {apex_last}"
    );
}

#[test]
fn a_loss_per_factor_is_the_problems_loss_for_it() {
    let mut bal = bal();
    // Ten gross outliers, so that the loss matters.
    for o in bal.observations.iter_mut().step_by(36) {
        o.pixel.x += 80.0;
    }
    let huber = Some(Robust::Huber(1.5));
    let mut own = problem(&bal, |_| Noise::Unit, |_| huber);
    let mut shared = problem(&bal, |_| Noise::Unit, |_| None);
    shared.0.set_robust(huber);
    let identity = |_| DMatrix::identity(2, 2);
    let expected = cost(&bal, identity, |_| huber);
    let a = solve(&mut own.0);
    let b = solve(&mut shared.0);
    assert!(relative(a.0, expected) <= 1e-12, "{} vs {expected}", a.0);
    assert!(relative(a.1, b.1) <= 1e-12, "{} vs {}", a.1, b.1);
    // A loss on the outliers alone: least squares elsewhere.
    let outlier = |k: usize| k.is_multiple_of(36).then_some(Robust::Cauchy(2.0));
    let mut mixed = problem(&bal, |_| Noise::Unit, outlier);
    let c = solve(&mut mixed.0);
    let expected = cost(&bal, identity, outlier);
    assert!(relative(c.0, expected) <= 1e-12, "{} vs {expected}", c.0);
    // A robust cost is not convex in the outliers: apex-solver's optimum
    // or a lower one (as the agreement tests ask).
    let (_, apex_last) = apex(&bal, |_| Noise::Unit, outlier);
    assert!(
        c.1 <= apex_last * (1.0 + 1e-9),
        "final {} vs apex {apex_last}",
        c.1
    );
}

#[test]
fn factors_linearized_one_at_a_time_reach_the_batch_kernels_optimum() {
    let mut bal = bal();
    for o in bal.observations.iter_mut().step_by(36) {
        o.pixel.x += 80.0;
    }
    // Isotropic, per-component and full models in one group, and a loss
    // on some factors.
    let noise = |k: usize| match k % 3 {
        0 => Noise::Sigma(0.5),
        1 => Noise::Sigmas(vec![1.0, 4.0]),
        _ => Noise::SqrtInformation(DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.0, 1.0])),
    };
    let s = |k: usize| match noise(k) {
        Noise::Sigma(x) => DMatrix::identity(2, 2) / x,
        Noise::Sigmas(x) => DMatrix::from_diagonal(&nalgebra::DVector::from_vec(
            x.iter().map(|v| 1.0 / v).collect(),
        )),
        Noise::SqrtInformation(m) => m,
        _ => unreachable!(),
    };
    let robust = |k: usize| k.is_multiple_of(4).then_some(Robust::Huber(1.5));
    let expected = cost(&bal, s, robust);
    let mut batch = problem_by(&bal, noise, robust, None);
    let (_, optimum) = solve(&mut batch.0);
    for jacobians in [Jacobians::Kernel, Jacobians::Dual] {
        let mut each = problem_by(&bal, noise, robust, Some(jacobians));
        let (initial, last) = solve(&mut each.0);
        assert!(
            relative(initial, expected) <= 1e-12,
            "{jacobians:?}: initial {initial} vs {expected}"
        );
        assert!(
            relative(last, optimum) <= 1e-9,
            "{jacobians:?}: final {last} vs the batch kernels' {optimum}"
        );
        let gap = point_gap(&each, &batch);
        assert!(gap <= 1e-6, "{jacobians:?}: points {gap} from the batch's");
    }
}

#[test]
fn noise_that_does_not_fit_is_refused_and_nothing_is_added() {
    let bal = bal();
    let (mut problem, _, observed) = problem(&bal, |_| Noise::Unit, |_| None);
    let before = problem.factor_count();
    let factor = factor_of(&bal, 0);
    let variables = observed[0];
    for (noise, says) in [
        (Noise::Sigmas(vec![1.0]), "1 standard deviations"),
        (Noise::Sigma(0.0), "not a finite number above 0"),
        (Noise::Sigma(f64::NAN), "not a finite number above 0"),
        (Noise::SqrtInformation(DMatrix::identity(3, 3)), "3×3"),
        (
            Noise::SqrtInformation(DMatrix::from_element(2, 2, f64::INFINITY)),
            "not finite",
        ),
    ] {
        let error = problem
            .add_weighted(&factor, &variables, &noise, None)
            .unwrap_err();
        assert!(
            matches!(&error, SchurError::Noise { .. }) && error.to_string().contains(says),
            "{noise:?}: {error}"
        );
        assert_eq!(problem.factor_count(), before, "{noise:?}");
    }
}
