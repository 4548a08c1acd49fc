//! SO(2): planar rotations stored as `(cos ρ, sin ρ)`, the `W` factor of the
//! orthonormal line representation (document 000 §III).

use nalgebra::{Matrix1, Matrix2, Vector1, Vector2};

use crate::dual::Dual;
use crate::lie::LieGroup;
use crate::manifold::{Manifold, NoLocal, Perturbation};
use crate::scalar::Scalar;
use crate::storage::{Layout, Storage};

/// `W = [[c, −s], [s, c]]` with `c² + s² = 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct So2<S> {
    /// `cos ρ` (document 000's `ω₁`).
    pub cos: S,
    /// `sin ρ` (document 000's `ω₂`).
    pub sin: S,
}

impl<S: Scalar> So2<S> {
    /// From a unit complex number `(cos, sin)` (not re-normalised).
    pub fn new(cos: S, sin: S) -> Self {
        So2 { cos, sin }
    }

    /// `W(ρ)`.
    pub fn exp(angle: S) -> Self {
        Self::new(angle.cos(), angle.sin())
    }

    /// `ρ = atan2(sin, cos)`.
    pub fn log(&self) -> S {
        self.sin.atan2(self.cos)
    }

    /// `self · rhs` (SO(2) is commutative).
    pub fn compose(&self, rhs: &Self) -> Self {
        Self::new(
            self.cos * rhs.cos - self.sin * rhs.sin,
            self.sin * rhs.cos + self.cos * rhs.sin,
        )
    }

    /// `W⁻¹ = Wᵀ`, the rotation by `−ρ`.
    pub fn inverse(&self) -> Self {
        Self::new(self.cos, -self.sin)
    }

    /// `W = [[cos ρ, −sin ρ], [sin ρ, cos ρ]]`.
    pub fn matrix(&self) -> Matrix2<S> {
        Matrix2::new(self.cos, -self.sin, self.sin, self.cos)
    }
}

/// Stored `[cos, sin]`.
impl<S: Scalar> Storage<S> for So2<S> {
    type With<T: Scalar> = So2<T>;
    const SCALARS: usize = 2;
    fn layout() -> Layout {
        Layout::array(&["cos", "sin"])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> So2<T> {
        So2::new(f(self.cos), f(self.sin))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        So2::new(next(), next())
    }
}

/// SO(2) in the [`LieGroup`] vocabulary: tangent `[ρ]`, acting on planar
/// points by `W p`. The group is commutative, so the adjoint and all four
/// Jacobians are `[1]` and both sides of `plus`/`minus` agree.
impl<S: Scalar> LieGroup<S> for So2<S> {
    const DOF: usize = 1;
    type Tangent = Vector1<S>;
    type Jacobian = Matrix1<S>;
    type Point = Vector2<S>;

    fn identity() -> Self {
        Self::new(S::one(), S::zero())
    }
    fn compose(&self, rhs: &Self) -> Self {
        So2::compose(self, rhs)
    }
    fn inverse(&self) -> Self {
        So2::inverse(self)
    }
    fn act(&self, point: &Vector2<S>) -> Vector2<S> {
        crate::linalg::mul(&self.matrix(), point)
    }
    fn exp(tau: &Vector1<S>) -> Self {
        So2::exp(tau[0])
    }
    fn log(&self) -> Vector1<S> {
        Vector1::new(So2::log(self))
    }
    fn adjoint(&self) -> Matrix1<S> {
        Matrix1::identity()
    }
    fn left_jacobian(_tau: &Vector1<S>) -> Matrix1<S> {
        Matrix1::identity()
    }
    fn left_jacobian_inverse(_tau: &Vector1<S>) -> Matrix1<S> {
        Matrix1::identity()
    }
}

/// `W ← R(δ) W` (either side: SO(2) is commutative).
impl<S: Scalar> Manifold<S> for So2<S> {
    const DIM: usize = 1;
    fn retract(&self, delta: &[S], _side: Perturbation) -> Self {
        Self::exp(delta[0]).compose(self)
    }
    fn retract_first_order(&self, delta: &[S], _side: Perturbation) -> Self {
        Self::new(S::one(), delta[0]).compose(self)
    }
    /// In closed form: `[1, δ] ∘ [c, s] = [c − δ s, s + δ c]`, so the
    /// derivatives are `−s` and `c` at coordinate `offset`.
    #[inline(always)]
    fn seeded<const D: usize, const N: usize>(
        &self,
        _side: Perturbation,
        offset: usize,
    ) -> <Self as Storage<S>>::With<Dual<N>>
    where
        S: Into<f64>,
    {
        let (c, s): (f64, f64) = (self.cos.into(), self.sin.into());
        let (mut cos, mut sin) = (Dual::constant(c), Dual::constant(s));
        cos.eps[offset] = -s;
        sin.eps[offset] = c;
        So2::new(cos, sin)
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "W ← R(δ) W, one column δ"
    }
    /// `δ = atan2` of `other · self⁻¹`, in `(−π, π]`.
    fn local(&self, other: &Self, _side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        delta[0] = other.compose(&self.inverse()).log();
        Ok(())
    }
}
