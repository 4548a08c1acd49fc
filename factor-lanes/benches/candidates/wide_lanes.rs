//! Candidate `wide`: `wide`'s `f64x4`, `f32x8`, `f64x8` as they are, whose
//! instruction set is fixed when `wide` is compiled (what this crate's lane
//! types wrapped before they became portable arrays).

use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::Real;
use crate::batch::Batchable;

macro_rules! wide_lanes {
    ($name:ident, $wide:ty, $s:ty, $n:literal) => {
        /// `wide`'s vector.
        #[derive(Clone, Copy)]
        pub struct $name($wide);

        macro_rules! binary {
            ($trait:ident, $method:ident) => {
                impl $trait for $name {
                    type Output = Self;
                    #[inline(always)]
                    fn $method(self, rhs: Self) -> Self {
                        Self($trait::$method(self.0, rhs.0))
                    }
                }
            };
        }
        binary!(Add, add);
        binary!(Sub, sub);
        binary!(Mul, mul);
        binary!(Div, div);

        impl Neg for $name {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                Self(-self.0)
            }
        }

        impl Real for $name {
            #[inline(always)]
            fn constant(c: f64) -> Self {
                Self(<$wide>::splat(c as $s))
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                Self(self.0.sqrt())
            }
            #[inline(always)]
            fn sin(self) -> Self {
                Self(self.0.sin())
            }
            #[inline(always)]
            fn cos(self) -> Self {
                Self(self.0.cos())
            }
            #[inline(always)]
            fn atan2(self, x: Self) -> Self {
                Self(self.0.atan2(x.0))
            }
            #[inline(always)]
            fn exp(self) -> Self {
                Self(self.0.exp())
            }
            #[inline(always)]
            fn ln(self) -> Self {
                Self(self.0.ln())
            }
            #[inline(always)]
            fn acos(self) -> Self {
                Self(self.0.acos())
            }
            #[inline(always)]
            fn asin(self) -> Self {
                Self(self.0.asin())
            }
            #[inline(always)]
            fn atan(self) -> Self {
                Self(self.0.atan())
            }
            #[inline(always)]
            fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
                Self(lhs.0.simd_lt(rhs.0).select(if_less.0, otherwise.0))
            }
        }

        impl Batchable for $name {
            type Scalar = $s;
            const LANES: usize = $n;
            #[inline(always)]
            fn load(s: &[$s]) -> Self {
                Self(<$wide>::new(core::array::from_fn(|k| s[k])))
            }
            #[inline(always)]
            fn store(self, s: &mut [$s]) {
                s[..$n].copy_from_slice(&self.0.to_array());
            }
        }
    };
}

wide_lanes!(WideF64x4, wide::f64x4, f64, 4);
wide_lanes!(WideF32x8, wide::f32x8, f32, 8);
wide_lanes!(WideF64x8, wide::f64x8, f64, 8);
