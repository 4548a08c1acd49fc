//! `W(ω, σ) = ∫₀¹ e^{tσ} Exp(tω) dt = a I + b [ω]× + c [ω]×²`: the matrix
//! that maps `ρ` to the translation of `Exp([ω, ρ, σ])` (Strasdat's `W`; for
//! `σ = 0` it is SO(3)'s `Jl(ω)`), and its inverse for `Log`.
//!
//! With `θ = ‖ω‖` and `Exp(tω) = I + sin(tθ)/θ [ω]× + (1 − cos tθ)/θ² [ω]×²`,
//!
//! - `a = ∫ e^{tσ} dt = (e^σ − 1)/σ`,
//! - `b = ∫ e^{tσ} sin(tθ)/θ dt`, `c = ∫ e^{tσ} (1 − cos tθ)/θ² dt`.
//!
//! Integrating, with `g = a − e^σ sin θ/θ`, `h = (1 − cos θ)/θ²` and
//! `r² = σ² + θ²`: `b = (e^σ h θ² − σ g)/r²`, `c = (σ e^σ h + g)/r²`. These
//! closed forms have no `1/θ`, only `1/r²`, and lose about `ε/r²` to
//! cancellation; so below `r² <` [`SERIES_RADIUS_SQUARED`] (`r < 0.2`) the
//! double Taylor series in `σ` and `θ²`, to total degree
//! [`SERIES_DEGREE`] in `(σ, θ)`, is used instead:
//!
//! `b = Σ σʲ (−θ²)ᵏ / (j! (2k+1)! (j+2k+2))`, `c = Σ σʲ (−θ²)ᵏ / (j! (2k+2)! (j+2k+3))`
//!
//! (from `sin(tθ)/θ = Σ (−θ²)ᵏ t^{2k+1}/(2k+1)!`,
//! `(1 − cos tθ)/θ² = Σ (−θ²)ᵏ t^{2k+2}/(2k+2)!` and `∫₀¹ tⁿ dt = 1/(n+1)`),
//! whose first omitted terms are below `1e-17` there. `a` has its own series
//! below `σ² <` [`SERIES_RADIUS_SQUARED`]. Every branch is decided on `σ²`
//! and `θ²`, never on `θ` (see the rules of `factor_core::manifold`).
//!
//! Measured against the power series `Σ Aᵏ/(k+1)!`, `A = σI + [ω]×`, on a
//! 401 × 401 grid of `θ ∈ [0, π]`, `σ ∈ [−3, 3]` (refined towards 0) and on
//! the switch circle `r = 0.2` scaled by `1 ± 1e-9`: `W` within `2.3e-15` of
//! its largest entry (`1.0e-15` for `0.1 < r < 0.4`, around the switch),
//! `W⁻¹` within `2.8e-15`; `tests/sim3_group.rs` checks `4e-15` at random
//! and edge-case arguments.

use factor_core::Scalar;
use factor_core::lie::so3::{hat, one_minus_cos_over_theta2, sin_over_theta};
use factor_core::linalg::squared_norm;
use nalgebra::{Matrix3, Vector3};

/// Below this `r² = σ² + θ²` the coefficients of `W` are the double series.
pub const SERIES_RADIUS_SQUARED: f64 = 0.04;

/// The total degree in `(σ, θ)` of the series kept (`θ²ᵏ` counts `2k`).
pub const SERIES_DEGREE: usize = 12;

/// `W = a I + b [ω]× + c [ω]×²`.
#[derive(Debug, Clone, Copy)]
pub struct WCoefficients<S> {
    /// `(e^σ − 1)/σ`.
    pub a: S,
    /// `∫₀¹ e^{tσ} sin(tθ)/θ dt`.
    pub b: S,
    /// `∫₀¹ e^{tσ} (1 − cos tθ)/θ² dt`.
    pub c: S,
}

/// `n!` for the series coefficients (exact in `f64` for `n ≤ 18`).
fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

/// `Σ_{j ≤ degree} σʲ · coefficient(j)`, by Horner's rule.
fn polynomial<S: Scalar>(sigma: S, degree: usize, coefficient: impl Fn(usize) -> f64) -> S {
    (0..=degree).rev().fold(S::zero(), |acc, j| {
        acc * sigma + S::from_f64(coefficient(j))
    })
}

/// `Σ_{j + 2k ≤ SERIES_DEGREE} σʲ (−θ²)ᵏ coefficient(j, k)`.
fn double_series<S: Scalar>(sigma: S, theta2: S, coefficient: impl Fn(usize, usize) -> f64) -> S {
    (0..=SERIES_DEGREE / 2).rev().fold(S::zero(), |acc, k| {
        let in_sigma = polynomial(sigma, SERIES_DEGREE - 2 * k, |j| coefficient(j, k));
        in_sigma - theta2 * acc
    })
}

/// `(e^σ − 1)/σ`, by its series `Σ σʲ/(j+1)!` for small `σ`.
fn exp_minus_one_over<S: Scalar>(sigma: S) -> S {
    let series = polynomial(sigma, SERIES_DEGREE, |j| 1.0 / factorial(j + 1));
    let exact = (sigma.exp() - S::one()) / sigma;
    let small = S::from_f64(SERIES_RADIUS_SQUARED);
    S::select_lt(sigma * sigma, small, series, exact)
}

/// The coefficients of `W(ω, σ)` from `σ` and `θ² = ‖ω‖²`.
pub fn w_coefficients<S: Scalar>(sigma: S, theta2: S) -> WCoefficients<S> {
    let a = exp_minus_one_over(sigma);
    let r2 = sigma * sigma + theta2;
    let series_b = double_series(sigma, theta2, |j, k| {
        1.0 / (factorial(j) * factorial(2 * k + 1) * (j + 2 * k + 2) as f64)
    });
    let series_c = double_series(sigma, theta2, |j, k| {
        1.0 / (factorial(j) * factorial(2 * k + 2) * (j + 2 * k + 3) as f64)
    });
    let e = sigma.exp();
    let h = one_minus_cos_over_theta2(theta2);
    let g = a - e * sin_over_theta(theta2);
    let closed_b = (e * h * theta2 - sigma * g) / r2;
    let closed_c = (sigma * e * h + g) / r2;
    let small = S::from_f64(SERIES_RADIUS_SQUARED);
    WCoefficients {
        a,
        b: S::select_lt(r2, small, series_b, closed_b),
        c: S::select_lt(r2, small, series_c, closed_c),
    }
}

/// `a I + b W + c W²`, `W = [ω]×`.
fn quadratic_in_hat<S: Scalar>(omega: &Vector3<S>, a: S, b: S, c: S) -> Matrix3<S> {
    let w = hat(omega);
    Matrix3::identity().map(|x| a * x) + w.map(|x| b * x) + (w * w).map(|x| c * x)
}

/// `W(ω, σ)`.
pub fn w_matrix<S: Scalar>(omega: &Vector3<S>, sigma: S) -> Matrix3<S> {
    let WCoefficients { a, b, c } = w_coefficients(sigma, squared_norm(omega));
    quadratic_in_hat(omega, a, b, c)
}

/// `W(ω, σ)⁻¹`, for `θ < 2π`. It is again `x I + y W + z W²` (`W³ = −θ² W`):
/// with `α = a − θ² c` and `Δ = α² + θ² b²` (`α + iθb = (e^{σ+iθ} − 1)/(σ+iθ)`,
/// so `Δ > 0` unless `σ = 0`, `θ ∈ 2πℤ∖{0}`), `x = 1/a`, `y = −b/Δ`,
/// `z = (b² − α c)/(a Δ)`.
pub fn w_matrix_inverse<S: Scalar>(omega: &Vector3<S>, sigma: S) -> Matrix3<S> {
    let theta2 = squared_norm(omega);
    let WCoefficients { a, b, c } = w_coefficients(sigma, theta2);
    let alpha = a - theta2 * c;
    let delta = alpha * alpha + theta2 * b * b;
    quadratic_in_hat(
        omega,
        a.recip(),
        -b / delta,
        (b * b - alpha * c) / (a * delta),
    )
}
