//! The vectorised elementary functions, lane-wise: `wide`'s polynomial
//! implementations (ported from Agner Fog's vector class library), with the
//! few inputs they get wrong sent lane by lane to `std`.
//!
//! Those inputs, found by the accuracy tests (`tests/math_accuracy.rs`):
//!
//! - `sin`/`cos` of `f64` reduce the argument by `k·π/2` in three parts
//!   (Cody–Waite), exact in the first two for `k < 2²⁸`, leaving an absolute
//!   error of about `k·2⁻¹⁰⁶` in the reduced argument `r`. Lanes with
//!   `|x| > 2²⁸` or with `r` so close to zero that this error would show
//!   (`|r| < k·2⁻⁴⁶`, a fraction ≈ `1.3·k·2⁻⁴⁶` of random inputs) go to
//!   `std`.
//! - `sin`/`cos` of `f32` reduce in `f32` and lose accuracy above ≈ 2¹¹
//!   (hundreds of ulp at 2¹², millions at 2¹⁵): they are computed in `f64`
//!   lanes instead and rounded.
//! - `ln` of a subnormal (of either sign) returns garbage: those lanes go to
//!   `std`.
//!
//! Everything else is `wide`'s, which the tests confirm within the bounds of
//! the crate documentation, special values (±0, ±∞, NaN, the atan2 axes and
//! signed zeros) included.

use crate::{F32x8, F64x4, F64x8};

/// Beyond this `|x|`, `k·DP1` in `wide`'s reduction is no longer exact.
const TRIG_REDUCTION_LIMIT: f64 = (1u64 << 28) as f64;
/// `|r| < k · TRIG_CANCELLATION` sends a lane to `std`: `2⁻⁴⁶`, far above
/// both the reduction's error (`k·2⁻¹⁰⁶`, so kept lanes lose under 2⁻⁶⁰
/// relatively) and the error of the estimate of `r` used to decide (`k·2⁻⁵¹`).
const TRIG_CANCELLATION: f64 = 1.0 / (1u64 << 46) as f64;

/// Replaces lane `k` of `values` by `exact(inputs[k])` wherever `keep[k]` is
/// false. The rare path of the functions above, kept out of line.
#[cold]
#[inline(never)]
fn patch_lanes<S: Copy, O, const N: usize>(
    values: &mut [O; N],
    inputs: [S; N],
    keep: [bool; N],
    exact: impl Fn(S) -> O,
) {
    for k in 0..N {
        if !keep[k] {
            values[k] = exact(inputs[k]);
        }
    }
}

/// Implements `sin`, `cos` and `sin_cos` of an `f64` lane type.
macro_rules! f64_trig {
    ($name:ident, $wide:ty, $n:literal) => {
        impl $name {
            /// Lane-wise sine and cosine, sharing the argument reduction.
            #[inline(always)]
            #[must_use]
            pub fn sin_cos(self) -> (Self, Self) {
                let x = <$wide>::new(self.0);
                let (s, c) = x.sin_cos();
                let ax = x.abs();
                let k = (ax * <$wide>::splat(core::f64::consts::FRAC_2_PI)).round();
                let r = ax - k * <$wide>::splat(core::f64::consts::FRAC_PI_2);
                let keep = ax.simd_le(<$wide>::splat(TRIG_REDUCTION_LIMIT))
                    & r.abs().simd_ge(k * <$wide>::splat(TRIG_CANCELLATION));
                if keep.all() {
                    return (Self(s.to_array()), Self(c.to_array()));
                }
                let mut out: [(f64, f64); $n] = {
                    let (s, c) = (s.to_array(), c.to_array());
                    core::array::from_fn(|k| (s[k], c[k]))
                };
                let keep = keep.to_array().map(|m| m.to_bits() != 0);
                patch_lanes(&mut out, x.to_array(), keep, f64::sin_cos);
                (
                    Self::from_array(out.map(|o| o.0)),
                    Self::from_array(out.map(|o| o.1)),
                )
            }
        }
    };
}

f64_trig!(F64x4, wide::f64x4, 4);
f64_trig!(F64x8, wide::f64x8, 8);

impl F32x8 {
    /// Lane-wise sine and cosine, computed in `f64` lanes and rounded.
    #[inline(always)]
    #[must_use]
    pub fn sin_cos(self) -> (Self, Self) {
        let x = self.to_array();
        let wide = |h: usize| F64x4::from_array(core::array::from_fn(|k| f64::from(x[4 * h + k])));
        let ((s0, c0), (s1, c1)) = (wide(0).sin_cos(), wide(1).sin_cos());
        let narrow = |lo: F64x4, hi: F64x4| {
            let (lo, hi) = (lo.to_array(), hi.to_array());
            Self::from_array(core::array::from_fn(|k| {
                if k < 4 {
                    lo[k] as f32
                } else {
                    hi[k - 4] as f32
                }
            }))
        };
        (narrow(s0, s1), narrow(c0, c1))
    }
}

/// Implements `ln` of a lane type, with subnormal lanes through `std`.
macro_rules! ln_impl {
    ($name:ident, $wide:ty, $s:ty) => {
        impl $name {
            /// Lane-wise natural logarithm (`−∞` at ±0, NaN below 0).
            #[inline(always)]
            #[must_use]
            pub fn ln(self) -> Self {
                let x = <$wide>::new(self.0);
                let y = x.ln();
                let subnormal = x.abs().simd_lt(<$wide>::splat(<$s>::MIN_POSITIVE))
                    & x.simd_ne(<$wide>::splat(0.0));
                if subnormal.none() {
                    return Self(y.to_array());
                }
                let mut out = y.to_array();
                let keep = subnormal.to_array().map(|m| m.to_bits() == 0);
                patch_lanes(&mut out, x.to_array(), keep, <$s>::ln);
                Self::from_array(out)
            }
        }
    };
}

ln_impl!(F64x4, wide::f64x4, f64);
ln_impl!(F64x8, wide::f64x8, f64);
ln_impl!(F32x8, wide::f32x8, f32);

/// Implements the functions taken from `wide` as they are, and `sin`/`cos`
/// from `sin_cos`.
macro_rules! lane_math {
    ($name:ident, $wide:ty) => {
        impl $name {
            /// Lane-wise sine (radians).
            #[inline(always)]
            #[must_use]
            pub fn sin(self) -> Self {
                self.sin_cos().0
            }

            /// Lane-wise cosine (radians).
            #[inline(always)]
            #[must_use]
            pub fn cos(self) -> Self {
                self.sin_cos().1
            }

            /// Lane-wise four-quadrant arc tangent of `self / x` (`self` the
            /// ordinate), in `[−π, π]`, with IEEE 754's signed zeros and
            /// infinities.
            #[inline(always)]
            #[must_use]
            pub fn atan2(self, x: Self) -> Self {
                Self(<$wide>::new(self.0).atan2(<$wide>::new(x.0)).to_array())
            }

            /// Lane-wise arc tangent, in `[−π/2, π/2]`.
            #[inline(always)]
            #[must_use]
            pub fn atan(self) -> Self {
                Self(<$wide>::new(self.0).atan().to_array())
            }

            /// Lane-wise arc sine, in `[−π/2, π/2]`; NaN outside `[−1, 1]`.
            #[inline(always)]
            #[must_use]
            pub fn asin(self) -> Self {
                Self(<$wide>::new(self.0).asin().to_array())
            }

            /// Lane-wise arc cosine, in `[0, π]`; NaN outside `[−1, 1]`.
            #[inline(always)]
            #[must_use]
            pub fn acos(self) -> Self {
                Self(<$wide>::new(self.0).acos().to_array())
            }

            /// Lane-wise `eˣ` (subnormal results included, `+∞` on overflow).
            #[inline(always)]
            #[must_use]
            pub fn exp(self) -> Self {
                Self(<$wide>::new(self.0).exp().to_array())
            }
        }
    };
}

lane_math!(F64x4, wide::f64x4);
lane_math!(F32x8, wide::f32x8);
lane_math!(F64x8, wide::f64x8);
