//! The batch loop compiled for the best instruction set the CPU has, chosen
//! at run time: on x86-64 the loop is instantiated three times, for the
//! build's target, for AVX2 + FMA and for AVX-512, and the first one the CPU
//! supports runs. The lane types' operations are loops over their lanes
//! that LLVM vectorises for the function they are inlined into, and the
//! kernels are `#[inline(always)]`, so the AVX2 and AVX-512 instances
//! compute in 256- and 512-bit registers with no `-C target-cpu`.
//!
//! Rust never contracts a multiply and an add into an FMA on its own, so
//! every instance computes the same, correctly rounded results: the choice
//! changes the speed only.

use factor_lanes::Lanes;

use crate::run::{Eval, Range, run};

/// [`run`] compiled for AVX2 and FMA.
///
/// # Safety
///
/// The CPU must have AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn run_avx2<L, E>(eval: &E, range: &mut Range<L::Scalar>)
where
    L: Lanes,
    E: Eval<L> + Eval<L::Scalar>,
{
    run::<L, E>(eval, range);
}

/// [`run`] compiled for AVX-512 (F, DQ, VL) with AVX2 and FMA.
///
/// # Safety
///
/// The CPU must have AVX-512 F, DQ and VL, AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2,fma")]
unsafe fn run_avx512<L, E>(eval: &E, range: &mut Range<L::Scalar>)
where
    L: Lanes,
    E: Eval<L> + Eval<L::Scalar>,
{
    run::<L, E>(eval, range);
}

/// The instruction sets the batch loop is compiled for, in increasing
/// order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Isa {
    /// The build's target (SSE2 on a default x86-64 build).
    Baseline,
    /// AVX2 and FMA.
    Avx2,
    /// AVX-512 F, DQ and VL.
    Avx512,
}

/// The best instruction set of this CPU that the batch loop is compiled
/// for.
pub fn detected() -> Isa {
    #[cfg(target_arch = "x86_64")]
    {
        let avx2 = std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma");
        let avx512 = avx2
            && std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512dq")
            && std::arch::is_x86_feature_detected!("avx512vl");
        if avx512 {
            return Isa::Avx512;
        }
        if avx2 {
            return Isa::Avx2;
        }
    }
    Isa::Baseline
}

/// [`run`] with the instance of `isa`, or of the best instruction set below
/// it that the CPU has.
pub(crate) fn run_with<L, E>(isa: Isa, eval: &E, range: &mut Range<L::Scalar>)
where
    L: Lanes,
    E: Eval<L> + Eval<L::Scalar>,
{
    match isa.min(detected()) {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the CPU has AVX-512 F, DQ, VL, AVX2 and FMA (detected).
        Isa::Avx512 => unsafe { run_avx512::<L, E>(eval, range) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the CPU has AVX2 and FMA (detected).
        Isa::Avx2 => unsafe { run_avx2::<L, E>(eval, range) },
        _ => run::<L, E>(eval, range),
    }
}
