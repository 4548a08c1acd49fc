//! The lane types: arithmetic, literals, square root and the lane-wise
//! select, each lane computed exactly as the scalar type computes it.

use core::ops::{Add, Div, Mul, Neg, Sub};

/// Defines a lane type over a `wide` vector of `$n` lanes of `$s`.
macro_rules! lane_type {
    ($(#[$doc:meta])* $name:ident, $wide:ty, $s:ty, $n:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, Default)]
        #[repr(transparent)]
        pub struct $name(pub(crate) $wide);

        impl $name {
            /// Lanes per value.
            pub const LANES: usize = $n;

            /// Every lane `value`.
            #[inline(always)]
            #[must_use]
            pub fn splat(value: $s) -> Self {
                Self(<$wide>::splat(value))
            }

            /// The literal `c` rounded to the lane scalar (as `c as` the
            /// scalar type) in every lane: what the generated `Real::constant`
            /// gives.
            #[inline(always)]
            #[must_use]
            pub fn constant(c: f64) -> Self {
                Self::splat(c as $s)
            }

            /// Lane `k` is `lanes[k]`.
            #[inline(always)]
            #[must_use]
            pub fn from_array(lanes: [$s; $n]) -> Self {
                Self(<$wide>::new(lanes))
            }

            /// The lanes, in order.
            #[inline(always)]
            #[must_use]
            pub fn to_array(self) -> [$s; $n] {
                self.0.to_array()
            }

            /// Lane-wise square root, correctly rounded (IEEE 754), as the
            /// scalar `sqrt`.
            #[inline(always)]
            #[must_use]
            pub fn sqrt(self) -> Self {
                Self(self.0.sqrt())
            }

            /// Lane-wise `if lhs < rhs { if_less } else { otherwise }`; a NaN
            /// in `lhs` or `rhs` selects `otherwise`, as the scalar `<` does.
            #[inline(always)]
            #[must_use]
            pub fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
                Self(lhs.0.simd_lt(rhs.0).select(if_less.0, otherwise.0))
            }
        }

        impl From<[$s; $n]> for $name {
            #[inline(always)]
            fn from(lanes: [$s; $n]) -> Self {
                Self::from_array(lanes)
            }
        }

        impl From<$name> for [$s; $n] {
            #[inline(always)]
            fn from(value: $name) -> Self {
                value.to_array()
            }
        }

        lane_binary_op!($name, Add, add);
        lane_binary_op!($name, Sub, sub);
        lane_binary_op!($name, Mul, mul);
        lane_binary_op!($name, Div, div);

        impl Neg for $name {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                Self(-self.0)
            }
        }
    };
}

/// Implements a lane-wise IEEE 754 operator (correctly rounded per lane).
macro_rules! lane_binary_op {
    ($name:ident, $trait:ident, $method:ident) => {
        impl $trait for $name {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                Self($trait::$method(self.0, rhs.0))
            }
        }
    };
}

lane_type!(
    /// Four `f64` lanes: one 256-bit AVX register where the build targets AVX
    /// (`-C target-cpu=native` or `x86-64-v3`), two SSE2 halves otherwise.
    F64x4,
    wide::f64x4,
    f64,
    4
);

lane_type!(
    /// Eight `f32` lanes: one 256-bit AVX register where the build targets
    /// AVX, two SSE halves otherwise.
    F32x8,
    wide::f32x8,
    f32,
    8
);

lane_type!(
    /// Eight `f64` lanes: one 512-bit register where the build targets
    /// AVX-512F (`-C target-cpu=native` on this machine, or `x86-64-v4`),
    /// two [`F64x4`]-like halves otherwise (AVX2 or SSE2).
    F64x8,
    wide::f64x8,
    f64,
    8
);
