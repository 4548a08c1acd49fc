//! Moving lanes in and out of memory: structure-of-arrays columns (one lane
//! per consecutive scalar) and gathers from strided or indexed data.

use crate::{F32x8, F64x4, F64x8};

/// Implements loads, stores and gathers of a lane type.
macro_rules! lane_memory {
    ($name:ident, $s:ty, $n:literal) => {
        impl $name {
            /// Lane `k` is `column[k]`: `N` consecutive configurations of a
            /// structure-of-arrays column, e.g. the chunks of
            /// `column.as_chunks::<N>()`.
            #[inline(always)]
            #[must_use]
            pub fn load(column: &[$s; $n]) -> Self {
                Self::from_array(*column)
            }

            /// Writes lane `k` to `column[k]`.
            #[inline(always)]
            pub fn store(self, column: &mut [$s; $n]) {
                *column = self.to_array();
            }

            /// Lane `k` is `data[start + k * stride]`: one scalar of `N`
            /// consecutive records of `stride` scalars each (array-of-structs
            /// data), or `None` when the last lane lies outside `data`.
            #[inline(always)]
            #[must_use]
            pub fn gather_strided(data: &[$s], start: usize, stride: usize) -> Option<Self> {
                let last = stride.checked_mul($n - 1)?.checked_add(start)?;
                if last >= data.len() {
                    return None;
                }
                Some(Self::from_array(core::array::from_fn(|k| {
                    data[start + k * stride]
                })))
            }

            /// Lane `k` is `data[indices[k]]`, or `None` when an index lies
            /// outside `data`.
            #[inline(always)]
            #[must_use]
            pub fn gather(data: &[$s], indices: [usize; $n]) -> Option<Self> {
                if indices.iter().any(|&i| i >= data.len()) {
                    return None;
                }
                Some(Self::from_array(indices.map(|i| data[i])))
            }
        }
    };
}

lane_memory!(F64x4, f64, 4);
lane_memory!(F32x8, f32, 8);
lane_memory!(F64x8, f64, 8);
