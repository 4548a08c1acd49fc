//! Levenberg–Marquardt (apex-solver's) on a built problem, reporting each
//! iteration as it ends.

use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use apex_solver::core::VarKey;
use apex_solver::core::variable::ManifoldVariable;
use apex_solver::optimizer::levenberg_marquardt::{LevenbergMarquardt, LevenbergMarquardtConfig};
use apex_solver::optimizer::{OptObserver, OptimizationStatus};
use slotmap::SlotMap;

use crate::built::Built;
use crate::timing::PhaseClock;
pub use factor_minimizer::{Criterion, Damping, Iteration, SolveOptions, Verdict};

/// What a solve ended with: [`solve`]'s result.
///
/// Read a variable back with [`Outcome::value`], the verdict with
/// [`Outcome::verdict`]; `{:?}` prints every field but the values (their
/// count instead: apex's variables are trait objects).
///
/// ```text
/// Outcome { status: CostToleranceReached, initial_cost: 2.5, final_cost: 1.2e-31,
///           iterations: 2, elapsed: 151µs, values: 1 variable(s), history: [Iteration { … }, …],
///           options: SolveOptions { … } }
/// ```
pub struct Outcome {
    /// apex-solver's status: why it stopped ([`Outcome::verdict`] says it
    /// in words).
    pub status: OptimizationStatus,
    /// The cost at the initial values.
    pub initial_cost: f64,
    /// The cost at the solution.
    pub final_cost: f64,
    /// Iterations run.
    pub iterations: usize,
    /// Wall time of the solve (set-up included).
    pub elapsed: Duration,
    /// The solution, by variable key.
    pub values: SlotMap<VarKey, Box<dyn ManifoldVariable>>,
    /// Each iteration's report.
    pub history: Vec<Iteration>,
    /// The options it ran with (the tolerances its verdict names).
    pub options: SolveOptions,
}

impl std::fmt::Debug for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Outcome")
            .field("status", &self.status)
            .field("initial_cost", &self.initial_cost)
            .field("final_cost", &self.final_cost)
            .field("iterations", &self.iterations)
            .field("elapsed", &self.elapsed)
            .field("values", &format_args!("{} variable(s)", self.values.len()))
            .field("history", &self.history)
            .field("options", &self.options)
            .finish()
    }
}

impl Outcome {
    /// The solution's value of `variable` (a variable of the solved
    /// problem, [`crate::builder::ProblemBuilder::add_variable`]).
    ///
    /// # Panics
    ///
    /// If `variable` is not one of the problem's.
    pub fn value<
        V: factor_core::host::HostMap<factor_core::host::Apex> + factor_core::Storage<f64>,
    >(
        &self,
        variable: &crate::builder::Variable<V>,
    ) -> V {
        crate::builder::value_of(&self.values, variable)
    }

    /// The verdict of the status (and of a non-finite final cost).
    pub fn verdict(&self) -> Verdict {
        if !self.final_cost.is_finite() {
            return Verdict::Failed(format!("the final cost is {}", self.final_cost));
        }
        match &self.status {
            OptimizationStatus::CostToleranceReached => {
                Criterion::CostTolerance.verdict(&self.options)
            }
            OptimizationStatus::ParameterToleranceReached => {
                Criterion::ParameterTolerance.verdict(&self.options)
            }
            OptimizationStatus::GradientToleranceReached => {
                Criterion::GradientTolerance.verdict(&self.options)
            }
            OptimizationStatus::Converged | OptimizationStatus::MinCostThresholdReached => {
                Verdict::Converged(self.status.to_string().to_lowercase())
            }
            OptimizationStatus::MaxIterationsReached => Verdict::IterationLimit,
            OptimizationStatus::StalledNoProgress => Verdict::Stalled,
            other => Verdict::Failed(other.to_string()),
        }
    }
}

/// The solve failed before it could report an outcome.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("apex-solver: {0}")]
pub struct SolveError(pub String);

/// The observer that turns apex's notifications into [`Iteration`]s.
struct Reporter {
    state: Arc<Mutex<ReporterState>>,
}

struct ReporterState {
    clock: Arc<PhaseClock>,
    start: Instant,
    last: Instant,
    previous_cost: f64,
    metrics: (f64, Option<f64>, Option<f64>),
    min_relative_decrease: f64,
    history: Vec<Iteration>,
    callback: Box<dyn FnMut(&Iteration) + Send>,
}

impl OptObserver for Reporter {
    fn on_step(&self, _values: &SlotMap<VarKey, Box<dyn ManifoldVariable>>, iteration: usize) {
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        let now = Instant::now();
        let (cost, damping, step_quality) = state.metrics;
        let previous = state.previous_cost;
        let (linearization, evaluation) = (state.clock.linearization(), state.clock.evaluation());
        let report = Iteration {
            index: iteration,
            cost,
            relative_decrease: if previous > 0.0 {
                (previous - cost) / previous
            } else {
                0.0
            },
            damping,
            step_quality,
            accepted: step_quality.is_some_and(|rho| rho > state.min_relative_decrease),
            linearization,
            evaluation,
            solve: (now - state.last).saturating_sub(linearization + evaluation),
            elapsed: now - state.start,
        };
        state.last = now;
        state.previous_cost = cost;
        (state.callback)(&report);
        state.history.push(report);
    }

    fn set_iteration_metrics(
        &self,
        cost: f64,
        _gradient_norm: f64,
        damping: Option<f64>,
        _step_norm: f64,
        step_quality: Option<f64>,
    ) {
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        state.metrics = (cost, damping, step_quality);
    }
}

/// Solves `built` with Levenberg–Marquardt, calling `on_iteration` as each
/// iteration ends, damped as `built.damping` says.
///
/// `on_iteration` is handed to apex-solver's observer, which keeps it for
/// the whole solve and may run it on another thread: it is `Send + 'static`,
/// so it cannot borrow the caller's variables. Move what it needs into it
/// (`move |iteration| …`): a counter, a channel's sender, or an
/// `Arc<Mutex<Vec<Iteration>>>` to collect into, as below. Every iteration
/// is also in [`Outcome::history`] when the solve returns; `|_| {}` reports
/// nothing.
///
/// ```
/// use std::sync::{Arc, Mutex};
///
/// use factor_apex::builder::{Noise, ProblemBuilder};
/// use factor_apex::solve::{Iteration, SolveOptions, Verdict, solve};
/// use factor_core::nalgebra::Vector2;
/// use factor_core::{Factor, Scalar};
///
/// /// `x − target`: pulls a point onto a target.
/// #[derive(Clone, Debug, Factor)]
/// #[factor(residual = pull, dim = 2)]
/// pub struct Pull<S: Scalar = f64> {
///     pub target: Vector2<S>,
///     #[variable]
///     pub x: Vector2<S>,
/// }
///
/// pub fn pull<S: Scalar>(f: &Pull<S>) -> Vector2<S> {
///     f.x - f.target
/// }
///
/// let factor = Pull { target: Vector2::new(1.0, 2.0), x: Vector2::zeros() };
/// let mut problem = ProblemBuilder::new();
/// let x = problem.add_variable(&factor.x);
/// problem.add_factor_dual(&factor, &[x.erase()], &Noise::Sigma(0.1), None)?;
/// let mut built = problem.build()?;
///
/// // The callback owns its handle on the list; this scope keeps the other.
/// let seen: Arc<Mutex<Vec<Iteration>>> = Arc::default();
/// let sink = Arc::clone(&seen);
/// let outcome = solve(&mut built, &SolveOptions::default(), move |iteration| {
///     sink.lock().unwrap().push(iteration.clone());
/// })?;
/// println!("{outcome:?}");
/// assert_eq!(*seen.lock().unwrap(), outcome.history);
/// assert!(matches!(outcome.verdict(), Verdict::Converged(_)));
/// let solved: Vector2<f64> = outcome.value(&x);
/// assert!((solved - factor.target).norm() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
///
/// apex-solver's error (a linear solve that failed, a problem it refuses).
pub fn solve<K>(
    built: &mut Built<K>,
    options: &SolveOptions,
    on_iteration: impl FnMut(&Iteration) + Send + 'static,
) -> Result<Outcome, SolveError> {
    let (low, high) = built.damping.diagonal_bounds();
    let config = LevenbergMarquardtConfig::default()
        .with_diagonal_bounds(low, high)
        .with_damping(built.damping.initial_lambda())
        .with_linear_solver_type(built.linear_solver)
        // apex stops after the iteration whose 0-based index reaches its
        // limit, so it runs `limit + 1` iterations.
        .with_max_iterations(options.max_iterations.saturating_sub(1))
        .with_cost_tolerance(options.cost_tolerance)
        .with_parameter_tolerance(options.parameter_tolerance)
        .with_gradient_tolerance(options.gradient_tolerance);
    let start = Instant::now();
    let state = Arc::new(Mutex::new(ReporterState {
        clock: Arc::clone(&built.clock),
        start,
        last: start,
        previous_cost: built.initial_cost,
        metrics: (f64::NAN, None, None),
        min_relative_decrease: config.min_relative_decrease,
        history: Vec::new(),
        callback: Box::new(on_iteration),
    }));
    let mut solver = LevenbergMarquardt::with_config(config);
    solver.add_observer(Reporter {
        state: Arc::clone(&state),
    });
    let result = solver
        .optimize(&mut built.problem)
        .map_err(|e| SolveError(e.to_string()))?;
    let history = std::mem::take(&mut state.lock().unwrap_or_else(PoisonError::into_inner).history);
    Ok(Outcome {
        status: result.status,
        initial_cost: result.initial_cost,
        final_cost: result.final_cost,
        iterations: result.iterations,
        elapsed: start.elapsed(),
        values: result.parameters,
        history,
        options: *options,
    })
}
