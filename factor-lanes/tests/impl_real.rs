//! `factor_lanes::impl_real!` on a trait with every function of the
//! generated `Real`: a kernel generic over it computes, through it, what the
//! lane types' own methods compute.

use core::ops::{Add, Div, Mul, Neg, Sub};

use factor_lanes::{F32x8, F64x4, F64x8};

/// The generated `Real`.
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    fn constant(c: f64) -> Self;
    fn sqrt(self) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn atan2(self, x: Self) -> Self;
    fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self;
    fn exp(self) -> Self;
    fn ln(self) -> Self;
    fn acos(self) -> Self;
    fn asin(self) -> Self;
    fn atan(self) -> Self;
}

factor_lanes::impl_real!(crate::Real);

/// Every function of the trait once, combined.
fn kernel<T: Real>(x: T) -> [T; 11] {
    let half = T::constant(0.5);
    [
        T::constant(0.25) + x,
        (x * x).sqrt(),
        x.sin(),
        x.cos(),
        x.atan2(half),
        T::select_lt(x, half, x, -x),
        x.exp(),
        (x * x + half).ln(),
        (x * half).acos(),
        (x * half).asin(),
        x.atan() / half - half * x,
    ]
}

macro_rules! extras_test {
    ($test:ident, $t:ty, $s:ty) => {
        #[test]
        fn $test() {
            let x = <$t>::from_array(core::array::from_fn(|k| k as $s * 0.3 - 1.0));
            let half = <$t>::splat(0.5);
            let want = [
                <$t>::splat(0.25) + x,
                (x * x).sqrt(),
                x.sin(),
                x.cos(),
                x.atan2(half),
                <$t>::select_lt(x, half, x, -x),
                x.exp(),
                (x * x + half).ln(),
                (x * half).acos(),
                (x * half).asin(),
                x.atan() / half - half * x,
            ];
            for (got, want) in kernel(x).iter().zip(want) {
                assert_eq!(
                    got.to_array().map(<$s>::to_bits),
                    want.to_array().map(<$s>::to_bits)
                );
            }
        }
    };
}

extras_test!(f64x4_implements_the_extra_functions, F64x4, f64);
extras_test!(f64x8_implements_the_extra_functions, F64x8, f64);
extras_test!(f32x8_implements_the_extra_functions, F32x8, f32);
