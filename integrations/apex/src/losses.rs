//! Robust losses that keep their digits, served to apex-solver as its
//! `LossFunction` (`[ρ(s), ρ'(s), ρ''(s)]` of the squared residual norm
//! `s`; apex's cost is `½ ρ(s)` per block, its step is built from `ρ'`,
//! `ρ''`).
//!
//! apex-solver 1.5's `CauchyLoss` computes `ρ(s) = δ² ln(1 + s c)` with
//! `c = 1/δ²`: for a large `δ`, `1 + s c` rounds to 1 and the cost it
//! reports is 0 (`--robust cauchy:1e10` printed a cost of 0 before and
//! after the solve), where the loss is least squares to within `s/δ²`.
//! [`Cauchy`] computes the same function as `s · ln(1 + x)/x` with
//! `x = (√s/δ)²` (`ln_1p`, no rounding of `1 + x`; `s` itself when `x`
//! underflows), and as `δ² (ln s − 2 ln δ)` when `x` is beyond `10¹⁶`
//! (where `ln(1 + x) = ln x` in `f64`), so that neither `δ²` nor `x`
//! overflows. Its derivatives are those apex uses, `ρ' = 1/(1 + x)` and
//! `ρ'' = −(ρ'/δ)²`. apex's `HuberLoss` (`s`, or `2δ√s − δ²` beyond `δ²`)
//! loses nothing and is used as it is.

use apex_solver::core::loss_functions::{HuberLoss, LossFunction};
use slam_problems::Robust;

use crate::options::BuildError;

/// Where `ln(1 + x)` is `ln x` in `f64`.
const LOG_IS_LINEAR: f64 = 1e16;

/// Cauchy's loss `ρ(s) = δ² ln(1 + s/δ²)`, computed without cancellation
/// (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cauchy {
    delta: f64,
}

impl Cauchy {
    /// The loss of scale `delta` (finite, above 0).
    pub fn new(delta: f64) -> Result<Self, String> {
        if delta.is_finite() && delta > 0.0 {
            Ok(Cauchy { delta })
        } else {
            Err(format!(
                "Cauchy's δ must be finite and above 0, not {delta}"
            ))
        }
    }
}

impl LossFunction for Cauchy {
    fn evaluate(&self, s: f64) -> [f64; 3] {
        let t = s.sqrt() / self.delta;
        let x = t * t;
        let rho = if x == 0.0 {
            s
        } else if x <= LOG_IS_LINEAR {
            s * (x.ln_1p() / x)
        } else {
            self.delta * self.delta * (s.ln() - 2.0 * self.delta.ln())
        };
        let weight = 1.0 / (1.0 + x);
        [rho, weight, -(weight / self.delta).powi(2)]
    }
}

/// The loss `robust` served to apex-solver: apex's Huber, this module's
/// Cauchy.
pub(crate) fn apex_loss(robust: Robust) -> Result<Box<dyn LossFunction + Send + Sync>, BuildError> {
    match robust {
        Robust::Huber(delta) => HuberLoss::new(delta)
            .map(|l| Box::new(l) as _)
            .map_err(|e| BuildError::Solver(e.to_string())),
        Robust::Cauchy(delta) => Cauchy::new(delta)
            .map(|l| Box::new(l) as _)
            .map_err(BuildError::Solver),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn relative(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    /// For `x = s/δ²` below 1e-8 the series `s (1 − x/2 + x²/3)` is exact
    /// in `f64`: a large δ is least squares.
    #[test]
    fn a_large_scale_is_least_squares() {
        for (delta, s) in [(1e10, 0.2), (1e10, 3.7e4), (1e5, 0.5), (1e100, 1e150)] {
            let x: f64 = s / (delta * delta);
            let series = s * (1.0 - x / 2.0 + x * x / 3.0);
            let [rho, weight, _] = Cauchy::new(delta).unwrap().evaluate(s);
            assert!(relative(rho, series) <= 1e-15, "δ {delta}, s {s}: {rho}");
            assert!(relative(weight, 1.0) <= 1e-8);
        }
    }

    /// Where `δ²`, `x = s/δ²` and `1 + x` are exact and `ln(1 + x)` is not
    /// small, the plain formula is exact to a few roundings; far beyond
    /// `δ²`, `ρ = δ² ln(s/δ²)` to within `δ²/s`.
    #[test]
    fn moderate_and_huge_residuals_agree_with_the_plain_formula() {
        for (delta, s) in [(1.0_f64, 0.5), (2.0, 30.0), (0.5, 0.75), (0.25, 1e4)] {
            let naive = delta * delta * (1.0 + s / (delta * delta)).ln();
            let [rho, ..] = Cauchy::new(delta).unwrap().evaluate(s);
            assert!(relative(rho, naive) <= 1e-15, "δ {delta}, s {s}");
        }
        // δ = 1e-100, s = 1e250: x = 1e450 overflows; ρ = 1e-200 ln(1e450).
        let [rho, weight, second] = Cauchy::new(1e-100).unwrap().evaluate(1e250);
        let expected = 1e-200 * 450.0 * std::f64::consts::LN_10;
        assert!(relative(rho, expected) <= 1e-15, "{rho} vs {expected}");
        // ρ' = 1/(1 + 1e450) underflows to 0, and with it ρ''.
        assert!(weight == 0.0 && second == 0.0, "{weight}, {second}");
    }

    /// `ρ'` and `ρ''` are the derivatives of `ρ` (central differences).
    #[test]
    fn the_derivatives_are_those_of_the_cost() {
        let loss = Cauchy::new(1.5).unwrap();
        for s in [0.01, 1.0, 2.25, 40.0] {
            let h = 1e-5 * s;
            let [rho, weight, second] = loss.evaluate(s);
            let (plus, minus) = (loss.evaluate(s + h), loss.evaluate(s - h));
            assert!(relative((plus[0] - minus[0]) / (2.0 * h), weight) < 1e-8);
            assert!(relative((plus[1] - minus[1]) / (2.0 * h), second) < 1e-6);
            assert!(rho > 0.0);
        }
        assert!(Cauchy::new(0.0).is_err() && Cauchy::new(f64::INFINITY).is_err());
    }
}
