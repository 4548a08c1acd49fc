//! The pose-only problem and its Levenberg–Marquardt solve.

use std::any::TypeId;

use factor_core::lie::Se3;
use factor_core::{Factor, Perturbation};

use factor_core::noise::Noise;
use factor_minimizer::{Damping, SolveOptions, Verdict, minimize};
use nalgebra::Matrix6;

use crate::error::PoseError;
use crate::model::PoseModel;
use crate::observations::{Normal, Observations, Terms, normal, normal_with, stored_scalars};

/// When [`PoseProblem::solve`] stops, and when it refuses a pose as
/// undetermined.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// The shared Levenberg–Marquardt's stopping criteria
    /// ([`SolveOptions`]).
    pub solve: SolveOptions,
    /// At the initial pose, `Σ uuᵀ` of the observations' whitened Jacobian
    /// rows `u` scaled to unit norm (the Gauss–Newton matrix with every
    /// row weighted alike, whatever its noise model) must have its smallest
    /// eigenvalue above this fraction of its largest.
    pub min_eigenvalue_ratio: f64,
}

impl Default for Options {
    /// [`SolveOptions::default`]'s tolerances with at most 20 iterations
    /// per solve (a frame tracked from the previous frame's pose converges
    /// in a few), and an eigenvalue ratio of 1e-12.
    fn default() -> Self {
        Options {
            solve: SolveOptions {
                max_iterations: 20,
                ..SolveOptions::default()
            },
            min_eigenvalue_ratio: 1e-12,
        }
    }
}

/// What [`PoseProblem::solve`] reached.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseSolution {
    /// The pose.
    pub pose: Se3<f64>,
    /// Iterations taken (steps tried, accepted or rejected).
    pub iterations: usize,
    /// The cost at the initial pose (NaN when observations were
    /// [deferred](PoseSolution::deferred): it is undefined there).
    pub initial_cost: f64,
    /// The cost at [`PoseSolution::pose`].
    pub cost: f64,
    /// How the (last) solve ended: [`Verdict::is_converged`] when a
    /// convergence criterion was met.
    pub verdict: Verdict,
    /// The observations undefined at the initial pose (a point behind
    /// it), left out of a first solve whose pose started the solve with
    /// all of them.
    pub deferred: usize,
    /// With [`Verdict::Refused`], the observation (its index, as
    /// [`PoseProblem::add`] returned it) whose refusal of a trial pose
    /// ended the solve.
    pub refused: Option<usize>,
}

/// One pose's observations against a fixed map: factors of any types, each
/// with one `Se3` variable (the pose) and the other variables held at the
/// values the factor carries.
#[derive(Default)]
pub struct PoseProblem {
    terms: Vec<Box<dyn Terms>>,
    types: Vec<TypeId>,
    observations: usize,
}

impl PoseProblem {
    /// No observations.
    pub fn new() -> Self {
        PoseProblem::default()
    }

    /// Adds `factor`, its residual whitened by `noise`; its landmarks
    /// (every variable but the pose) stay at the factor's values, and its
    /// pose's value is not used. Returns the observation's index (errors
    /// name it).
    ///
    /// # Errors
    ///
    /// [`PoseError::NoPose`] when `F` has not exactly one `Se3` variable;
    /// [`PoseError::MixedSides`] when its pose is perturbed on the other
    /// side than the problem's other observations';
    /// [`PoseError::Noise`] for a noise model that does not fit its
    /// residual.
    pub fn add<F: Factor + 'static>(
        &mut self,
        factor: &F,
        noise: &Noise,
    ) -> Result<usize, PoseError> {
        let index = self.observations;
        let id = TypeId::of::<F>();
        let at = match self.types.iter().position(|t| *t == id) {
            Some(at) => at,
            None => {
                let terms = Observations::<F>::new()?;
                if self.terms.first().is_some_and(|t| t.side() != terms.side()) {
                    return Err(PoseError::MixedSides { factor: F::NAME });
                }
                self.terms.push(Box::new(terms));
                self.types.push(id);
                self.terms.len() - 1
            }
        };
        let terms = self.terms[at]
            .as_any_mut()
            .downcast_mut::<Observations<F>>()
            .expect("the terms of its type");
        terms.push(factor, noise, index)?;
        self.observations += 1;
        Ok(index)
    }

    /// The observations added.
    pub fn len(&self) -> usize {
        self.observations
    }

    /// Whether none was added.
    pub fn is_empty(&self) -> bool {
        self.observations == 0
    }

    /// Their residual rows.
    pub fn rows(&self) -> usize {
        self.terms.iter().map(|t| t.rows()).sum()
    }

    /// The pose's perturbation side (its tangent's meaning); `None` when
    /// empty.
    pub fn side(&self) -> Option<Perturbation> {
        self.terms.first().map(|t| t.side())
    }

    /// The cost and normal equations at `pose`, each observation linearized
    /// by its factor's generated kernel (dual numbers for a factor without
    /// one), the pose's Jacobian block only.
    ///
    /// # Errors
    ///
    /// [`PoseError::Observation`] for the first one that cannot be
    /// evaluated there.
    pub fn normal(&mut self, pose: &Se3<f64>) -> Result<Normal, PoseError> {
        let stored = stored_scalars(pose);
        normal(&mut self.terms, &stored)
    }

    /// Levenberg–Marquardt from `initial`, the shared minimizer's
    /// ([`factor_minimizer::minimize`]: its damping, criteria and
    /// verdicts): each step solves the 6 × 6 system `(H + λ diag(H)) δ =
    /// −g` by Cholesky and retracts the pose on the factors' side; a step
    /// that leaves an observation undefined (a point behind the camera) is
    /// rejected.
    ///
    /// Observations undefined at `initial` itself (a landmark behind a
    /// camera started at the previous frame's pose) are deferred: the pose
    /// is first solved without them, then with all of them from there
    /// ([`PoseSolution::deferred`]; the iterations of both count).
    ///
    /// # Errors
    ///
    /// [`PoseError::NoObservations`]; [`PoseError::Underdetermined`] when
    /// `H` at the start of either solve is singular (by
    /// [`Options::min_eigenvalue_ratio`]) or not finite;
    /// [`PoseError::Observation`] for one still undefined at the first
    /// solve's pose, or the first one when none is defined at `initial`.
    pub fn solve(
        &mut self,
        initial: &Se3<f64>,
        options: &Options,
    ) -> Result<PoseSolution, PoseError> {
        let side = self.side().ok_or(PoseError::NoObservations)?;
        let undefined = match self.start(initial) {
            Ok(start) => return self.iterate(initial, start, side, options, 0),
            Err(error @ PoseError::Observation { .. }) => error,
            Err(other) => return Err(other),
        };
        let stored = stored_scalars(initial);
        let deferred: usize = self
            .terms
            .iter_mut()
            .map(|t| t.set_aside_undefined(&stored))
            .sum();
        // Every observation undefined at the start: nothing to solve the
        // first pose from, and the first one's error says why (it was a
        // singular matrix of 0 observations with a NaN ratio).
        if deferred == self.observations {
            for t in &mut self.terms {
                t.activate_all();
            }
            return Err(undefined);
        }
        let first = self
            .start(initial)
            .and_then(|start| self.iterate(initial, start, side, options, 0));
        for t in &mut self.terms {
            t.activate_all();
        }
        let first = first?;
        let start = self.start(&first.pose)?;
        let mut solution = self.iterate(&first.pose, start, side, options, first.iterations)?;
        solution.initial_cost = f64::NAN;
        solution.deferred = deferred;
        Ok(solution)
    }

    /// The normal equations at `pose` and how well the active
    /// observations determine it: `Σ uuᵀ` of their whitened Jacobian rows
    /// `u` scaled to unit norm, which no noise model's scale moves (one
    /// observation weighted by σ = 1e-90 made `H` itself look singular).
    fn start(&mut self, pose: &Se3<f64>) -> Result<(Normal, Matrix6<f64>), PoseError> {
        let stored = stored_scalars(pose);
        let mut determination = Matrix6::zeros();
        let normal = normal_with(&mut self.terms, &stored, Some(&mut determination))?;
        Ok((normal, determination))
    }

    /// Levenberg–Marquardt on the active observations from `initial`,
    /// whose normal equations and determination are `start` ([`Self::start`]),
    /// the iterations counted from `iterations`.
    fn iterate(
        &mut self,
        initial: &Se3<f64>,
        (current, determination): (Normal, Matrix6<f64>),
        side: Perturbation,
        options: &Options,
        iterations: usize,
    ) -> Result<PoseSolution, PoseError> {
        let eigenvalues = determination.symmetric_eigenvalues();
        let ratio = eigenvalues.min() / eigenvalues.max();
        // Also refuses a NaN (incomparable).
        if ratio.partial_cmp(&options.min_eigenvalue_ratio) != Some(std::cmp::Ordering::Greater) {
            return Err(PoseError::Underdetermined {
                observations: self.terms.iter().map(|t| t.active()).sum(),
                rows: self.rows(),
                ratio,
            });
        }
        let start = std::time::Instant::now();
        let initial_cost = current.cost;
        let mut model = PoseModel::new(&mut self.terms, side, *initial, current);
        let minimized = minimize(
            &mut model,
            initial_cost,
            start,
            Damping::Diagonal,
            &options.solve,
            |_| {},
        );
        Ok(PoseSolution {
            pose: model.pose,
            iterations: iterations + minimized.history.len(),
            initial_cost,
            cost: minimized.final_cost,
            refused: matches!(minimized.verdict, Verdict::Refused(_))
                .then_some(model.refused)
                .flatten(),
            verdict: minimized.verdict,
            deferred: 0,
        })
    }
}
