//! The loop on small problems whose minima and failures are known in
//! closed form: Rosenbrock's function as least squares, a model whose
//! factorization always fails, one whose trials a factor always refuses,
//! and the iteration limit.

use std::time::Instant;

use factor_minimizer::{
    Criterion, Damped, Damping, Linearization, Minimized, Model, Prediction, SolveOptions, Trial,
    Verdict, minimize,
};

/// Rosenbrock's function as least squares, `r = (10 (y − x²), 1 − x)`:
/// its minimum is `(1, 1)` with cost 0, reached through a curved valley.
struct Rosenbrock {
    x: [f64; 2],
    step: [f64; 2],
    /// Trials to refuse (a factor's refusal) before any is evaluated.
    refuse: usize,
    /// Whether every damped system fails to factorize.
    singular: bool,
}

impl Rosenbrock {
    fn at(x: [f64; 2]) -> Self {
        Rosenbrock {
            x,
            step: [0.0; 2],
            refuse: 0,
            singular: false,
        }
    }

    fn residual(x: [f64; 2]) -> [f64; 2] {
        [10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]]
    }

    fn cost(x: [f64; 2]) -> f64 {
        let r = Self::residual(x);
        0.5 * (r[0] * r[0] + r[1] * r[1])
    }

    /// `H = JᵀJ` (row-major 2 × 2) and `g = Jᵀr` at the current values.
    fn normal(&self) -> ([f64; 4], [f64; 2]) {
        let [a, b] = self.x;
        let r = Self::residual([a, b]);
        // J = [[-20a, 10], [-1, 0]].
        let j = [-20.0 * a, 10.0, -1.0, 0.0];
        let h = [
            j[0] * j[0] + j[2] * j[2],
            j[0] * j[1] + j[2] * j[3],
            j[1] * j[0] + j[3] * j[2],
            j[1] * j[1] + j[3] * j[3],
        ];
        let g = [j[0] * r[0] + j[2] * r[1], j[1] * r[0] + j[3] * r[1]];
        (h, g)
    }
}

impl Model for Rosenbrock {
    fn linearize(&mut self, cost: f64, bounds: (f64, f64)) -> Linearization {
        let (h, g) = self.normal();
        Linearization::read([(h[0], g[0]), (h[3], g[1])], cost, bounds)
    }

    fn solve_damped(&mut self, damped: Damped) -> Option<Prediction> {
        if self.singular {
            return None;
        }
        let (h, g) = self.normal();
        let (a, d) = (h[0] + damped.of(h[0]), h[3] + damped.of(h[3]));
        let det = a * d - h[1] * h[2];
        if !(det > 0.0 && a > 0.0) {
            return None;
        }
        self.step = [
            -(d * g[0] - h[1] * g[1]) / det,
            -(-h[2] * g[0] + a * g[1]) / det,
        ];
        let s = self.step;
        Some(Prediction {
            g_delta: g[0] * s[0] + g[1] * s[1],
            h_delta: s[0] * (h[0] * s[0] + h[1] * s[1]) + s[1] * (h[2] * s[0] + h[3] * s[1]),
        })
    }

    fn evaluate_step(&mut self) -> Trial {
        if self.refuse > 0 {
            self.refuse -= 1;
            return Trial::Refused("the candidate is behind the camera".into());
        }
        Trial::Cost(Self::cost([
            self.x[0] + self.step[0],
            self.x[1] + self.step[1],
        ]))
    }

    fn accept(&mut self) {
        self.x = [self.x[0] + self.step[0], self.x[1] + self.step[1]];
    }

    fn step_norm(&self) -> f64 {
        self.step[0].hypot(self.step[1])
    }

    fn parameter_norm(&self) -> f64 {
        self.x[0].hypot(self.x[1])
    }
}

const START: [f64; 2] = [-1.2, 1.0];

/// `model` minimized from its values with `options` and the diagonal
/// damping.
fn run(model: &mut Rosenbrock, options: &SolveOptions) -> Minimized {
    let cost = Rosenbrock::cost(model.x);
    minimize(
        model,
        cost,
        Instant::now(),
        Damping::Diagonal,
        options,
        |_| {},
    )
}

#[test]
fn rosenbrock_reaches_its_minimum_through_the_valley() {
    for damping in [Damping::Diagonal, Damping::Uniform] {
        let mut model = Rosenbrock::at(START);
        let initial = Rosenbrock::cost(START);
        let minimized = minimize(
            &mut model,
            initial,
            Instant::now(),
            damping,
            &SolveOptions::default(),
            |_| {},
        );
        assert!(
            minimized.verdict.is_converged(),
            "{damping:?}: {minimized:?}"
        );
        assert!(
            (model.x[0] - 1.0).abs() < 1e-6 && (model.x[1] - 1.0).abs() < 1e-6,
            "{damping:?}: {:?}",
            model.x
        );
        assert_eq!(minimized.final_cost, Rosenbrock::cost(model.x));
        // Every report is consistent with the one before it: a rejected
        // step keeps the cost, an accepted one lowers it.
        let mut cost = initial;
        for (k, iteration) in minimized.history.iter().enumerate() {
            assert_eq!(iteration.index, k);
            if iteration.accepted {
                assert!(iteration.cost < cost, "{iteration:?}");
            } else {
                assert_eq!(iteration.cost, cost, "{iteration:?}");
            }
            cost = iteration.cost;
        }
    }
}

#[test]
fn the_iteration_limit_is_a_verdict_of_its_own() {
    let mut model = Rosenbrock::at(START);
    let options = SolveOptions {
        max_iterations: 3,
        ..SolveOptions::default()
    };
    let minimized = run(&mut model, &options);
    assert_eq!(minimized.verdict, Verdict::IterationLimit);
    assert_eq!(minimized.history.len(), 3);
    assert!(!minimized.verdict.is_converged());
}

#[test]
fn a_system_that_never_factorizes_fails_at_any_damping() {
    let mut model = Rosenbrock::at(START);
    model.singular = true;
    let minimized = run(&mut model, &SolveOptions::default());
    match &minimized.verdict {
        Verdict::Failed(why) => {
            assert!(why.contains("cannot be factorized at any damping"), "{why}")
        }
        other => panic!("{other:?}"),
    }
    assert!(
        minimized
            .history
            .iter()
            .all(|i| !i.accepted && i.step_quality.is_none())
    );
    assert_eq!(model.x, START);
}

#[test]
fn steps_a_factor_always_refuses_end_as_refused_with_its_message() {
    let mut model = Rosenbrock::at(START);
    model.refuse = usize::MAX;
    let minimized = run(&mut model, &SolveOptions::default());
    assert_eq!(
        minimized.verdict,
        Verdict::Refused("the candidate is behind the camera".into())
    );
    assert_eq!(model.x, START);
}

#[test]
fn a_few_refused_trials_raise_the_damping_and_the_solve_goes_on() {
    let mut model = Rosenbrock::at(START);
    model.refuse = 3;
    let minimized = run(&mut model, &SolveOptions::default());
    assert!(minimized.verdict.is_converged(), "{minimized:?}");
    assert!((model.x[0] - 1.0).abs() < 1e-6 && (model.x[1] - 1.0).abs() < 1e-6);
    let damping: Vec<f64> = minimized.history[..3]
        .iter()
        .map(|i| i.damping.unwrap())
        .collect();
    assert!(
        damping[0] < damping[1] && damping[1] < damping[2],
        "{damping:?}"
    );
}

#[test]
fn a_criterion_names_its_tolerance() {
    let options = SolveOptions::default();
    assert_eq!(
        Criterion::CostTolerance.verdict(&options).to_string(),
        "converged (the last step decreased the cost by less than 1e-8 of it)"
    );
    assert_eq!(
        Verdict::IterationLimit.to_string(),
        "stopped at the iteration limit, not converged"
    );
}

#[test]
fn an_initial_cost_that_is_not_finite_fails_at_once() {
    for initial in [f64::NAN, f64::INFINITY, -1.0] {
        let mut model = Rosenbrock::at(START);
        let minimized = minimize(
            &mut model,
            initial,
            Instant::now(),
            Damping::Diagonal,
            &SolveOptions::default(),
            |_| {},
        );
        assert_eq!(
            minimized.verdict,
            Verdict::Failed(format!("the initial cost is {initial}"))
        );
        assert!(minimized.history.is_empty());
        assert_eq!(model.x, START);
    }
}

/// A zero residual from the start: one rejected step (nothing to gain),
/// then the residual's cosine with the Jacobian (0 of 0 counts 0) ends it.
#[test]
fn a_zero_initial_cost_converges() {
    let mut model = Rosenbrock::at([1.0, 1.0]);
    let minimized = run(&mut model, &SolveOptions::default());
    assert!(minimized.verdict.is_converged(), "{minimized:?}");
    assert_eq!(minimized.final_cost, 0.0);
    assert_eq!(model.x, [1.0, 1.0]);
}

/// A criterion met at the last iteration the limit allows is the verdict:
/// a limit of exactly the iterations an unlimited solve takes converges.
#[test]
fn a_criterion_met_at_the_last_allowed_iteration_converges() {
    let mut unlimited = Rosenbrock::at(START);
    let all = run(&mut unlimited, &SolveOptions::default());
    assert!(all.verdict.is_converged(), "{all:?}");
    let options = SolveOptions {
        max_iterations: all.history.len(),
        ..SolveOptions::default()
    };
    let mut limited = Rosenbrock::at(START);
    let exact = run(&mut limited, &options);
    assert_eq!(exact.verdict, all.verdict);
    assert_eq!(limited.x, unlimited.x);
    let options = SolveOptions {
        max_iterations: all.history.len() - 1,
        ..SolveOptions::default()
    };
    let short = run(&mut Rosenbrock::at(START), &options);
    assert_eq!(short.verdict, Verdict::IterationLimit);
}

#[test]
fn tolerances_that_are_not_numbers_at_least_zero_fail_at_once() {
    for options in [
        SolveOptions {
            cost_tolerance: f64::NAN,
            ..SolveOptions::default()
        },
        SolveOptions {
            parameter_tolerance: -1e-8,
            ..SolveOptions::default()
        },
    ] {
        let mut model = Rosenbrock::at(START);
        let minimized = run(&mut model, &options);
        match &minimized.verdict {
            Verdict::Failed(why) => assert!(why.contains("tolerance is"), "{why}"),
            other => panic!("{other:?}"),
        }
        assert!(minimized.history.is_empty());
    }
    assert_eq!(SolveOptions::default().invalid(), None);
}
