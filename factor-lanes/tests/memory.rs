//! Loads, stores and gathers of every lane type: which scalar lands in which
//! lane, and `None` (never a panic) when a gather reaches outside its data.

use factor_lanes::{F32x8, F64x4, F64x8};

macro_rules! memory_tests {
    ($module:ident, $t:ty, $s:ty, $n:literal) => {
        mod $module {
            use super::*;

            /// `0, 1, 2, …` as the scalar.
            fn counting(len: usize) -> Vec<$s> {
                (0..len).map(|k| k as $s).collect()
            }

            #[test]
            fn load_and_store_move_consecutive_scalars() {
                let column = counting(3 * $n);
                let (chunks, tail) = column.as_chunks::<$n>();
                assert!(tail.is_empty());
                let mut out = vec![0.0 as $s; 3 * $n];
                for (chunk, slot) in chunks.iter().zip(out.as_chunks_mut::<$n>().0) {
                    let v = <$t>::load(chunk);
                    assert_eq!(v.to_array(), *chunk);
                    (v + <$t>::splat(1.0)).store(slot);
                }
                assert_eq!(out, column.iter().map(|&x| x + 1.0).collect::<Vec<_>>());
            }

            #[test]
            fn gather_strided_takes_one_field_of_consecutive_records() {
                // Records of 7 scalars (a pose), field 4 of records 2, 3, …
                let data = counting(7 * ($n + 3));
                let v = <$t>::gather_strided(&data, 7 * 2 + 4, 7).expect("in bounds");
                assert_eq!(
                    v.to_array(),
                    core::array::from_fn(|k| (7 * (2 + k) + 4) as $s)
                );
                let last = 7 * ($n - 1) + 6;
                assert!(<$t>::gather_strided(&data[..=last], 6, 7).is_some());
                assert!(
                    <$t>::gather_strided(&data[..last], 6, 7).is_none(),
                    "last lane one past the end"
                );
                assert!(
                    <$t>::gather_strided(&data, usize::MAX - 1, 7).is_none(),
                    "overflowing index"
                );
                assert!(
                    <$t>::gather_strided(&data, 0, usize::MAX).is_none(),
                    "overflowing stride"
                );
            }

            #[test]
            fn gather_takes_the_indexed_scalars() {
                let data = counting(100);
                let indices: [usize; $n] = core::array::from_fn(|k| (k * 37 + 5) % 100);
                let v = <$t>::gather(&data, indices).expect("in bounds");
                assert_eq!(v.to_array(), indices.map(|i| i as $s));
                let mut outside = indices;
                outside[$n - 1] = 100;
                assert!(<$t>::gather(&data, outside).is_none());
            }

            #[test]
            fn arrays_convert_both_ways() {
                let lanes: [$s; $n] = core::array::from_fn(|k| k as $s * 0.5 - 1.0);
                let v: $t = lanes.into();
                assert_eq!(<[$s; $n]>::from(v), lanes);
                assert_eq!(<$t>::LANES, $n);
            }

            #[test]
            fn select_lt_is_lane_wise_and_nan_selects_otherwise() {
                let lhs: [$s; $n] =
                    core::array::from_fn(|k| if k % 3 == 2 { <$s>::NAN } else { k as $s });
                let rhs = <$t>::splat(2.0);
                let got = <$t>::select_lt(
                    <$t>::from_array(lhs),
                    rhs,
                    <$t>::splat(10.0),
                    <$t>::splat(20.0),
                );
                let want: [$s; $n] =
                    core::array::from_fn(|k| if lhs[k] < 2.0 { 10.0 } else { 20.0 });
                assert_eq!(got.to_array(), want);
            }

            #[test]
            fn constant_rounds_as_the_scalar_cast() {
                let c = 0.1_f64;
                assert_eq!(<$t>::constant(c).to_array(), [c as $s; $n]);
            }
        }
    };
}

memory_tests!(f64x4, F64x4, f64, 4);
memory_tests!(f64x8, F64x8, f64, 8);
memory_tests!(f32x8, F32x8, f32, 8);
