//! Manifolds: tangent dimension, retraction and perturbation side.
//!
//! The Jacobian of a factor w.r.t. a variable `x` is the derivative of
//! `residual(retract(x, δ))` at `δ = 0`. Groups can be perturbed on either
//! side, chosen per variable ([`Perturbation`]), never crate-wide: document
//! 000 perturbs its camera pose on the left, document 001 its body pose on the
//! right.
//!
//! Two retractions are offered:
//! - [`Manifold::retract`] is exact (for example `Exp(δ) T` with the full SE(3)
//!   exponential). Numerical differentiation and solvers use it.
//! - [`Manifold::retract_first_order`] agrees with it to first order in `δ`
//!   at `δ = 0` (for example `(I + δ^) T`), which is all a derivative at
//!   `δ = 0` sees. Dual numbers and the symbolic tracer use it: it has no
//!   small-angle branch and costs a handful of operations. The result may be
//!   off the manifold by `O(|δ|²)` (a quaternion of norm `1 + O(|δ|²)`), which
//!   changes no first derivative of a smooth residual.
//!
//! A third map is optional: [`Manifold::local`], the inverse of `retract`
//! (the local coordinates of a point in the chart at another, Ceres'
//! `Minus`). Jacobians never need it; a C++ solver's manifold generated from
//! the type does (`slamjac generate --lang cpp` with Ceres, which refuses a
//! type without it).
//!
//! A type of your own becomes a variable by implementing [`Manifold`] (and
//! [`crate::Storage`]); the rules its retractions must follow to be
//! differentiated by dual numbers and traced by the symbolic engine are in
//! the trait's documentation. `examples/user-factor/` has two, a unit vector
//! on S² and Sim(3).

use nalgebra::{SMatrix, Scalar as NalgebraScalar};

use crate::dual::Dual;
use crate::scalar::Scalar;
use crate::storage::Storage;

/// Which side a group perturbation acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Perturbation {
    /// `x ← Exp(δ) · x`: document 000's convention for its camera pose and
    /// landmarks.
    Left,
    /// `x ← x · Exp(δ)`: document 001's body pose, and the retraction of
    /// GTSAM (`Pose3::retract`), manif (`rplus`) and apex-solver.
    Right,
}

impl Perturbation {
    /// `"left"` or `"right"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Perturbation::Left => "left",
            Perturbation::Right => "right",
        }
    }
}

/// A manifold with a retraction on a tangent space of dimension [`Manifold::DIM`].
///
/// A factor's Jacobian w.r.t. a variable is `∂r(x ⊞ δ)/∂δ` at `δ = 0`, with
/// `⊞` the variable's [`Manifold::retract_first_order`]; dual numbers
/// evaluate it and the symbolic tracer records it for the generated kernels.
/// Central differences (`factor_testing::assert_correct_jacobians`) and
/// solvers step with the exact [`Manifold::retract`].
///
/// # Rules for a retraction that is traced
///
/// 1. **Generic over `S: Scalar`.** One body runs on `f64`, `f32`, dual
///    numbers and the symbolic scalar, using only [`Scalar`]'s arithmetic and
///    functions (`sqrt`, `sin`, `cos`, `atan2`, `exp`, `ln`, `acos`, `asin`,
///    `atan`).
/// 2. **No comparison but [`Scalar::select_lt`].** No `<`, `if`, `match`,
///    `is_finite` or `f64` conversion on a value: a symbolic scalar has no
///    value to compare, and `select_lt` is what the tracer keeps as a
///    branch of the generated kernel ([`Scalar::abs`] is built on it).
/// 3. **Both arms are evaluated.** Every scalar type computes both arms of a
///    `select_lt` (a kernel evaluates both, then selects) and returns the
///    chosen one whole, value and derivative. The unselected arm may
///    therefore be non-finite (a closed form at `θ = 0`, `1/(s + z)` on the
///    wrong hemisphere) but must not panic (no `unwrap`, `assert!`, indexing
///    by a value). Select with `select_lt`, never with an arithmetic mask
///    `m a + (1 − m) b`, through which `0 · NaN = NaN` leaks.
/// 4. **Ties take `otherwise`.** `select_lt(a, b, x, y)` is `a < b`: at
///    `a == b` (including `−0 == 0`) and for a NaN it returns `y`, in every
///    scalar type (dual numbers compare real parts, the tracer folds
///    constant conditions with `<`, kernels use `<`). The `otherwise` arm must
///    be valid on the boundary itself.
/// 5. **`retract_first_order` agrees with `retract` to first order at
///    `δ = 0`**: the same point at `δ = 0` and the same derivative there,
///    which defines the tangent basis, hence the Jacobian's columns. Dual
///    numbers and generated kernels both use only `retract_first_order`, so
///    they agree with each other even when it is wrong; only
///    `assert_correct_jacobians`, whose central differences go through
///    `retract`, sees a disagreement. `retract` stays on the manifold;
///    `retract_first_order` may leave it by `O(|δ|²)`.
/// 6. **Every branch is decided by the point, not by `δ`.** A basis, a
///    chart or a sheet (`q` or `−q`) is chosen from `self`, so both
///    retractions use the same one and the map is smooth in `δ` near 0. A
///    condition on `δ` is allowed only where it holds strictly at `δ = 0`
///    (the small-angle case `θ² <` threshold); one tied at `δ = 0` gives a
///    one-sided derivative.
/// 7. **Small-angle branches on `θ²`, never on `θ`.** `θ = √(δ·δ)` has an
///    infinite derivative at `δ = 0`: a series in `θ` or a condition on it
///    makes the dual Jacobian `0 · ∞ = NaN` (reported as
///    [`crate::FactorError::NonFinite`]). Decide on `θ²` and write the series
///    in `θ²`, taking `√θ²` only in the exact arm:
///    [`crate::lie::so3::angle_coefficient`] does this, and
///    [`crate::lie::so3::sin_over_theta`] and
///    [`crate::lie::so3::one_minus_cos_over_theta2`] are ready-made.
/// 8. **The storage order is fixed.** [`crate::Storage::map_scalars`] and
///    [`crate::Storage::read_scalars`] visit the scalars in the order
///    [`crate::Storage::layout`] names them; that order is the layout of a
///    generated kernel's input arrays and of what users write. Changing it
///    changes every kernel's meaning: regenerate, and convert stored inputs.
/// 9. **The tangent is ordered as documented.** `delta[k]` is column `k` of
///    every Jacobian block of the variable; [`Manifold::tangent_description`]
///    names the columns in that order, and [`Manifold::DIM`] is how many are
///    read.
/// 10. **No allocation is needed.** Values are fixed-size (`nalgebra`'s
///     static matrices, arrays of scalars) and `delta` is read by index, so
///     a retraction costs no heap traffic in a solver's inner loop.
/// 11. **[`Manifold::seeded`], if overridden, is the derivative of
///     `retract_first_order`.** Dual numbers start from it; its default
///     ([`seeded_through_retraction`]) is right by construction, an
///     override (a closed form, to save the retraction's dual arithmetic)
///     must agree with the default to rounding.
///
/// [`Manifold::local`], when a type gives it, is traced too (a C++ solver's
/// manifold is generated from it and from `retract`) and follows the same
/// rules, its branches decided by `self` (rule 6) or holding strictly at
/// `other = self` (rule 7: it is differentiated there).
///
/// A manifold that is not a group (S²) ignores the side and says so in its
/// description. Where no basis is continuous everywhere (on S², by the
/// hairy-ball theorem), a branch chooses one per region: the Jacobian is
/// exact in that region's basis, and Jacobians on either side of a boundary
/// differ by the change of basis between them.
#[diagnostic::on_unimplemented(
    message = "`{Self}` cannot be a variable: it does not implement `Manifold<{S}>`",
    label = "no tangent space and retraction over `{S}`",
    note = "a `#[variable]` needs a tangent space: `{S}`, nalgebra's vectors (a point is a \
            `Vector3<{S}>`, not a `Point3`), `factor_core`'s Lie and geometry types, or a type of yours implementing `factor_core::Manifold<{S}>` \
            (see its documentation for the rules); a field without `#[variable]` is a constant \
            and needs `Storage<{S}>` only"
)]
pub trait Manifold<S: Scalar>: Sized {
    /// Tangent dimension.
    const DIM: usize;

    /// Exact retraction `x ⊞ δ` on the given side. `delta.len() == DIM`.
    fn retract(&self, delta: &[S], side: Perturbation) -> Self;

    /// A map that agrees with [`Manifold::retract`] to first order at `δ = 0`
    /// (rule 5); the default is `retract` itself, which is then traced and
    /// must follow the rules too.
    fn retract_first_order(&self, delta: &[S], side: Perturbation) -> Self {
        self.retract(delta, side)
    }

    /// The perturbation and the tangent's column order in words, for reports.
    fn tangent_description(side: Perturbation) -> &'static str;

    /// `self` over [`Dual<N>`] numbers seeded through its chart: each stored
    /// scalar of `self ⊞ δ` ([`Manifold::retract_first_order`]) with its
    /// derivative w.r.t. `δ` at `δ = 0` placed at coordinates
    /// `offset..offset + D` of a stacked tangent of `N` (`D` is
    /// [`Manifold::DIM`]). A residual evaluated on every variable so seeded
    /// differentiates w.r.t. all their tangents in one pass, with no
    /// retraction evaluated at the stacked tangent's width:
    /// `#[derive(Factor)]`'s `linearize_dual` does this.
    ///
    /// The default is [`seeded_through_retraction`] (the retraction on dual
    /// numbers as wide as this variable's tangent); this crate's Lie groups
    /// (but Sim(3)), lines and plane override it with the closed form of
    /// their retraction's derivative, which costs a few products instead of
    /// the retraction's dual arithmetic. An override must agree with the default to
    /// rounding (rule 11 above).
    ///
    /// # Panics
    ///
    /// If `D` is not [`Manifold::DIM`] or `offset + D > N`.
    #[inline(always)]
    fn seeded<const D: usize, const N: usize>(
        &self,
        side: Perturbation,
        offset: usize,
    ) -> <Self as Storage<S>>::With<Dual<N>>
    where
        S: Into<f64>,
        Self: Storage<S>,
        <Self as Storage<S>>::With<Dual<D>>: Manifold<Dual<D>>
            + Storage<Dual<D>, With<Dual<N>> = <Self as Storage<S>>::With<Dual<N>>>,
    {
        seeded_through_retraction::<S, Self, D, N>(self, side, offset)
    }

    /// The local coordinates of `other` in the chart at `self`: the tangent
    /// `δ` with `self.retract(δ, side) == other`, written into `delta`
    /// (`DIM` entries), on the largest domain the retraction is invertible
    /// on (a rotation's up to the angle `2π` on the quaternion sphere, so
    /// that retracting by it gives back `other`'s own stored scalars, not
    /// `−q`). Optional: the default gives [`NoLocal`], and everything but a
    /// generated solver manifold works without it (Ceres' `Minus` and
    /// `MinusJacobian` are it and its derivative at `other = self`).
    ///
    /// It is traced like the retractions (the rules above) and
    /// differentiated w.r.t. `other` at `other = self`, where `other`'s
    /// scalars may leave the manifold: write it so that it stays smooth
    /// there (a quaternion's inverse as its conjugate, a logarithm that is
    /// homogeneous in the quaternion's scale).
    fn local(&self, other: &Self, side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        let _ = (other, side, delta);
        Err(NoLocal)
    }
}

/// What a type without [`Manifold::local`] gives: the inverse of its
/// retraction is not known.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NoLocal;

/// One map of a variable's chart, as a code generator traces it
/// (`Factor::chart_over`, which the derive dispatches to the variable's
/// type).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChartMap {
    /// [`Manifold::retract`]: `argument` is the tangent `δ`, the output the
    /// retracted value's stored scalars.
    Retract,
    /// [`Manifold::retract_first_order`], read and written as `Retract`.
    RetractFirstOrder,
    /// [`Manifold::local`]: `argument` is the other value's stored scalars,
    /// the output its local coordinates (a tangent).
    Local,
}

/// The default of [`Manifold::seeded`]: `x` lifted to `Dual<D>`, retracted to
/// first order by the `D` unit seeds `δ_k = e_k`, every stored scalar then
/// widened to `Dual<N>` at `offset`. The retraction runs once, on dual
/// numbers as wide as `x`'s own tangent.
///
/// ```
/// use factor_core::dual::Dual;
/// use factor_core::lie::{Quaternion, So3};
/// use factor_core::manifold::seeded_through_retraction;
/// use factor_core::Perturbation;
///
/// // The half-turn about z, `q = k`, perturbed on the right, `q ⊗ [δ/2, 1]`,
/// // its tangent at coordinates 2..5 of 5: `∂q/∂δ_x = ½ k ⊗ i = ½ j`,
/// // `∂q/∂δ_y = ½ k ⊗ j = −½ i`.
/// let rotation = So3::from_quaternion(Quaternion::new(0.0, 0.0, 1.0, 0.0));
/// let lifted: So3<Dual<5>> =
///     seeded_through_retraction::<f64, _, 3, 5>(&rotation, Perturbation::Right, 2);
/// assert_eq!(lifted.quaternion.z.re, 1.0);
/// assert_eq!(lifted.quaternion.y.eps, [0.0, 0.0, 0.5, 0.0, 0.0]);
/// assert_eq!(lifted.quaternion.x.eps, [0.0, 0.0, 0.0, -0.5, 0.0]);
/// ```
///
/// # Panics
///
/// If `D` is not `x`'s tangent dimension or `offset + D > N`.
#[inline(always)]
pub fn seeded_through_retraction<S, V, const D: usize, const N: usize>(
    x: &V,
    side: Perturbation,
    offset: usize,
) -> V::With<Dual<N>>
where
    S: Scalar + Into<f64>,
    V: Storage<S>,
    V::With<Dual<D>>: Manifold<Dual<D>> + Storage<Dual<D>, With<Dual<N>> = V::With<Dual<N>>>,
{
    assert_eq!(
        D,
        <V::With<Dual<D>> as Manifold<Dual<D>>>::DIM,
        "`D` is the variable's tangent dimension"
    );
    let delta: [Dual<D>; D] = std::array::from_fn(|k| Dual::variable(0.0, k));
    x.map_scalars(&mut |s| Dual::<D>::constant(s.into()))
        .retract_first_order(&delta, side)
        .map_scalars(&mut |s| s.widen::<N>(offset))
}

/// Scalars are a 1-dimensional vector space.
impl<S: Scalar> Manifold<S> for S {
    const DIM: usize = 1;
    fn retract(&self, delta: &[S], _side: Perturbation) -> Self {
        *self + delta[0]
    }
    /// `x + δ`: the derivative is `e_offset`.
    #[inline(always)]
    fn seeded<const D: usize, const N: usize>(
        &self,
        _side: Perturbation,
        offset: usize,
    ) -> <Self as Storage<S>>::With<Dual<N>>
    where
        S: Into<f64>,
    {
        Dual::variable((*self).into(), offset)
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "additive: x ← x + δ"
    }
    fn local(&self, other: &Self, _side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        delta[0] = *other - *self;
        Ok(())
    }
}

/// Fixed-size vectors and matrices are vector spaces: `x ← x + δ`, with `δ`
/// in column-major order (for a vector, its entries in order).
impl<S: Scalar + NalgebraScalar, const R: usize, const C: usize> Manifold<S> for SMatrix<S, R, C> {
    const DIM: usize = R * C;
    fn retract(&self, delta: &[S], _side: Perturbation) -> Self {
        let mut out = *self;
        for (x, d) in out.iter_mut().zip(delta) {
            *x += *d;
        }
        out
    }
    /// `x + δ`: entry `k` (column-major) has the derivative `e_{offset + k}`.
    #[inline(always)]
    fn seeded<const D: usize, const N: usize>(
        &self,
        _side: Perturbation,
        offset: usize,
    ) -> <Self as Storage<S>>::With<Dual<N>>
    where
        S: Into<f64>,
    {
        let mut k = offset;
        self.map(|x| {
            let seeded = Dual::variable(x.into(), k);
            k += 1;
            seeded
        })
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "additive: x ← x + δ, columns δ in the vector's order"
    }
    fn local(&self, other: &Self, _side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        for ((d, x), y) in delta.iter_mut().zip(self.iter()).zip(other.iter()) {
            *d = *y - *x;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn vectors_retract_additively_on_either_side() {
        let x = Vector3::new(1.0, 2.0, 3.0);
        let d = [0.5, -1.0, 2.0];
        assert_eq!(
            x.retract(&d, Perturbation::Left),
            Vector3::new(1.5, 1.0, 5.0)
        );
        assert_eq!(
            x.retract(&d, Perturbation::Right),
            Vector3::new(1.5, 1.0, 5.0)
        );
        assert_eq!(<Vector3<f64> as Manifold<f64>>::DIM, 3);
    }
}
