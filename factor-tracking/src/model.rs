//! One pose's observations as the shared minimizer's [`Model`]: the dense
//! 6 × 6 normal equations, solved by Cholesky.

use factor_core::lie::Se3;
use factor_core::{Manifold, Perturbation};
use factor_minimizer::{Damped, Linearization, Model, Prediction, Trial};
use nalgebra::Vector6;

use crate::error::PoseError;
use crate::observations::{Normal, Terms, normal, stored_scalars};

/// The pose, its normal equations, and the trial step's.
pub(crate) struct PoseModel<'t> {
    terms: &'t mut [Box<dyn Terms>],
    side: Perturbation,
    /// The current pose and its normal equations.
    pub(crate) pose: Se3<f64>,
    current: Normal,
    /// The last step, the pose it reaches and (once evaluated there) that
    /// pose's normal equations: a trial evaluates the cost by the same pass
    /// that linearizes, so an accepted step's linearization is kept.
    step: Vector6<f64>,
    candidate: Se3<f64>,
    next: Option<Normal>,
    /// The observation that refused the last trial it refused.
    pub(crate) refused: Option<usize>,
}

impl<'t> PoseModel<'t> {
    /// The observations `terms` at `pose`, whose normal equations are
    /// `current`, retracted on `side`.
    pub(crate) fn new(
        terms: &'t mut [Box<dyn Terms>],
        side: Perturbation,
        pose: Se3<f64>,
        current: Normal,
    ) -> Self {
        PoseModel {
            terms,
            side,
            pose,
            current,
            step: Vector6::zeros(),
            candidate: pose,
            next: None,
            refused: None,
        }
    }
}

impl Model for PoseModel<'_> {
    fn linearize(&mut self, cost: f64, bounds: (f64, f64)) -> Linearization {
        let (h, g) = (&self.current.hessian, &self.current.gradient);
        Linearization::read((0..6).map(|j| (h[(j, j)], g[j])), cost, bounds)
    }

    fn solve_damped(&mut self, damped: Damped) -> Option<Prediction> {
        let (h, g) = (&self.current.hessian, &self.current.gradient);
        let mut system = *h;
        for j in 0..6 {
            system[(j, j)] += damped.of(h[(j, j)]);
        }
        self.step = -system.cholesky()?.solve(g);
        Some(Prediction {
            g_delta: g.dot(&self.step),
            h_delta: self.step.dot(&(h * self.step)),
        })
    }

    fn evaluate_step(&mut self) -> Trial {
        self.candidate = self.pose.retract(self.step.as_slice(), self.side);
        let stored = stored_scalars(&self.candidate);
        match normal(self.terms, &stored) {
            Ok(next) => {
                let cost = next.cost;
                self.next = Some(next);
                Trial::Cost(cost)
            }
            Err(error) => {
                self.next = None;
                // The factor's own words; which observation, by index.
                Trial::Refused(match error {
                    PoseError::Observation { observation, error } => {
                        self.refused = Some(observation);
                        error.to_string()
                    }
                    other => other.to_string(),
                })
            }
        }
    }

    fn accept(&mut self) {
        self.pose = self.candidate;
        if let Some(next) = self.next.take() {
            self.current = next;
        }
    }

    fn step_norm(&self) -> f64 {
        self.step.norm()
    }

    fn parameter_norm(&self) -> f64 {
        let stored = stored_scalars(&self.pose);
        stored.iter().map(|x| x * x).sum::<f64>().sqrt()
    }
}
