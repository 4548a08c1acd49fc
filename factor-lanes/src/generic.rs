//! [`Lanes`]: the lane types and the scalars `f64`, `f32` (one lane each)
//! behind one interface, for code generic over how many configurations a
//! value holds.

use crate::{F32x8, F64x4, F64x8};

/// A number type that holds [`Lanes::LANES`] configurations: a lane type, or
/// a scalar (one lane). Generic batch code loads its inputs from
/// structure-of-arrays columns with it and stores its outputs.
pub trait Lanes: Copy + Send + Sync + 'static {
    /// The scalar of one lane.
    type Scalar: Lanes<Scalar = Self::Scalar> + Default + From<f32> + PartialEq + core::fmt::Debug;
    /// Lanes per value.
    const LANES: usize;

    /// Every lane `value`.
    fn splat(value: Self::Scalar) -> Self;

    /// Lane `k` is `column[k]`, `k < LANES`.
    ///
    /// # Panics
    ///
    /// If `column` is shorter than `LANES`.
    fn load(column: &[Self::Scalar]) -> Self;

    /// Writes lane `k` to `column[k]`, `k < LANES`.
    ///
    /// # Panics
    ///
    /// If `column` is shorter than `LANES`.
    fn store(self, column: &mut [Self::Scalar]);
}

macro_rules! scalar_lanes {
    ($s:ty) => {
        impl Lanes for $s {
            type Scalar = $s;
            const LANES: usize = 1;

            #[inline(always)]
            fn splat(value: $s) -> Self {
                value
            }

            #[inline(always)]
            fn load(column: &[$s]) -> Self {
                column[0]
            }

            #[inline(always)]
            fn store(self, column: &mut [$s]) {
                column[0] = self;
            }
        }
    };
}

scalar_lanes!(f64);
scalar_lanes!(f32);

macro_rules! vector_lanes {
    ($name:ident, $s:ty, $n:literal) => {
        impl Lanes for $name {
            type Scalar = $s;
            const LANES: usize = $n;

            #[inline(always)]
            fn splat(value: $s) -> Self {
                $name::splat(value)
            }

            #[inline(always)]
            fn load(column: &[$s]) -> Self {
                match column.first_chunk::<$n>() {
                    Some(chunk) => $name::load(chunk),
                    None => panic!("a column of {} scalars, {} lanes", column.len(), $n),
                }
            }

            #[inline(always)]
            fn store(self, column: &mut [$s]) {
                match column.first_chunk_mut::<$n>() {
                    Some(chunk) => $name::store(self, chunk),
                    None => panic!("a column of {} scalars, {} lanes", column.len(), $n),
                }
            }
        }
    };
}

vector_lanes!(F64x4, f64, 4);
vector_lanes!(F32x8, f32, 8);
vector_lanes!(F64x8, f64, 8);
