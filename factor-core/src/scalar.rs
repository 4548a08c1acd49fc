//! The scalar abstraction every residual and all geometry are written against.
//!
//! [`Scalar`] is implemented by `f64`, `f32`, this crate's dual numbers
//! ([`crate::dual::Dual`], what every linearization runs on) and num-dual's
//! statically sized dual vectors ([`DualSVec64`], for code written against
//! them); a symbolic scalar (a small `Copy` handle into an expression arena)
//! implements it too, so one residual definition is evaluated,
//! differentiated and traced without a second copy of anything.
//!
//! Design decisions:
//! - The bounds are only what `nalgebra` needs for storage and products
//!   (`nalgebra::Scalar`, `Zero`, `One`, the closed arithmetic operators), never
//!   `RealField`: a symbolic value cannot answer `<` or `is_finite`.
//! - `Copy` is required: dual vectors of a fixed size are `Copy`, and a symbolic
//!   scalar is a handle.
//! - Every data-dependent branch goes through one primitive,
//!   [`Scalar::select_lt`], so a tracer can record it as a conditional instead of
//!   answering a comparison. Both arms are evaluated; only the chosen one is
//!   returned (for duals, with its derivative), so the discarded arm may be
//!   non-finite without harm.

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use num_dual::{DualNum, DualSVec64};
use num_traits::{One, Zero};

/// A number type that residuals and geometry are generic over.
pub trait Scalar:
    nalgebra::Scalar
    + Copy
    + Debug
    + Zero
    + One
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
{
    /// A constant. For a symbolic scalar this is a literal, never an input.
    fn from_f64(value: f64) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Sine.
    fn sin(self) -> Self;
    /// Cosine.
    fn cos(self) -> Self;
    /// Four-quadrant arc tangent of `self / x` (`self` is the ordinate).
    fn atan2(self, x: Self) -> Self;
    /// `e^self`.
    fn exp(self) -> Self;
    /// Natural logarithm, defined for `self > 0`.
    fn ln(self) -> Self;
    /// Arc cosine in `[0, π]`, defined on `[−1, 1]`; its derivative
    /// `−1/√(1 − x²)` is infinite at `±1`.
    fn acos(self) -> Self;
    /// Arc sine in `[−π/2, π/2]`, defined on `[−1, 1]`; its derivative
    /// `1/√(1 − x²)` is infinite at `±1`.
    fn asin(self) -> Self;
    /// Arc tangent in `(−π/2, π/2)`.
    fn atan(self) -> Self;
    /// `if lhs < rhs { if_less } else { otherwise }`, the one branching primitive.
    fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self;

    /// `1 / self`.
    fn recip(self) -> Self {
        Self::one() / self
    }
    /// `self * self`.
    fn squared(self) -> Self {
        self * self
    }
    /// Absolute value, through [`Scalar::select_lt`].
    fn abs(self) -> Self {
        Self::select_lt(self, Self::zero(), -self, self)
    }
    /// The number it stands for (a dual number's real part), when it is
    /// one; `None` for a symbolic scalar (the default). Residuals never
    /// branch on it (they branch through [`Scalar::select_lt`]); the audit
    /// reads it to tell a Lie-algebra matrix from another before
    /// exponentiating one.
    fn known_value(self) -> Option<f64> {
        None
    }
    /// `R(q) v`, or `R(q)ᵀ v` when `transpose`, for the quaternion
    /// `q = [x, y, z, w]` and its homogeneous rotation matrix `R`
    /// ([`crate::linalg::homogeneous_rotation`]), where this number type has
    /// a faster way than multiplying by that matrix entry by entry. `None`
    /// (the default): [`Quaternion::rotate`](crate::lie::Quaternion::rotate)
    /// multiplies by the matrix, which is what a symbolic scalar must trace.
    /// Dual numbers compute the value in `f64` and the derivative through
    /// `∂(R v)/∂q` and `R` ([`crate::dual`]).
    fn rotate_by_quaternion(_q: &[Self; 4], _v: &[Self; 3], _transpose: bool) -> Option<[Self; 3]> {
        None
    }
}

macro_rules! impl_scalar_for_float {
    ($float:ty) => {
        impl Scalar for $float {
            #[inline]
            fn from_f64(value: f64) -> Self {
                value as $float
            }
            #[inline]
            fn sqrt(self) -> Self {
                <$float>::sqrt(self)
            }
            #[inline]
            fn sin(self) -> Self {
                <$float>::sin(self)
            }
            #[inline]
            fn cos(self) -> Self {
                <$float>::cos(self)
            }
            #[inline]
            fn atan2(self, x: Self) -> Self {
                <$float>::atan2(self, x)
            }
            #[inline]
            fn exp(self) -> Self {
                <$float>::exp(self)
            }
            #[inline]
            fn ln(self) -> Self {
                <$float>::ln(self)
            }
            #[inline]
            fn acos(self) -> Self {
                <$float>::acos(self)
            }
            #[inline]
            fn asin(self) -> Self {
                <$float>::asin(self)
            }
            #[inline]
            fn atan(self) -> Self {
                <$float>::atan(self)
            }
            #[inline]
            fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
                if lhs < rhs { if_less } else { otherwise }
            }
            #[inline]
            fn recip(self) -> Self {
                <$float>::recip(self)
            }
            #[inline]
            fn known_value(self) -> Option<f64> {
                Some(f64::from(self))
            }
        }
    };
}

impl_scalar_for_float!(f64);
impl_scalar_for_float!(f32);

/// Dual vectors carry the derivative w.r.t. `N` seeded tangent coordinates.
/// A branch compares real parts and returns the chosen arm whole, so the
/// derivative is the derivative of the branch that holds at the point.
impl<const N: usize> Scalar for DualSVec64<N> {
    #[inline]
    fn from_f64(value: f64) -> Self {
        DualSVec64::from_re(value)
    }
    #[inline]
    fn sqrt(self) -> Self {
        DualNum::sqrt(&self)
    }
    #[inline]
    fn sin(self) -> Self {
        DualNum::sin(&self)
    }
    #[inline]
    fn cos(self) -> Self {
        DualNum::cos(&self)
    }
    /// `atan2` with the derivative `(x dy − y dx) / (x² + y²)`. num-dual 0.15
    /// differentiates through `atan(y / x)`, which is NaN at `x = 0` (the
    /// quaternion logarithm at an angle of exactly π).
    #[inline]
    fn atan2(self, x: Self) -> Self {
        let numerator = self * x.re - x * self.re; // real part 0, ε = x dy − y dx
        let mut result = numerator * (self.re * self.re + x.re * x.re).recip();
        result.re = self.re.atan2(x.re);
        result
    }
    #[inline]
    fn exp(self) -> Self {
        DualNum::exp(&self)
    }
    #[inline]
    fn ln(self) -> Self {
        DualNum::ln(&self)
    }
    /// `acos` with the derivative `−1/√((1 − x)(1 + x))`. num-dual 0.15
    /// writes `1 − x·x`, whose rounding costs up to 2e-9 of relative accuracy
    /// near `|x| = 1` (measured over `1 − |x| ∈ [1e-15, 0.8]`: at worst 1.9e-9,
    /// around `1 − |x| ≈ 1e-8`; this form: 2.3e-16), since `1 − x` and `1 + x`
    /// are exact there. At `x = ±1` the derivative is infinite: seeded
    /// directions get `∓∞`, unseeded ones `0 · ∞ = NaN`.
    #[inline]
    fn acos(self) -> Self {
        let x = self.re;
        let mut result = self * -((1.0 - x) * (1.0 + x)).sqrt().recip();
        result.re = x.acos();
        result
    }
    /// `asin` with the derivative `1/√((1 − x)(1 + x))`, written out for the
    /// reason given for `acos`; at `x = ±1` the derivative is infinite as
    /// there.
    #[inline]
    fn asin(self) -> Self {
        let x = self.re;
        let mut result = self * ((1.0 - x) * (1.0 + x)).sqrt().recip();
        result.re = x.asin();
        result
    }
    #[inline]
    fn atan(self) -> Self {
        DualNum::atan(&self)
    }
    #[inline]
    fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
        if lhs.re < rhs.re { if_less } else { otherwise }
    }
    #[inline]
    fn recip(self) -> Self {
        DualNum::recip(&self)
    }
    #[inline]
    fn known_value(self) -> Option<f64> {
        Some(self.re)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hypot_like<S: Scalar>(a: S, b: S) -> S {
        (a * a + b * b).sqrt()
    }

    #[test]
    fn generic_code_runs_on_floats_and_duals() {
        assert_eq!(hypot_like(3.0_f64, 4.0), 5.0);
        assert_eq!(hypot_like(3.0_f32, 4.0), 5.0);
        let a = DualSVec64::<2>::from_re(3.0).derivative(0);
        let b = DualSVec64::<2>::from_re(4.0).derivative(1);
        let h = hypot_like(a, b);
        assert_eq!(h.re, 5.0);
        let eps = h.eps.unwrap_generic(nalgebra::Const::<2>, nalgebra::U1);
        assert!((eps[0] - 0.6).abs() < 1e-15 && (eps[1] - 0.8).abs() < 1e-15);
    }

    #[test]
    fn dual_atan2_is_differentiable_where_x_is_zero() {
        for (y, x) in [(1.5, 0.0), (-0.5, 0.0), (0.3, -2.0), (2.0, 1.0)] {
            let yd = DualSVec64::<2>::from_re(y).derivative(0);
            let xd = DualSVec64::<2>::from_re(x).derivative(1);
            let a = Scalar::atan2(yd, xd);
            let eps = a.eps.unwrap_generic(nalgebra::Const::<2>, nalgebra::U1);
            let r2 = x * x + y * y;
            assert_eq!(a.re, f64::atan2(y, x));
            assert!(
                (eps[0] - x / r2).abs() < 1e-15 && (eps[1] + y / r2).abs() < 1e-15,
                "{eps:?}"
            );
        }
    }

    fn derivative(y: DualSVec64<1>) -> f64 {
        y.eps.unwrap_generic(nalgebra::Const::<1>, nalgebra::U1)[0]
    }

    /// The dual derivatives of `exp`, `ln`, `acos`, `asin`, `atan` against
    /// forms independent of the implementation: `exp' = exp`, `ln' = 1/x`,
    /// `acos' = −asin' = −1/sin(acos |x|)`, `atan' = cos²(atan x)`. Near `|x| = 1` (`x = ±cos(10⁻⁶)`, where
    /// `1 − x² ≈ 10⁻¹²`) `acos'` and `asin'` keep full relative accuracy.
    #[test]
    fn dual_library_functions_have_exact_derivatives() {
        let near_one = [1e-6_f64.cos(), 1.0 - 1.3e-8];
        let inside = [-0.9, -0.3, 0.0, 0.2, 0.7];
        let ends = near_one.iter().flat_map(|x| [*x, -x]);
        for x in inside.into_iter().chain(ends) {
            let d = DualSVec64::<1>::from_re(x).derivative(0);
            // √(1 − x²) = sin(acos |x|), accurate to a few ulp: acos |x| ∈ [0, π/2].
            let root = x.abs().acos().sin();
            let cases = [
                ("acos", Scalar::acos(d), x.acos(), -1.0 / root),
                ("asin", Scalar::asin(d), x.asin(), 1.0 / root),
                ("atan", Scalar::atan(d), x.atan(), x.atan().cos().powi(2)),
                ("exp", Scalar::exp(d), x.exp(), x.exp()),
            ];
            for (name, y, value, slope) in cases {
                assert_eq!(y.re, value, "{name}({x})");
                let error = (derivative(y) - slope).abs() / slope.abs();
                assert!(error < 4e-16, "{name}'({x}): relative error {error:e}");
            }
            if x > 0.0 {
                let y = Scalar::ln(d);
                assert_eq!(y.re, x.ln());
                assert!((derivative(y) * x - 1.0).abs() < 4e-16);
            }
        }
    }

    /// At the ends of `acos`'s and `asin`'s domain the derivative is infinite.
    #[test]
    fn dual_acos_and_asin_have_infinite_slopes_at_the_ends() {
        for x in [1.0, -1.0] {
            let d = DualSVec64::<1>::from_re(x).derivative(0);
            assert_eq!(derivative(Scalar::acos(d)), f64::NEG_INFINITY);
            assert_eq!(derivative(Scalar::asin(d)), f64::INFINITY);
        }
    }

    #[test]
    fn select_follows_the_branch_that_holds_with_its_derivative() {
        let x = DualSVec64::<1>::from_re(-2.0).derivative(0);
        let y = x.abs();
        assert_eq!(y.re, 2.0);
        assert_eq!(
            y.eps.unwrap_generic(nalgebra::Const::<1>, nalgebra::U1)[0],
            -1.0
        );
        assert_eq!(f64::select_lt(1.0, 2.0, 10.0, 20.0), 10.0);
        assert_eq!(f64::select_lt(2.0, 2.0, 10.0, 20.0), 20.0);
    }
}
