//! The three lane types behind one interface, for tests that run the same
//! check on each.

use factor_lanes::{F32x8, F64x4, F64x8};

use super::ulp::Ulp;

/// A lane type as the tests see it.
pub trait Lanes: Copy {
    /// The scalar of one lane.
    type S: Ulp + core::fmt::Debug + Into<f64>;
    /// Lanes per value.
    const N: usize;
    /// Lane `k` is `s[k]`.
    fn from_lanes(s: &[Self::S]) -> Self;
    /// The lanes.
    fn lanes(self) -> Vec<Self::S>;
    /// `x` rounded to the scalar.
    fn scalar(x: f64) -> Self::S;
}

macro_rules! lanes_impl {
    ($t:ty, $s:ty, $n:literal) => {
        impl Lanes for $t {
            type S = $s;
            const N: usize = $n;
            fn from_lanes(s: &[$s]) -> Self {
                <$t>::from_array(core::array::from_fn(|k| s[k]))
            }
            fn lanes(self) -> Vec<$s> {
                self.to_array().to_vec()
            }
            fn scalar(x: f64) -> $s {
                x as $s
            }
        }
    };
}

lanes_impl!(F64x4, f64, 4);
lanes_impl!(F64x8, f64, 8);
lanes_impl!(F32x8, f32, 8);
