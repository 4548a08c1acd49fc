//! Candidate "portable": aligned arrays whose operations are lane loops, left
//! to LLVM to vectorise for the instruction set of the function they are
//! inlined into (so a `#[target_feature]` batch loop picked at run time gets
//! AVX2 or AVX-512 code without `-C target-cpu`). The transcendental functions
//! are lane-wise `std` calls here: the point kernel uses none.

use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::Real;
use crate::batch::Batchable;

macro_rules! portable_lanes {
    ($name:ident, $s:ty, $n:literal, $align:literal) => {
        /// `$n` lanes of `$s`.
        #[derive(Clone, Copy)]
        #[repr(C, align($align))]
        pub struct $name([$s; $n]);

        impl $name {
            #[inline(always)]
            fn map(self, f: impl Fn($s) -> $s) -> Self {
                Self(core::array::from_fn(|i| f(self.0[i])))
            }
            #[inline(always)]
            fn zip(self, rhs: Self, f: impl Fn($s, $s) -> $s) -> Self {
                Self(core::array::from_fn(|i| f(self.0[i], rhs.0[i])))
            }
        }

        impl Add for $name {
            type Output = Self;
            #[inline(always)]
            fn add(self, rhs: Self) -> Self {
                self.zip(rhs, |a, b| a + b)
            }
        }
        impl Sub for $name {
            type Output = Self;
            #[inline(always)]
            fn sub(self, rhs: Self) -> Self {
                self.zip(rhs, |a, b| a - b)
            }
        }
        impl Mul for $name {
            type Output = Self;
            #[inline(always)]
            fn mul(self, rhs: Self) -> Self {
                self.zip(rhs, |a, b| a * b)
            }
        }
        impl Div for $name {
            type Output = Self;
            #[inline(always)]
            fn div(self, rhs: Self) -> Self {
                self.zip(rhs, |a, b| a / b)
            }
        }
        impl Neg for $name {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                self.map(|a| -a)
            }
        }

        impl Real for $name {
            #[inline(always)]
            fn constant(c: f64) -> Self {
                Self([c as $s; $n])
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                self.map(<$s>::sqrt)
            }
            #[inline(always)]
            fn sin(self) -> Self {
                self.map(<$s>::sin)
            }
            #[inline(always)]
            fn cos(self) -> Self {
                self.map(<$s>::cos)
            }
            #[inline(always)]
            fn atan2(self, x: Self) -> Self {
                self.zip(x, <$s>::atan2)
            }
            #[inline(always)]
            fn exp(self) -> Self {
                self.map(<$s>::exp)
            }
            #[inline(always)]
            fn ln(self) -> Self {
                self.map(<$s>::ln)
            }
            #[inline(always)]
            fn acos(self) -> Self {
                self.map(<$s>::acos)
            }
            #[inline(always)]
            fn asin(self) -> Self {
                self.map(<$s>::asin)
            }
            #[inline(always)]
            fn atan(self) -> Self {
                self.map(<$s>::atan)
            }
            #[inline(always)]
            fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
                Self(core::array::from_fn(|i| {
                    if lhs.0[i] < rhs.0[i] {
                        if_less.0[i]
                    } else {
                        otherwise.0[i]
                    }
                }))
            }
        }

        impl Batchable for $name {
            type Scalar = $s;
            const LANES: usize = $n;
            #[inline(always)]
            fn load(s: &[$s]) -> Self {
                Self(core::array::from_fn(|k| s[k]))
            }
            #[inline(always)]
            fn store(self, s: &mut [$s]) {
                s[..$n].copy_from_slice(&self.0);
            }
        }
    };
}

portable_lanes!(F64x4, f64, 4, 32);
portable_lanes!(F32x8, f32, 8, 32);
portable_lanes!(F64x8, f64, 8, 64);
