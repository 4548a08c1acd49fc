//! The lane types: arithmetic, literals, square root and the lane-wise
//! select, each lane computed exactly as the scalar type computes it.
//!
//! A lane type is an aligned array whose operations are loops over its
//! lanes, which LLVM vectorises for the instruction set of the function they
//! are inlined into: the build's target by default, or AVX2 / AVX-512 in a
//! `#[target_feature]` function chosen at run time (what `factor-batch`
//! does), with no `-C target-cpu`. `wide` supplies the vectorised
//! elementary functions ([`crate::math`]).

use core::ops::{Add, Div, Mul, Neg, Sub};

/// Defines a lane type of `$n` lanes of `$s`, aligned to `$align` bytes (its
/// size: one vector register of that width).
macro_rules! lane_type {
    ($(#[$doc:meta])* $name:ident, $s:ty, $n:literal, $align:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        #[repr(C, align($align))]
        pub struct $name(pub(crate) [$s; $n]);

        impl $name {
            /// Lanes per value.
            pub const LANES: usize = $n;

            /// Every lane `value`.
            #[inline(always)]
            #[must_use]
            pub fn splat(value: $s) -> Self {
                Self([value; $n])
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
                Self(lanes)
            }

            /// The lanes, in order.
            #[inline(always)]
            #[must_use]
            pub fn to_array(self) -> [$s; $n] {
                self.0
            }

            /// `f` of each lane.
            #[inline(always)]
            fn map(self, f: impl Fn($s) -> $s) -> Self {
                Self(core::array::from_fn(|k| f(self.0[k])))
            }

            /// `f` of each pair of lanes.
            #[inline(always)]
            fn zip(self, rhs: Self, f: impl Fn($s, $s) -> $s) -> Self {
                Self(core::array::from_fn(|k| f(self.0[k], rhs.0[k])))
            }

            /// Lane-wise square root, correctly rounded (IEEE 754), as the
            /// scalar `sqrt`.
            #[inline(always)]
            #[must_use]
            pub fn sqrt(self) -> Self {
                self.map(<$s>::sqrt)
            }

            /// Lane-wise `if lhs < rhs { if_less } else { otherwise }`; a NaN
            /// in `lhs` or `rhs` selects `otherwise`, as the scalar `<` does.
            #[inline(always)]
            #[must_use]
            pub fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
                Self(core::array::from_fn(|k| {
                    if lhs.0[k] < rhs.0[k] {
                        if_less.0[k]
                    } else {
                        otherwise.0[k]
                    }
                }))
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

        lane_binary_op!($name, Add, add, +);
        lane_binary_op!($name, Sub, sub, -);
        lane_binary_op!($name, Mul, mul, *);
        lane_binary_op!($name, Div, div, /);

        impl Neg for $name {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                self.map(|a| -a)
            }
        }
    };
}

/// Implements a lane-wise IEEE 754 operator (correctly rounded per lane).
macro_rules! lane_binary_op {
    ($name:ident, $trait:ident, $method:ident, $op:tt) => {
        impl $trait for $name {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                self.zip(rhs, |a, b| a $op b)
            }
        }
    };
}

lane_type!(
    /// Four `f64` lanes: one 256-bit register in code compiled for AVX2
    /// (`-C target-cpu=native`, `x86-64-v3`, or a `#[target_feature]`
    /// function), two SSE2 halves otherwise.
    F64x4,
    f64,
    4,
    32
);

lane_type!(
    /// Eight `f32` lanes: one 256-bit register in code compiled for AVX2,
    /// two SSE halves otherwise.
    F32x8,
    f32,
    8,
    32
);

lane_type!(
    /// Eight `f64` lanes: one 512-bit register in code compiled for
    /// AVX-512F (`x86-64-v4`, or a `#[target_feature]` function), two
    /// [`F64x4`]-like halves otherwise (AVX2 or SSE2).
    F64x8,
    f64,
    8,
    64
);
