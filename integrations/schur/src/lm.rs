//! Levenberg–Marquardt with the eliminated variables solved by the Schur
//! complement (module `schur`): the same algorithm, criteria and reports
//! as the general path (`factor_apex::solve`, apex-solver's
//! Levenberg–Marquardt, itself Ceres'):
//!
//! - the damped system `(H + λD) δ = −g`, `D = clamp(diag H, 1e-6, 1e32)`,
//!   λ starting at 1e-4 (the problem's `Damping::Diagonal`, the default),
//!   or `D = I`, λ starting at 1e-5 (`Damping::Uniform`: apex-solver's
//!   settings for it, GTSAM's default), both as
//!   [`factor_apex::solve::Damping`] gives them;
//! - a step is accepted when its gain ratio `ρ` (actual over predicted
//!   decrease, the prediction `−gᵀδ − ½ δᵀHδ`) exceeds 1e-3; then `λ ←
//!   λ max(1/3, 1 − (2ρ − 1)³)` and `ν ← 2` (Nielsen), else `λ ← λν`, `ν ←
//!   2ν`; λ stays within [1e-12, 1e12];
//! - converged, from the second iteration on, when the largest cosine
//!   between the whitened residual and a column of the whitened Jacobian,
//!   `|g_j| / √(H_jj · 2 cost)` (MINPACK's orthogonality test, at the
//!   values the last accepted step reached), is at most the gradient
//!   tolerance, or when the cost is at most 1e-30 of the initial cost (a
//!   zero residual); after an accepted step, from the second iteration on,
//!   when the step is shorter than the parameter tolerance relative to
//!   `‖x‖` and lowered the cost by at most 0.1% of it, or when the cost
//!   fell by at most the cost tolerance
//!   relative — each only for a step the damping shaped no more than the
//!   cost, `λ D_jj ≤ H_jj` on every coordinate; stalled after 5 rejections
//!   in a row with λ at its maximum;
//! - a step that would meet the length or cost test but for its damping,
//!   or a stall, after a trial step a factor refused (since the last
//!   accepted step) ends the solve as `Verdict::Refused`: stopped short of
//!   a minimum, the steps towards it refused;
//! - a stall whose last trial had no finite gain ratio for want of a
//!   factorization or of f64's range (a pose at 1e50 m) ends it as
//!   `Verdict::Failed`, and the iteration reports no gain ratio rather than
//!   a NaN.
//!
//! Where this departs from apex-solver's and Ceres' criteria, each change
//! answers a wrong "converged": with every σ 1e8 times larger, the
//! absolute gradient tolerance (apex's) stopped at 79 times the optimum
//! (and one relative to `‖g₀‖` stopped a problem with one observation of
//! σ = 1e-4 at 3e-8 above its optimum), and `D`'s absolute floor of 1e-6 took over the steps, which the length
//! and cost criteria then read as convergence at the initial cost (σ 1e12
//! times larger; the cost criterion's floor of 1e-10 on the cost did the
//! same); in a room 1e6 m from the origin, the parameter tolerance
//! (relative to `‖x‖ ≈ 1e8`) read a step the damping had shortened, after
//! the accuracy envelope refused the steps towards the optimum, as
//! convergence at 13 times the optimum.
//!
//! A rejected step costs no linearization: the normal equations of the
//! current values are kept and only the damping changes. A damped system
//! that is not positive definite, or a trial step where a factor rejects
//! its configuration, is a rejected step.

use std::time::{Duration, Instant};

use factor_apex::solve::{Criterion, Iteration, SolveOptions, Verdict};

use crate::group::{Rejected, Values};
use crate::partition::Partition;
use crate::passes;
use crate::problem::Problem;
use crate::reduced::ReducedSolver;
use crate::schur::{self, Damped, Normal, StepBuffers, StepTimes};
use crate::structure::Structure;

const MIN_DAMPING: f64 = 1e-12;
const MAX_DAMPING: f64 = 1e12;
const MIN_RELATIVE_DECREASE: f64 = 1e-3;
const MAX_CONSECUTIVE_REJECTIONS: usize = 5;
/// An accepted step that lowered the cost by more than this fraction of it
/// is progress, however short (the parameter tolerance is relative to
/// `‖x‖`, about 1e8 in georeferenced coordinates).
const PROGRESS: f64 = 1e-3;
/// A cost at most this fraction of the initial cost is the rounding of a
/// zero residual (ε² ≈ 5e-32 relative): a problem whose measurements its
/// variables fit exactly has converged there (its steps still lower the
/// cost by nearly all of it, and its gradient is parallel to its residual).
const NEGLIGIBLE_COST: f64 = 1e-30;

/// Where a solve's time went (wall time unless said).
#[derive(Debug, Clone, Copy, Default)]
pub struct Profile {
    /// The structure: ordering, layout, symbolic factorization.
    pub setup: Duration,
    /// Linearization passes (gather, fused kernels, scatter).
    pub linearization: Duration,
    /// Inside them, the batch normal-equation kernels (summed over the
    /// threads: thread time, not wall time, on several threads).
    pub kernels: Duration,
    /// Forming `S` (damping and eliminating the landmarks).
    pub eliminate: Duration,
    /// Factorizing and solving the reduced system.
    pub factorize: Duration,
    /// Back-substituting the landmarks (and the model's decrease).
    pub back_substitute: Duration,
    /// Retracting the variables by the steps.
    pub retract: Duration,
    /// Evaluating the cost at the trial steps (and initially).
    pub evaluation: Duration,
    /// Threads.
    pub threads: usize,
    /// Entries of `S`'s lower triangle and of its Cholesky factor.
    pub reduced_entries: usize,
    pub factor_entries: usize,
    /// The reduced system's dimension.
    pub reduced_dim: usize,
}

/// What a solve ended with; the solution is in the problem's values.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The cost at the initial values.
    pub initial_cost: f64,
    /// The cost at the solution.
    pub final_cost: f64,
    /// Iterations run (steps tried, accepted or rejected).
    pub iterations: usize,
    /// Wall time of the solve (set-up included).
    pub elapsed: Duration,
    /// Each iteration's report.
    pub history: Vec<Iteration>,
    /// How it ended.
    pub verdict: Verdict,
    /// Evaluations at trial steps that a factor rejected (degenerate), and
    /// the first one's message.
    pub rejected: usize,
    pub first_rejection: Option<String>,
    /// Where the time went.
    pub profile: Profile,
}

/// The solve could not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SolveError {
    /// The problem is not in the shape this solver takes.
    #[error(transparent)]
    Shape(#[from] crate::error::SchurError),
    /// The initial cost is not finite, or a factor rejects its initial
    /// configuration.
    #[error("{0}")]
    Initial(String),
}

/// A solve, prepared: the structure analysed, the initial cost evaluated.
pub struct Solver<'p> {
    problem: &'p mut Problem,
    structure: Structure,
    partition: Partition,
    reduced: ReducedSolver,
    offsets: Vec<usize>,
    candidate: Vec<f64>,
    squared: Vec<Vec<f64>>,
    trial_squared: Vec<Vec<f64>>,
    normal: Normal,
    buffers: StepBuffers,
    profile: Profile,
    rejected: Rejected,
    /// The message of the last evaluation pass a factor rejected.
    last_rejection: Option<String>,
    start: Instant,
    initial_cost: f64,
}

impl<'p> Solver<'p> {
    /// Prepares the solve of `problem` from its values: analyses its
    /// structure (for rayon's threads) and evaluates the initial cost.
    ///
    /// # Errors
    ///
    /// A problem not in Schur shape ([`crate::error::SchurError`]), or initial
    /// values with a non-finite cost or a degenerate factor.
    pub fn new(problem: &'p mut Problem) -> Result<Self, SolveError> {
        let start = Instant::now();
        let threads = rayon::current_num_threads().max(1);
        let structure = problem.structure()?;
        let partition = Partition::new(&structure, threads);
        let reduced = ReducedSolver::new(&structure.csc, partition.parts())?;
        let normal = Normal::zeros(&structure);
        let profile = Profile {
            setup: start.elapsed(),
            threads: partition.parts(),
            reduced_entries: structure.csc.len(),
            factor_entries: reduced.factor_entries(),
            reduced_dim: structure.csc.dim(),
            ..Profile::default()
        };
        let squared: Vec<Vec<f64>> = problem.groups.iter().map(|g| vec![0.0; g.len()]).collect();
        let mut solver = Solver {
            offsets: structure
                .storage_order
                .iter()
                .map(|&id| problem.variables[id as usize].offset)
                .collect(),
            candidate: problem.values.clone(),
            trial_squared: squared.clone(),
            squared,
            buffers: StepBuffers::new(&normal),
            normal,
            structure,
            partition,
            reduced,
            profile,
            rejected: Rejected::default(),
            last_rejection: None,
            problem,
            start,
            initial_cost: f64::NAN,
        };
        // The candidate holds the initial values.
        solver.initial_cost = match solver.evaluate_candidate() {
            Some(cost) if cost.is_finite() => cost,
            Some(cost) => return Err(SolveError::Initial(format!("the initial cost is {cost}"))),
            None => {
                return Err(SolveError::Initial(format!(
                    "a factor is degenerate at the initial values: {}",
                    solver.rejected.first.clone().unwrap_or_default()
                )));
            }
        };
        std::mem::swap(&mut solver.squared, &mut solver.trial_squared);
        solver.rejected = Rejected::default();
        Ok(solver)
    }

    /// The cost at the initial values, `Σ ½ ρ(‖rᵢ‖²)`.
    pub fn initial_cost(&self) -> f64 {
        self.initial_cost
    }

    /// The factorization chosen for the reduced system (dense up to 40
    /// unknowns, supernodal sparse beyond) and its size, in words: for a
    /// report's header.
    pub fn linear_solver(&self) -> String {
        format!(
            "{} of the {}-unknown reduced system",
            self.reduced.name(),
            self.profile.reduced_dim
        )
    }

    /// Linearizes at the current values; the pass's wall time.
    fn linearize(&mut self) -> Duration {
        let start = Instant::now();
        let values = Values {
            scalars: &self.problem.values,
            offsets: &self.offsets,
        };
        self.profile.kernels += passes::linearize(
            self.problem,
            values,
            &self.structure,
            &self.partition,
            &self.squared,
            &mut self.normal,
        );
        let elapsed = start.elapsed();
        self.profile.linearization += elapsed;
        elapsed
    }

    /// The cost at the candidate values (`None` where a factor rejects its
    /// configuration); their squared norms in `trial_squared`.
    fn evaluate_candidate(&mut self) -> Option<f64> {
        let start = Instant::now();
        let values = Values {
            scalars: &self.candidate,
            offsets: &self.offsets,
        };
        let (cost, rejected) = passes::evaluate(
            self.problem,
            values,
            &self.partition,
            &mut self.trial_squared,
        );
        self.profile.evaluation += start.elapsed();
        let ok = rejected.count == 0;
        if !ok {
            self.last_rejection.clone_from(&rejected.first);
        }
        self.rejected.merge(rejected);
        ok.then_some(cost)
    }

    fn parameter_norm(&self) -> f64 {
        schur::norm(&[&self.problem.values])
    }

    fn step_norm(&self) -> f64 {
        schur::norm(&[&self.buffers.reduced, &self.buffers.eliminated])
    }

    /// Minimises the cost from the problem's values, which hold the
    /// solution afterwards; calls `on_iteration` as each iteration ends.
    pub fn run(
        mut self,
        options: &SolveOptions,
        mut on_iteration: impl FnMut(&Iteration),
    ) -> Outcome {
        let s = &mut self;
        let initial_cost = s.initial_cost;
        let mut cost = initial_cost;
        let bounds = s.problem.damping.diagonal_bounds();
        let mut lambda = s.problem.damping.initial_lambda();
        let mut nu = 2.0;
        let mut consecutive_rejections = 0;
        // A factor's refusal of a trial step since the last accepted one.
        let mut blocked: Option<String> = None;
        let mut history = Vec::new();
        // The first iteration's span holds the set-up, as the general
        // path's does.
        let mut last = s.start;
        let mut linearization = s.linearize();
        // What the convergence tests read of each linearization.
        let mut damping_ratio = s.normal.damping_ratio(&s.structure, bounds);
        let mut cosine = s.normal.largest_cosine(&s.structure, cost);
        let mut verdict = Verdict::IterationLimit;
        for index in 0..options.max_iterations.max(1) {
            if !s.normal.gradient_norm().is_finite() {
                verdict = Verdict::Failed("the normal equations are not finite".into());
                break;
            }
            // At the values the last accepted step reached.
            let at_minimum = if index == 0 {
                None
            } else if cosine <= options.gradient_tolerance {
                Some(Criterion::Orthogonality)
            } else if cost <= NEGLIGIBLE_COST * initial_cost {
                Some(Criterion::NegligibleCost)
            } else {
                None
            };
            if let Some(why) = at_minimum {
                verdict = why.verdict(options);
                break;
            }
            let lambda_used = lambda;
            let mut times = StepTimes::default();
            let step = schur::step(
                Damped { lambda, bounds },
                &s.normal,
                &s.structure,
                &s.partition,
                &mut s.reduced,
                &mut s.buffers,
                &mut times,
            );
            s.profile.eliminate += times.eliminate;
            s.profile.factorize += times.factorize;
            s.profile.back_substitute += times.back_substitute;
            let mut evaluation = Duration::ZERO;
            let mut trial = None;
            if let Some(step) = &step {
                let retract_start = Instant::now();
                passes::retract(
                    s.problem,
                    &s.structure,
                    &s.buffers,
                    &s.problem.values,
                    &mut s.candidate,
                );
                s.profile.retract += retract_start.elapsed();
                let evaluation_start = Instant::now();
                trial = s.evaluate_candidate().map(|c| (c, step));
                evaluation = evaluation_start.elapsed();
                if trial.is_none() {
                    blocked = s.last_rejection.clone();
                }
            }
            let rho = match trial {
                Some((new_cost, step)) if new_cost.is_finite() => {
                    step_quality(cost, new_cost, -step.g_delta - 0.5 * step.h_delta)
                }
                _ => f64::NAN,
            };
            // Why this trial step had no finite gain ratio, when it was not
            // a factor's refusal: a failed factorization or a value beyond
            // f64's range (what a stall then fails on).
            let unsolvable = if step.is_none() {
                Some("the damped normal equations cannot be factorized")
            } else if rho.is_nan() && blocked.is_none() {
                Some("the step's cost or its predicted decrease is beyond the range of f64")
            } else {
                None
            };
            let accepted = rho > MIN_RELATIVE_DECREASE;
            if accepted {
                let coefficient = 2.0 * rho - 1.0;
                lambda *= (1.0_f64 / 3.0).max(1.0 - coefficient * coefficient * coefficient);
                nu = 2.0;
                consecutive_rejections = 0;
            } else {
                lambda *= nu;
                nu *= 2.0;
                consecutive_rejections += 1;
            }
            lambda = lambda.clamp(MIN_DAMPING, MAX_DAMPING);
            let previous = cost;
            let step_norm = if step.is_some() { s.step_norm() } else { 0.0 };
            if accepted {
                cost = trial.map_or(cost, |(c, _)| c);
                std::mem::swap(&mut s.problem.values, &mut s.candidate);
                std::mem::swap(&mut s.squared, &mut s.trial_squared);
            }
            let now = Instant::now();
            let report = Iteration {
                index,
                cost,
                relative_decrease: if previous > 0.0 {
                    (previous - cost) / previous
                } else {
                    0.0
                },
                damping: Some(lambda),
                step_quality: (!rho.is_nan()).then_some(rho),
                accepted,
                linearization,
                evaluation,
                solve: (now - last).saturating_sub(linearization + evaluation),
                elapsed: now - s.start,
            };
            on_iteration(&report);
            history.push(report);
            // A step the damping shaped more than the cost on some
            // coordinate says nothing of a minimum by its length or gain,
            // unless the residual is already nearly orthogonal to the
            // Jacobian (within the square root of the gradient tolerance:
            // the rounding near a minimum, where rejected steps raise the
            // damping too).
            let undamped =
                damping_ratio * lambda_used <= 1.0 || cosine <= options.gradient_tolerance.sqrt();
            let short = index > 0
                && (previous - cost) <= PROGRESS * previous
                && step_norm
                    <= options.parameter_tolerance
                        * (s.parameter_norm() + options.parameter_tolerance);
            let flat = index > 0 && (previous - cost).abs() <= options.cost_tolerance * previous;
            let converged = if !accepted {
                None
            } else if undamped && short {
                Some(Criterion::ParameterTolerance)
            } else if undamped && flat {
                Some(Criterion::CostTolerance)
            } else {
                None
            };
            if index + 1 >= options.max_iterations.max(1) {
                break;
            }
            if let Some(why) = converged {
                verdict = why.verdict(options);
                break;
            }
            if accepted {
                // Shortened by the damping that refused steps raised: the
                // steps towards a minimum were refused.
                if !undamped
                    && (short || flat)
                    && let Some(refusal) = blocked.take()
                {
                    verdict = Verdict::Refused(refusal);
                    break;
                }
                blocked = None;
            }
            if consecutive_rejections >= MAX_CONSECUTIVE_REJECTIONS && lambda >= MAX_DAMPING {
                verdict = match (blocked.take(), unsolvable) {
                    (Some(refusal), _) => Verdict::Refused(refusal),
                    (None, Some(why)) => Verdict::Failed(format!(
                        "{why} at any damping (values at the limits of f64's range?)"
                    )),
                    (None, None) => Verdict::Stalled,
                };
                break;
            }
            last = Instant::now();
            linearization = if accepted {
                let elapsed = s.linearize();
                damping_ratio = s.normal.damping_ratio(&s.structure, bounds);
                cosine = s.normal.largest_cosine(&s.structure, cost);
                elapsed
            } else {
                Duration::ZERO
            };
        }
        Outcome {
            initial_cost,
            final_cost: cost,
            iterations: history.len(),
            elapsed: s.start.elapsed(),
            history,
            verdict,
            rejected: s.rejected.count,
            first_rejection: s.rejected.first.take(),
            profile: s.profile,
        }
    }
}

/// Prepares and runs the solve of `problem` ([`Solver::new`],
/// [`Solver::run`]).
///
/// # Errors
///
/// As [`Solver::new`].
pub fn solve(
    problem: &mut Problem,
    options: &SolveOptions,
    on_iteration: impl FnMut(&Iteration),
) -> Result<Outcome, SolveError> {
    Ok(Solver::new(problem)?.run(options, on_iteration))
}

/// The gain ratio, as apex-solver computes it: the actual decrease over
/// the predicted one, with a prediction that is not positive judged by the
/// sign of the actual decrease.
fn step_quality(cost: f64, new_cost: f64, predicted: f64) -> f64 {
    let actual = cost - new_cost;
    if predicted < -1e-15 {
        -1.0
    } else if predicted.abs() <= 1e-15 {
        if actual > 0.0 { 1.0 } else { 0.0 }
    } else {
        actual / predicted
    }
}
