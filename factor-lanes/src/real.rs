//! [`impl_real!`](crate::impl_real): implements a generated crate's own `Real`
//! trait for the lane types.

/// Implements a generated kernel crate's `Real` trait for [`F64x4`],
/// [`F32x8`] and [`F64x8`].
///
/// Every generated crate (`generated/`, a user's kernel crate) writes its own
/// `Real` trait, so this crate cannot implement it; the generated crate calls
/// this macro instead, where the trait is local. In the generated crate, with
/// `factor-lanes` an optional dependency behind a feature
/// (`lanes = ["dep:factor-lanes"]`), `src/real.rs` ends with
///
/// ```text
/// #[cfg(feature = "lanes")]
/// factor_lanes::impl_real!(crate::Real);
/// ```
///
/// The trait must have the methods of the generated `Real`: `constant(f64)`,
/// `sqrt`, `sin`, `cos`, `atan2(self, x)`, `exp`, `ln`, `acos`, `asin`, `atan`
/// and `select_lt(lhs, rhs, if_less, otherwise)` (the operators are
/// implemented on the lane types already), as every generated `Real` has:
///
/// ```
/// use core::ops::{Add, Div, Mul, Neg, Sub};
///
/// /// A generated crate's `Real`.
/// pub trait Real:
///     Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self>
///     + Div<Output = Self> + Neg<Output = Self>
/// {
///     fn constant(c: f64) -> Self;
///     fn sqrt(self) -> Self;
///     fn sin(self) -> Self;
///     fn cos(self) -> Self;
///     fn atan2(self, x: Self) -> Self;
///     fn exp(self) -> Self;
///     fn ln(self) -> Self;
///     fn acos(self) -> Self;
///     fn asin(self) -> Self;
///     fn atan(self) -> Self;
///     fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self;
/// }
///
/// factor_lanes::impl_real!(Real);
///
/// /// A kernel generic over the trait, as the generated ones are.
/// fn softplus<T: Real>(x: T) -> T {
///     (T::constant(1.0) + x.exp()).ln()
/// }
///
/// let y = softplus(factor_lanes::F64x4::from_array([-1.0, 0.0, 1.0, 2.0]));
/// assert!((y.to_array()[1] - 2f64.ln()).abs() < 1e-15);
/// ```
///
/// Every method is `#[inline(always)]`, so a kernel inlined into a
/// `#[target_feature]` function computes with that function's instructions.
///
/// [`F64x4`]: crate::F64x4
/// [`F32x8`]: crate::F32x8
/// [`F64x8`]: crate::F64x8
#[macro_export]
macro_rules! impl_real {
    ($real:path) => {
        $crate::impl_real!(@for $real, $crate::F64x4);
        $crate::impl_real!(@for $real, $crate::F32x8);
        $crate::impl_real!(@for $real, $crate::F64x8);
    };
    (@for $real:path, $lanes:ty) => {
        impl $real for $lanes {
            #[inline(always)]
            fn constant(c: f64) -> Self {
                <$lanes>::constant(c)
            }
            #[inline(always)]
            fn atan2(self, x: Self) -> Self {
                <$lanes>::atan2(self, x)
            }
            #[inline(always)]
            fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
                <$lanes>::select_lt(lhs, rhs, if_less, otherwise)
            }
            $crate::impl_real!(@unary $lanes; sqrt, sin, cos, exp, ln, acos, asin, atan);
        }
    };
    (@unary $lanes:ty; $($function:ident),+) => {
        $(
            #[inline(always)]
            fn $function(self) -> Self {
                <$lanes>::$function(self)
            }
        )+
    };
}
