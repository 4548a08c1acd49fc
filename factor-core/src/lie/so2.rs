//! SO(2): planar rotations stored as `(cos ρ, sin ρ)`, the `W` factor of the
//! orthonormal line representation (document 000 §III).

use crate::manifold::{Manifold, Perturbation};
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

/// `W ← R(δ) W` (either side: SO(2) is commutative).
impl<S: Scalar> Manifold<S> for So2<S> {
    const DIM: usize = 1;
    fn retract(&self, delta: &[S], _side: Perturbation) -> Self {
        Self::exp(delta[0]).compose(self)
    }
    fn retract_first_order(&self, delta: &[S], _side: Perturbation) -> Self {
        Self::new(S::one(), delta[0]).compose(self)
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "W ← R(δ) W, one column δ"
    }
}
