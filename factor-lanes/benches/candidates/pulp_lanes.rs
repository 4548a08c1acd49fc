//! Candidate `pulp`: its `V3` (AVX2 + FMA: `f64x4`, `f32x8`) and `V4`
//! (AVX-512: `f64x8`) vectors behind operators. pulp's operations are methods
//! of a CPU-feature token; the generated kernels' `Real` has no token, so each
//! operation conjures one: sound only where the batch loop checked the CPU
//! first, which is how the benchmark runs them (its AVX2 / AVX-512 loops).
//! pulp has no transcendental functions: they are lane-wise `std` calls here
//! (the point kernel uses none).

use core::marker::PhantomData;
use core::ops::{Add, Div, Mul, Neg, Sub};

use pulp::Simd;
use pulp::bytemuck::{cast_slice, pod_read_unaligned};
use pulp::x86::{V3, V4};

use crate::Real;
use crate::batch::Batchable;

/// A pulp token that the batch loop has already checked the CPU for.
pub trait Checked: Simd {
    /// The token. Only called inside a loop that checked the CPU.
    fn checked() -> Self;
}

impl Checked for V3 {
    #[inline(always)]
    fn checked() -> Self {
        // SAFETY: only the benchmark's AVX2 loop, entered after
        // `V3::try_new()` succeeded, computes with these values.
        unsafe { V3::new_unchecked() }
    }
}

impl Checked for V4 {
    #[inline(always)]
    fn checked() -> Self {
        // SAFETY: only the benchmark's AVX-512 loop, entered after
        // `V4::try_new()` succeeded, computes with these values.
        unsafe { V4::new_unchecked() }
    }
}

macro_rules! pulp_lanes {
    ($name:ident, $s:ty, $v:ident, $m:ident,
     $add:ident, $sub:ident, $mul:ident, $div:ident, $neg:ident, $splat:ident,
     $sqrt:ident, $lt:ident, $select:ident) => {
        /// pulp's vector of `$s` for token `S`.
        #[derive(Clone, Copy)]
        pub struct $name<S: Simd>(S::$v, PhantomData<S>);

        impl<S: Checked> $name<S> {
            #[inline(always)]
            fn new(v: S::$v) -> Self {
                Self(v, PhantomData)
            }
            #[inline(always)]
            fn lanes(self) -> usize {
                core::mem::size_of::<S::$v>() / core::mem::size_of::<$s>()
            }
            #[inline(always)]
            fn map2(self, x: Self, f: impl Fn($s, $s) -> $s) -> Self {
                let mut out = [0.0 as $s; 16];
                let (a, b) = (self.as_slice(), x.as_slice());
                for k in 0..self.lanes() {
                    out[k] = f(a[k], b[k]);
                }
                Self::new(pod_read_unaligned(cast_slice(&out[..self.lanes()])))
            }
            #[inline(always)]
            fn as_slice(&self) -> &[$s] {
                cast_slice(core::slice::from_ref(&self.0))
            }
        }

        impl<S: Checked> Add for $name<S> {
            type Output = Self;
            #[inline(always)]
            fn add(self, rhs: Self) -> Self {
                Self::new(S::checked().$add(self.0, rhs.0))
            }
        }
        impl<S: Checked> Sub for $name<S> {
            type Output = Self;
            #[inline(always)]
            fn sub(self, rhs: Self) -> Self {
                Self::new(S::checked().$sub(self.0, rhs.0))
            }
        }
        impl<S: Checked> Mul for $name<S> {
            type Output = Self;
            #[inline(always)]
            fn mul(self, rhs: Self) -> Self {
                Self::new(S::checked().$mul(self.0, rhs.0))
            }
        }
        impl<S: Checked> Div for $name<S> {
            type Output = Self;
            #[inline(always)]
            fn div(self, rhs: Self) -> Self {
                Self::new(S::checked().$div(self.0, rhs.0))
            }
        }
        impl<S: Checked> Neg for $name<S> {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                Self::new(S::checked().$neg(self.0))
            }
        }

        impl<S: Checked> Real for $name<S> {
            #[inline(always)]
            fn constant(c: f64) -> Self {
                Self::new(S::checked().$splat(c as $s))
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                Self::new(S::checked().$sqrt(self.0))
            }
            #[inline(always)]
            fn sin(self) -> Self {
                self.map2(self, |a, _| a.sin())
            }
            #[inline(always)]
            fn cos(self) -> Self {
                self.map2(self, |a, _| a.cos())
            }
            #[inline(always)]
            fn atan2(self, x: Self) -> Self {
                self.map2(x, <$s>::atan2)
            }
            #[inline(always)]
            fn exp(self) -> Self {
                self.map2(self, |a, _| a.exp())
            }
            #[inline(always)]
            fn ln(self) -> Self {
                self.map2(self, |a, _| a.ln())
            }
            #[inline(always)]
            fn acos(self) -> Self {
                self.map2(self, |a, _| a.acos())
            }
            #[inline(always)]
            fn asin(self) -> Self {
                self.map2(self, |a, _| a.asin())
            }
            #[inline(always)]
            fn atan(self) -> Self {
                self.map2(self, |a, _| a.atan())
            }
            #[inline(always)]
            fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
                let s = S::checked();
                Self::new(s.$select(s.$lt(lhs.0, rhs.0), if_less.0, otherwise.0))
            }
        }

        impl<S: Checked> Batchable for $name<S> {
            type Scalar = $s;
            const LANES: usize = core::mem::size_of::<S::$v>() / core::mem::size_of::<$s>();
            #[inline(always)]
            fn load(s: &[$s]) -> Self {
                Self::new(pod_read_unaligned(cast_slice(&s[..Self::LANES])))
            }
            #[inline(always)]
            fn store(self, s: &mut [$s]) {
                s[..Self::LANES].copy_from_slice(self.as_slice());
            }
        }
    };
}

pulp_lanes!(
    PulpF64,
    f64,
    f64s,
    m64s,
    add_f64s,
    sub_f64s,
    mul_f64s,
    div_f64s,
    neg_f64s,
    splat_f64s,
    sqrt_f64s,
    less_than_f64s,
    select_f64s
);
pulp_lanes!(
    PulpF32,
    f32,
    f32s,
    m32s,
    add_f32s,
    sub_f32s,
    mul_f32s,
    div_f32s,
    neg_f32s,
    splat_f32s,
    sqrt_f32s,
    less_than_f32s,
    select_f32s
);
