//! What a solve reports: each iteration as it ends, and how it ended.

use std::time::Duration;

use crate::SolveOptions;

/// One iteration (a step tried, accepted or rejected), as it ends: what a
/// solve's callback receives, and what its outcome's history holds, one per
/// iteration, in order. `{:?}` prints every field.
#[derive(Debug, Clone, PartialEq)]
pub struct Iteration {
    /// 0 for the first step.
    pub index: usize,
    /// The cost after the iteration (unchanged by a rejected step).
    pub cost: f64,
    /// `(previous cost − cost) / previous cost`.
    pub relative_decrease: f64,
    /// The damping λ after the iteration's update.
    pub damping: Option<f64>,
    /// The step quality ρ (actual over predicted decrease).
    pub step_quality: Option<f64>,
    /// Whether the step was accepted.
    pub accepted: bool,
    /// The wall time of the linearization pass (residuals and Jacobians).
    pub linearization: Duration,
    /// The wall time of the residual-only pass that evaluated the step.
    pub evaluation: Duration,
    /// The rest of the iteration: assembling and solving the linear system,
    /// updating the variables (the first iteration also holds the solver's
    /// set-up).
    pub solve: Duration,
    /// Time since the solve started.
    pub elapsed: Duration,
}

/// How a solve ended, for a command line.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Verdict {
    /// A convergence criterion was met.
    Converged(String),
    /// The iteration limit was reached first.
    IterationLimit,
    /// No step reduced the cost any more (damping at its maximum).
    Stalled,
    /// Stopped short of a minimum, not converged: the steps that would
    /// lower the cost further met configurations a factor refuses, and the
    /// damping they raised left only a step shorter than the parameter
    /// tolerance; the last refusal's message.
    Refused(String),
    /// The solve stopped on a failure (non-finite values, an
    /// ill-conditioned system, ...).
    Failed(String),
}

impl Verdict {
    /// Whether a convergence criterion was met.
    pub fn is_converged(&self) -> bool {
        matches!(self, Verdict::Converged(_))
    }
}

impl std::fmt::Display for Verdict {
    /// The verdict in words, as a solve's summary prints it: "converged
    /// (the last step decreased the cost by less than 1e-8 of it)",
    /// "stopped at the iteration limit, not converged", …
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Verdict::Converged(why) => write!(f, "converged ({why})"),
            Verdict::IterationLimit => f.write_str("stopped at the iteration limit, not converged"),
            Verdict::Stalled => {
                f.write_str("stopped: no step reduces the cost any more (damping at its maximum)")
            }
            Verdict::Refused(refusal) => write!(
                f,
                "stopped short of a minimum, not converged: the steps that would lower the cost \
                 further meet configurations a factor refuses, and the damping they raised left \
                 only a step shorter than the parameter tolerance (last refusal: {refusal})"
            ),
            Verdict::Failed(why) => write!(f, "failed: {why}"),
        }
    }
}

/// A stopping criterion a solve met, in the same words whichever solver
/// met it (this crate's Levenberg–Marquardt or apex-solver's).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Criterion {
    /// An accepted step decreased the cost by less than
    /// [`SolveOptions::cost_tolerance`] of it.
    CostTolerance,
    /// An accepted step was shorter than
    /// [`SolveOptions::parameter_tolerance`] of the parameters.
    ParameterTolerance,
    /// The gradient's norm fell below [`SolveOptions::gradient_tolerance`]
    /// (apex-solver).
    GradientTolerance,
    /// The largest cosine between the whitened residual and a column of the
    /// whitened Jacobian fell below [`SolveOptions::gradient_tolerance`]
    /// (MINPACK's orthogonality test, which the noise models' scale does
    /// not move: the absolute gradient tolerance stopped a problem whose
    /// every σ was 1e8 times larger at 79 times its optimum).
    Orthogonality,
    /// The cost fell to at most 1e-30 of its initial value: the rounding of
    /// a zero residual.
    NegligibleCost,
}

impl Criterion {
    /// [`Verdict::Converged`], naming the criterion and its tolerance in
    /// `options`.
    pub fn verdict(self, options: &SolveOptions) -> Verdict {
        Verdict::Converged(match self {
            Criterion::CostTolerance => format!(
                "the last step decreased the cost by less than {:e} of it",
                options.cost_tolerance
            ),
            Criterion::ParameterTolerance => format!(
                "the last step was shorter than {:e} of the parameters",
                options.parameter_tolerance
            ),
            Criterion::GradientTolerance => format!(
                "the gradient's norm fell below {:e}",
                options.gradient_tolerance
            ),
            Criterion::Orthogonality => format!(
                "the residual's cosine with every Jacobian column fell below {:e}",
                options.gradient_tolerance
            ),
            Criterion::NegligibleCost => {
                "the cost fell to 1e-30 of its initial value, the rounding of a zero residual"
                    .to_owned()
            }
        })
    }
}
