//! Levenberg–Marquardt with the eliminated variables solved by the Schur
//! complement (module `schur`): this crate's problem as a
//! [`factor_minimizer::Model`], minimized by the one loop every solver
//! path shares ([`factor_minimizer::minimize`]: its damping, criteria,
//! verdicts and reports). Each linearization runs the fused kernels (or each
//! factor's Jacobians) into `U`, `V`, `W`; each damped solve eliminates the
//! landmarks and factorizes the reduced system; a trial step retracts every
//! variable and evaluates the cost (a factor that refuses its
//! configuration there rejects the step).

use std::time::{Duration, Instant};

use factor_minimizer::{
    Damped, Iteration, Linearization, Model, Prediction, SolveOptions, Trial, Verdict, minimize,
};

use crate::group::{Rejected, Values};
use crate::partition::Partition;
use crate::passes;
use crate::problem::Problem;
use crate::reduced::ReducedSolver;
use crate::schur::{self, Normal, StepBuffers, StepTimes};
use crate::structure::Structure;

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
        let cost: Vec<usize> = problem
            .groups
            .iter()
            .map(|g| g.linearized().relative_cost())
            .collect();
        let partition = Partition::new(&structure, &cost, threads);
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
            problem,
            start,
            initial_cost: f64::NAN,
        };
        // The candidate holds the initial values.
        solver.initial_cost = match solver.evaluate_candidate() {
            Ok(cost) if cost.is_finite() => cost,
            Ok(cost) => return Err(SolveError::Initial(format!("the initial cost is {cost}"))),
            Err(why) => {
                return Err(SolveError::Initial(format!(
                    "a factor is degenerate at the initial values: {why}"
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

    /// Linearizes at the current values.
    fn linearize_pass(&mut self) {
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
        self.profile.linearization += start.elapsed();
    }

    /// The cost at the candidate values, or the message of the first factor
    /// that rejects its configuration there; their squared norms in
    /// `trial_squared`.
    fn evaluate_candidate(&mut self) -> Result<f64, String> {
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
        let refusal = (rejected.count > 0).then(|| rejected.first.clone().unwrap_or_default());
        self.rejected.merge(rejected);
        refusal.map_or(Ok(cost), Err)
    }

    /// Minimises the cost from the problem's values, which hold the
    /// solution afterwards; calls `on_iteration` as each iteration ends.
    pub fn run(mut self, options: &SolveOptions, on_iteration: impl FnMut(&Iteration)) -> Outcome {
        let (initial_cost, start, damping) = (self.initial_cost, self.start, self.problem.damping);
        let minimized = minimize(
            &mut self,
            initial_cost,
            start,
            damping,
            options,
            on_iteration,
        );
        Outcome {
            initial_cost,
            final_cost: minimized.final_cost,
            iterations: minimized.history.len(),
            elapsed: self.start.elapsed(),
            history: minimized.history,
            verdict: minimized.verdict,
            rejected: self.rejected.count,
            first_rejection: self.rejected.first.take(),
            profile: self.profile,
        }
    }
}

impl Model for Solver<'_> {
    fn linearize(&mut self, cost: f64, bounds: (f64, f64)) -> Linearization {
        self.linearize_pass();
        Linearization::read(
            self.normal.diagonal_and_gradient(&self.structure),
            cost,
            bounds,
        )
    }

    fn solve_damped(&mut self, damped: Damped) -> Option<Prediction> {
        let mut times = StepTimes::default();
        let prediction = schur::step(
            damped,
            &self.normal,
            &self.structure,
            &self.partition,
            &mut self.reduced,
            &mut self.buffers,
            &mut times,
        );
        self.profile.eliminate += times.eliminate;
        self.profile.factorize += times.factorize;
        self.profile.back_substitute += times.back_substitute;
        prediction
    }

    fn evaluate_step(&mut self) -> Trial {
        let retract_start = Instant::now();
        passes::retract(
            self.problem,
            &self.structure,
            &self.buffers,
            &self.problem.values,
            &mut self.candidate,
        );
        self.profile.retract += retract_start.elapsed();
        match self.evaluate_candidate() {
            Ok(cost) => Trial::Cost(cost),
            Err(why) => Trial::Refused(why),
        }
    }

    fn accept(&mut self) {
        std::mem::swap(&mut self.problem.values, &mut self.candidate);
        std::mem::swap(&mut self.squared, &mut self.trial_squared);
    }

    fn step_norm(&self) -> f64 {
        schur::norm(&[&self.buffers.reduced, &self.buffers.eliminated])
    }

    fn parameter_norm(&self) -> f64 {
        schur::norm(&[&self.problem.values])
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
