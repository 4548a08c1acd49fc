//! [`LieGroup`]: the verbs every group of [`crate::lie`] shares, under one
//! name each, generic over the scalar.
//!
//! The vocabulary is that of manif's `LieGroupBase`/`TangentBase` and of
//! Sophus: `identity`, `compose`, `inverse`, `act` on a point, `exp`/`log`
//! between the group and its tangent space at the identity, the adjoint, the
//! left and right Jacobians and their inverses, and `plus`/`minus` on either
//! side.
//!
//! # Conventions
//!
//! - `Exp(τ)` is the exact exponential; `Log` its inverse on the principal
//!   domain (rotation angle `θ ≤ π` for SO(3) and SE(3); `θ < 2π` for unit
//!   quaternions, whose `log` does not identify `q` with `−q`).
//! - Pose tangents are `τ = [ω, ρ]`, rotation first, with
//!   `Exp([ω, ρ]) = [Exp(ω), Jl(ω) ρ]`. Peers that order `[ρ, θ]` (manif,
//!   apex-solver) have every 6×6 matrix below with its blocks swapped
//!   (`Ad = [[R, t^R], [0, R]]` there); GTSAM orders `[ω, v]` as here.
//! - `plus(X, τ, Right) = X ⊕ τ = X Exp(τ)`, `plus(X, τ, Left) = Exp(τ) X`;
//!   `minus(Y, X, Right) = Log(X⁻¹ Y)`, `minus(Y, X, Left) = Log(Y X⁻¹)`, so
//!   `minus(plus(X, τ, s), X, s) = τ` on the principal domain.
//! - Adjoint: `X Exp(τ) X⁻¹ = Exp(Ad_X τ)`; `Ad_{XY} = Ad_X Ad_Y`,
//!   `Ad_{X⁻¹} = Ad_X⁻¹`.
//! - Jacobians, with `θ = |ω|` and `W = [ω]×` (`hat(ω) b = ω × b`):
//!   `Jl(ω) = I + (1 − cos θ)/θ² W + (θ − sin θ)/θ³ W²` for rotations,
//!   `Jr(τ) = Jl(−τ)` for every group, and to first order in `δ`
//!   `Exp(τ + δ) = Exp(Jl(τ) δ) Exp(τ) = Exp(τ) Exp(Jr(τ) δ)`. Hence
//!   `Jl(τ) = Ad_{Exp(τ)} Jr(τ)`, and `Jr(τ)⁻¹ δ` is the first-order change of
//!   `minus(Exp(τ) Exp(δ), I, Right)`.
//!
//! # Moving a Jacobian between perturbation sides
//!
//! A right perturbation `X Exp(δ)` and a left one `Exp(δ') X` are the same
//! element when `δ' = Ad_X δ`. So for any function `f` of `X`, with
//! `J_right = ∂f(X Exp(δ))/∂δ` and `J_left = ∂f(Exp(δ) X)/∂δ` at `δ = 0`:
//!
//! - `J_left = J_right · Ad_{X⁻¹}`, and `J_right = J_left · Ad_X`;
//! - a covariance `Σ` of a right tangent is `Ad_X Σ Ad_Xᵀ` as a left one.
//!
//! The pose variables of `slamjac` factors declare their side
//! ([`Perturbation`]); an estimator that perturbs the other side converts
//! the factor's block this way.

use std::ops::Neg;

use crate::manifold::Perturbation;
use crate::scalar::Scalar;

/// A Lie group over scalar `S`, with its tangent space at the identity.
///
/// Only [`LieGroup::right_jacobian`], [`LieGroup::right_jacobian_inverse`],
/// [`LieGroup::plus`] and [`LieGroup::minus`] have default definitions:
/// `Jr(τ) = Jl(−τ)` and the `⊕`/`⊖` of the module documentation.
pub trait LieGroup<S: Scalar>: Sized + Copy {
    /// Degrees of freedom, the tangent dimension.
    const DOF: usize;
    /// A tangent vector (`DOF` coordinates).
    type Tangent: Copy + Neg<Output = Self::Tangent>;
    /// A `DOF × DOF` matrix: adjoints and Jacobians (rows and columns in the
    /// tangent's coordinate order).
    type Jacobian: Copy;
    /// A point the group acts on.
    type Point: Copy;

    /// The identity `I`.
    fn identity() -> Self;
    /// `self · rhs`.
    fn compose(&self, rhs: &Self) -> Self;
    /// `self⁻¹`.
    fn inverse(&self) -> Self;
    /// The action on a point: `R p` for rotations, `R p + t` for poses.
    fn act(&self, point: &Self::Point) -> Self::Point;
    /// `Exp(τ)`.
    fn exp(tau: &Self::Tangent) -> Self;
    /// `Log(self)`, on the principal domain.
    fn log(&self) -> Self::Tangent;
    /// `Ad_X`: `X Exp(τ) X⁻¹ = Exp(Ad_X τ)`.
    fn adjoint(&self) -> Self::Jacobian;
    /// `Jl(τ)`: `Exp(τ + δ) ≈ Exp(Jl(τ) δ) Exp(τ)`.
    fn left_jacobian(tau: &Self::Tangent) -> Self::Jacobian;
    /// `Jl(τ)⁻¹`.
    fn left_jacobian_inverse(tau: &Self::Tangent) -> Self::Jacobian;

    /// `Jr(τ) = Jl(−τ)`: `Exp(τ + δ) ≈ Exp(τ) Exp(Jr(τ) δ)`.
    fn right_jacobian(tau: &Self::Tangent) -> Self::Jacobian {
        Self::left_jacobian(&-*tau)
    }
    /// `Jr(τ)⁻¹ = Jl(−τ)⁻¹`.
    fn right_jacobian_inverse(tau: &Self::Tangent) -> Self::Jacobian {
        Self::left_jacobian_inverse(&-*tau)
    }
    /// `X ⊕ τ`: `X Exp(τ)` on the right, `Exp(τ) X` on the left.
    fn plus(&self, tau: &Self::Tangent, side: Perturbation) -> Self {
        let step = Self::exp(tau);
        match side {
            Perturbation::Right => self.compose(&step),
            Perturbation::Left => step.compose(self),
        }
    }
    /// `self ⊖ other`: `Log(other⁻¹ self)` on the right, `Log(self other⁻¹)`
    /// on the left; the inverse of [`LieGroup::plus`] on the same side.
    fn minus(&self, other: &Self, side: Perturbation) -> Self::Tangent {
        let inverse = other.inverse();
        match side {
            Perturbation::Right => inverse.compose(self).log(),
            Perturbation::Left => self.compose(&inverse).log(),
        }
    }
}
