//! The Levenberg–Marquardt loop: apex-solver's algorithm (itself Ceres'),
//! with the stopping tests made independent of the noise models' scale.
//!
//! - the damped system `(H + λD) δ = −g` ([`crate::Damping`] gives `D` and
//!   the first λ);
//! - a step is accepted when its gain ratio `ρ` (actual over predicted
//!   decrease, the prediction `−gᵀδ − ½ δᵀHδ`) exceeds 1e-3; then `λ ←
//!   λ max(1/3, 1 − (2ρ − 1)³)` and `ν ← 2` (Nielsen), else `λ ← λν`, `ν ←
//!   2ν`; λ stays within [1e-12, 1e12];
//! - converged, from the second iteration on, when the largest cosine
//!   between the whitened residual and a column of the whitened Jacobian,
//!   `|g_j| / √(H_jj · 2 cost)` (MINPACK's orthogonality test, at the
//!   values the last accepted step reached), is at most the gradient
//!   tolerance, or when the cost is at most 1e-30 of the initial cost (a
//!   zero residual), these two also after the last iteration the limit
//!   allows; from the second iteration on, when a step (accepted,
//!   or rejected but evaluated) is shorter than the parameter tolerance
//!   relative to `‖x‖` and lowered the cost by at most 0.1% of it, or when
//!   an accepted step lowered the cost by at most the cost tolerance
//!   relative — each only for a step the damping shaped no more than the
//!   cost, `λ D_jj ≤ H_jj` on every coordinate; stalled after 5
//!   rejections in a row with λ at its maximum;
//! - a step that would meet the length or cost test but for its damping,
//!   or a stall, after a trial step a factor refused (since the last
//!   accepted step) ends the solve as [`Verdict::Refused`]: stopped short
//!   of a minimum, the steps towards it refused;
//! - a stall whose last trial had no finite gain ratio for want of a
//!   factorization or of f64's range (a pose at 1e50 m) ends it as
//!   [`Verdict::Failed`], and the iteration reports no gain ratio rather
//!   than a NaN.
//!
//! Where this departs from apex-solver's and Ceres' criteria, each change
//! answers a wrong "converged": with every σ 1e8 times larger, the
//! absolute gradient tolerance (apex's) stopped at 79 times the optimum
//! (and one relative to `‖g₀‖` stopped a problem with one observation of
//! σ = 1e-4 at 3e-8 above its optimum), and `D`'s absolute floor of 1e-6
//! took over the steps, which the length and cost criteria then read as
//! convergence at the initial cost (σ 1e12 times larger; the cost
//! criterion's floor of 1e-10 on the cost did the same); in a room 1e6 m
//! from the origin, the parameter tolerance (relative to `‖x‖ ≈ 1e8`) read
//! a step the damping had shortened, after the accuracy envelope refused
//! the steps towards the optimum, as convergence at 13 times the optimum.
//!
//! A rejected step costs no linearization: the normal equations of the
//! current values are kept and only the damping changes. A damped system
//! that is not positive definite, or a trial step where a factor rejects
//! its configuration, is a rejected step.

use std::time::{Duration, Instant};

use crate::{Criterion, Damped, Damping, Iteration, Model, SolveOptions, Trial, Verdict};

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

/// What [`minimize`] ended with; the solution is the model's current values.
#[derive(Debug, Clone, PartialEq)]
pub struct Minimized {
    /// The cost at the solution.
    pub final_cost: f64,
    /// Each iteration's report, in order.
    pub history: Vec<Iteration>,
    /// How it ended.
    pub verdict: Verdict,
}

/// Minimises `model`'s cost from its current values, whose cost is
/// `initial_cost`, damped as `damping` says, until `options`' criteria
/// stop it; calls `on_iteration` as each iteration ends. `start` is when
/// the solve began: the first iteration's report holds the time from it
/// (the solver's set-up), and every report's `elapsed` counts from it.
///
/// An initial cost that is not finite (or negative) ends the solve at once
/// as [`Verdict::Failed`], with no iteration and the model untouched (no
/// step can be judged against it), as do options with a tolerance that is
/// negative or NaN. `max_iterations: 0` runs one iteration.
pub fn minimize<M: Model>(
    model: &mut M,
    initial_cost: f64,
    start: Instant,
    damping: Damping,
    options: &SolveOptions,
    mut on_iteration: impl FnMut(&Iteration),
) -> Minimized {
    let refusal = if !(initial_cost.is_finite() && initial_cost >= 0.0) {
        Some(format!("the initial cost is {initial_cost}"))
    } else {
        options.invalid()
    };
    if let Some(why) = refusal {
        return Minimized {
            final_cost: initial_cost,
            history: Vec::new(),
            verdict: Verdict::Failed(why),
        };
    }
    let mut cost = initial_cost;
    let bounds = damping.diagonal_bounds();
    let mut lambda = damping.initial_lambda();
    let mut nu = 2.0;
    let mut consecutive_rejections = 0;
    // A factor's refusal of a trial step since the last accepted one.
    let mut blocked: Option<String> = None;
    let mut history = Vec::new();
    let mut last = start;
    let (mut linearization, mut linearized_in) = timed(|| model.linearize(cost, bounds));
    let mut verdict = Verdict::IterationLimit;
    let limit = options.max_iterations.max(1);
    // One pass more than the limit allows steps: its tests at the values
    // the last step reached count, then the limit stops it.
    for index in 0..=limit {
        if !linearization.gradient_finite {
            verdict = Verdict::Failed("the normal equations are not finite".into());
            break;
        }
        // At the values the last accepted step reached.
        let at_minimum = if index == 0 {
            None
        } else if linearization.cosine <= options.gradient_tolerance {
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
        if index == limit {
            break;
        }
        let lambda_used = lambda;
        let prediction = model.solve_damped(Damped { lambda, bounds });
        let mut evaluation = Duration::ZERO;
        let mut new_cost = None;
        if prediction.is_some() {
            let trial;
            (trial, evaluation) = timed(|| model.evaluate_step());
            match trial {
                Trial::Cost(c) => new_cost = Some(c),
                Trial::Refused(why) => blocked = Some(why),
            }
        }
        let rho = match (prediction, new_cost) {
            (Some(p), Some(c)) if c.is_finite() => {
                step_quality(cost, c, -p.g_delta - 0.5 * p.h_delta)
            }
            _ => f64::NAN,
        };
        // Why this trial step had no finite gain ratio, when it was not a
        // factor's refusal: a failed factorization or a value beyond f64's
        // range (what a stall then fails on).
        let unsolvable = if prediction.is_none() {
            Some("the damped normal equations cannot be factorized")
        } else if rho.is_nan() && blocked.is_none() {
            Some("the step's cost or its predicted decrease is not finite")
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
        let step_norm = if prediction.is_some() {
            model.step_norm()
        } else {
            0.0
        };
        if accepted {
            cost = new_cost.unwrap_or(cost);
            model.accept();
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
            linearization: linearized_in,
            evaluation,
            solve: (now - last).saturating_sub(linearized_in + evaluation),
            elapsed: now - start,
        };
        on_iteration(&report);
        history.push(report);
        // A step the damping shaped more than the cost on some coordinate
        // says nothing of a minimum by its length or gain, unless the
        // residual is already nearly orthogonal to the Jacobian (within the
        // square root of the gradient tolerance: the rounding near a
        // minimum, where rejected steps raise the damping too).
        let undamped = linearization.damping_ratio * lambda_used <= 1.0
            || linearization.cosine <= options.gradient_tolerance.sqrt();
        let short = index > 0
            && (previous - cost) <= PROGRESS * previous
            && step_norm
                <= options.parameter_tolerance
                    * (model.parameter_norm() + options.parameter_tolerance);
        let flat = index > 0 && (previous - cost).abs() <= options.cost_tolerance * previous;
        let converged = if !accepted {
            // A rejected step the model could measure (no refusal) that was
            // not shaped by the damping and is shorter than the tolerance:
            // the minimum is within rounding of the values (Ceres tests a
            // rejected step's length too); noise-free problems end here,
            // their cost at the rounding of zero, where every step's change
            // is rounding.
            (new_cost.is_some() && undamped && short).then_some(Criterion::ParameterTolerance)
        } else if undamped && short {
            Some(Criterion::ParameterTolerance)
        } else if undamped && flat {
            Some(Criterion::CostTolerance)
        } else {
            None
        };
        if let Some(why) = converged {
            verdict = why.verdict(options);
            break;
        }
        if accepted {
            // Shortened by the damping that refused steps raised: the steps
            // towards a minimum were refused.
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
                    "{why} at any damping (a singular or indefinite system, NaN, or values at \
                     the limits of f64's range)"
                )),
                (None, None) => Verdict::Stalled,
            };
            break;
        }
        last = Instant::now();
        if accepted {
            (linearization, linearized_in) = timed(|| model.linearize(cost, bounds));
        } else {
            linearized_in = Duration::ZERO;
        }
    }
    Minimized {
        final_cost: cost,
        history,
        verdict,
    }
}

/// `f()` and its wall time.
fn timed<T>(f: impl FnOnce() -> T) -> (T, Duration) {
    let start = Instant::now();
    let value = f();
    (value, start.elapsed())
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
