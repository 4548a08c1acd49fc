//! Robust losses as the solver uses them: the cost `½ ρ(s)` of a factor
//! whose squared residual norm is `s = ‖r‖²`, and the IRLS weight `ρ'(s)`
//! its normal equations are weighted with.
//!
//! Huber's and Cauchy's `ρ''(s)` are never positive, so the second-order
//! correction of Triggs et al. (which Ceres and apex-solver apply when
//! `ρ'' > 0`) is zero for both: the weighted Gauss–Newton system
//! `Jᵀ ρ' J δ = −Jᵀ ρ' r` is exactly theirs. The losses are apex-solver's
//! (and Ceres'): Huber `ρ(s) = s` up to `δ²`, `2δ√s − δ²` beyond; Cauchy
//! `ρ(s) = δ² ln(1 + s/δ²)`.

use slam_problems::Robust;

/// `ρ(s)`: `s` for least squares.
pub(crate) fn loss(robust: Option<Robust>, s: f64) -> f64 {
    match robust {
        None => s,
        Some(Robust::Huber(delta)) => {
            if s > delta * delta {
                2.0 * delta * s.sqrt() - delta * delta
            } else {
                s
            }
        }
        Some(Robust::Cauchy(delta)) => delta * delta * (s / (delta * delta)).ln_1p(),
    }
}

/// `ρ'(s)`, the weight of a factor's normal equations: 1 for least squares.
pub(crate) fn weight(robust: Option<Robust>, s: f64) -> f64 {
    match robust {
        Some(Robust::Huber(delta)) if s > delta * delta => delta / s.sqrt(),
        None | Some(Robust::Huber(_)) => 1.0,
        Some(Robust::Cauchy(delta)) => 1.0 / (1.0 + s / (delta * delta)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The weight is the derivative of the loss (central differences).
    #[test]
    fn weights_are_the_losses_derivatives() {
        for robust in [None, Some(Robust::Huber(2.0)), Some(Robust::Cauchy(1.5))] {
            for s in [0.1, 1.0, 3.9, 4.1, 30.0, 1e4] {
                let h = 1e-6 * s;
                let numeric = (loss(robust, s + h) - loss(robust, s - h)) / (2.0 * h);
                let w = weight(robust, s);
                assert!(
                    (numeric - w).abs() <= 1e-7 * w.max(1e-3),
                    "{robust:?} {s}: {numeric} vs {w}"
                );
            }
        }
        // Huber is continuous at δ²; Cauchy is below least squares.
        let huber = Some(Robust::Huber(2.0));
        assert!((loss(huber, 4.0) - 4.0).abs() < 1e-15);
        assert!(loss(Some(Robust::Cauchy(1.0)), 9.0) < 9.0);
    }
}
