//! Candidate "portable": this crate's lane types, aligned arrays whose
//! operations are lane loops left to LLVM to vectorise for the instruction
//! set of the function they are inlined into (so a `#[target_feature]` batch
//! loop picked at run time gets AVX2 or AVX-512 code without
//! `-C target-cpu`), through `impl_real!` in the generated crate's `lanes`
//! feature.

use factor_lanes::{F32x8, F64x4, F64x8};

use crate::batch::Batchable;

macro_rules! batchable {
    ($t:ty, $s:ty, $n:literal) => {
        impl Batchable for $t {
            type Scalar = $s;
            const LANES: usize = $n;
            #[inline(always)]
            fn load(s: &[$s]) -> Self {
                <$t>::load(s[..$n].try_into().expect("a whole group"))
            }
            #[inline(always)]
            fn store(self, s: &mut [$s]) {
                <$t>::store(self, (&mut s[..$n]).try_into().expect("a whole group"))
            }
        }
    };
}

batchable!(F64x4, f64, 4);
batchable!(F32x8, f32, 8);
batchable!(F64x8, f64, 8);
