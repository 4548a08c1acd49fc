//! What the minimizer asks of a problem: its linear-solver strategy.

/// A least-squares problem as Levenberg–Marquardt sees it: current values,
/// their normal equations `H δ = −g` (`H = JᵀJ`, `g = Jᵀr`, whitened), a
/// step and the candidate values it reaches. The problem keeps all of it;
/// the minimizer only orders the calls.
///
/// The cost is `½ Σ ‖rᵢ‖²` of the whitened residuals (the ½ matters: the
/// predicted decrease `−gᵀδ − ½ δᵀHδ` and the cosine test assume it), `H`
/// and `g` its Gauss–Newton matrix and gradient in the tangent coordinates
/// the step is solved in; the problem retracts its values by the step
/// itself (on a manifold, by its own retraction). The calls:
///
/// 1. [`Model::linearize`] at the current values (once at the start, then
///    after every accepted step);
/// 2. [`Model::solve_damped`] for a damping λ (again with a larger one
///    after a rejected step, at the same linearization);
/// 3. [`Model::evaluate_step`]: the cost at the current values retracted by
///    the step (the candidate);
/// 4. [`Model::accept`] when the step is taken.
pub trait Model {
    /// Linearizes at the current values, whose cost is `cost`, and reports
    /// what the stopping tests read of the normal equations; `bounds` are
    /// the damping's `D = clamp(diag H, low, high)` ([`crate::Damping`]).
    fn linearize(&mut self, cost: f64, bounds: (f64, f64)) -> Linearization;

    /// Solves `(H + λ D) δ = −g` at the last linearization; `None` when the
    /// damped system cannot be factorized (not positive definite).
    fn solve_damped(&mut self, damped: Damped) -> Option<Prediction>;

    /// Retracts the current values by the last step into the candidate and
    /// evaluates its cost.
    fn evaluate_step(&mut self) -> Trial;

    /// Makes the candidate the current values (after
    /// [`Model::evaluate_step`] returned a cost).
    fn accept(&mut self);

    /// `‖δ‖`, the last step's norm in its tangent coordinates.
    fn step_norm(&self) -> f64;

    /// `‖x‖`, the current values' norm: the scale the parameter tolerance
    /// is relative to (a step counts as short when `‖δ‖ ≤ tol (‖x‖ +
    /// tol)`); for values on a manifold, the norm of their stored
    /// coordinates (a unit quaternion counts 1).
    fn parameter_norm(&self) -> f64;
}

/// What the stopping tests read of a linearization.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linearization {
    /// Whether `g` is finite (a solve stops as failed otherwise).
    pub gradient_finite: bool,
    /// `max_j D_jj / H_jj`: a step damped by λ was shaped by the damping
    /// more than by the cost on some coordinate when `λ · ratio > 1`.
    pub damping_ratio: f64,
    /// The largest cosine between the whitened residual and a column of the
    /// whitened Jacobian, `max_j |g_j| / √(H_jj · 2 cost)` (MINPACK's
    /// orthogonality test; 0 for a zero cost).
    pub cosine: f64,
}

impl Linearization {
    /// What the tests read of normal equations given coordinate by
    /// coordinate as `(H_jj, g_j)` over the free coordinates, at values of
    /// cost `cost`, for the damping's `bounds`.
    ///
    /// `damping_ratio` is the largest `clamp(H_jj, bounds) / H_jj`: how
    /// many times its curvature the damping adds to a coordinate at λ = 1
    /// (1 for Marquardt's scaling within its bounds, infinite for a
    /// coordinate of no curvature). `cosine` is the largest `|g_j| /
    /// √(H_jj ‖r‖²)` with `‖r‖² = 2 cost`: 0 at a stationary point, and the
    /// same whatever the scale of the noise models; a column of zeros
    /// counts 0.
    pub fn read(
        diagonal_and_gradient: impl IntoIterator<Item = (f64, f64)>,
        cost: f64,
        bounds: (f64, f64),
    ) -> Self {
        let mut read = Linearization {
            gradient_finite: true,
            damping_ratio: 0.0,
            cosine: 0.0,
        };
        for (h, g) in diagonal_and_gradient {
            read.gradient_finite &= g.is_finite();
            read.damping_ratio = read.damping_ratio.max(h.clamp(bounds.0, bounds.1) / h);
            let cosine = g.abs() / (h.sqrt() * (2.0 * cost).sqrt());
            if !cosine.is_nan() {
                read.cosine = read.cosine.max(cosine);
            }
        }
        read
    }
}

/// The damping of one linear solve: `(H + λ D) δ = −g`, `D = clamp(diag H,
/// bounds.0, bounds.1)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damped {
    /// λ.
    pub lambda: f64,
    /// The bounds of `D`'s entries.
    pub bounds: (f64, f64),
}

impl Damped {
    /// `λ clamp(h, low, high)`: what the damping adds to a diagonal entry
    /// `h` of `H`.
    pub fn of(self, h: f64) -> f64 {
        self.lambda * h.clamp(self.bounds.0, self.bounds.1)
    }
}

/// What the undamped quadratic model predicts of a step `δ`: the decrease
/// `−gᵀδ − ½ δᵀHδ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prediction {
    /// `gᵀδ`.
    pub g_delta: f64,
    /// `δᵀHδ` (the undamped `H`).
    pub h_delta: f64,
}

/// The evaluation of a trial step.
#[derive(Debug, Clone, PartialEq)]
pub enum Trial {
    /// The cost at the candidate (possibly not finite).
    Cost(f64),
    /// A factor refused its configuration at the candidate (degenerate
    /// geometry): the step is rejected, and the message names why.
    Refused(String),
}
