//! The batch loop every candidate runs: the point-reprojection kernel over
//! structure-of-arrays columns, `LANES` configurations per call.

use crate::Real;
use factor_generated::point_reprojection::point_reprojection;

/// Scalars per configuration of the point kernel's inputs: intrinsics (4),
/// observed (2), pose (7), point (3).
pub const INPUTS: usize = 16;
/// Scalars per configuration of its outputs: residual (2), `d_pose` (12),
/// `d_point` (6).
pub const OUTPUTS: usize = 20;

/// A lane type the batch loop can run on.
pub trait Batchable: Real {
    /// The scalar of one lane.
    type Scalar: Copy + Default;
    /// Lanes per value.
    const LANES: usize;
    /// The first `LANES` scalars of `s`, one per lane.
    fn load(s: &[Self::Scalar]) -> Self;
    /// Writes the lanes to the first `LANES` scalars of `s`.
    fn store(self, s: &mut [Self::Scalar]);
}

impl Batchable for f64 {
    type Scalar = f64;
    const LANES: usize = 1;
    #[inline(always)]
    fn load(s: &[f64]) -> Self {
        s[0]
    }
    #[inline(always)]
    fn store(self, s: &mut [f64]) {
        s[0] = self;
    }
}

impl Batchable for f32 {
    type Scalar = f32;
    const LANES: usize = 1;
    #[inline(always)]
    fn load(s: &[f32]) -> Self {
        s[0]
    }
    #[inline(always)]
    fn store(self, s: &mut [f32]) {
        s[0] = self;
    }
}

/// Runs the kernel with both Jacobian blocks on every whole group of `LANES`
/// configurations of `input` (one column per input scalar), writing `output`
/// (one column per output scalar).
#[inline(always)]
pub fn point_batch<L: Batchable>(input: &[Vec<L::Scalar>], output: &mut [Vec<L::Scalar>]) {
    let n = input[0].len();
    let mut i = 0;
    while i + L::LANES <= n {
        let load = |k: usize| L::load(&input[k][i..]);
        let intrinsics = core::array::from_fn(load);
        let observed = core::array::from_fn(|k| load(4 + k));
        let pose = core::array::from_fn(|k| load(6 + k));
        let point = core::array::from_fn(|k| load(13 + k));
        let zero = L::constant(0.0);
        let (mut residual, mut d_pose, mut d_point) = ([zero; 2], [zero; 12], [zero; 6]);
        point_reprojection(
            &intrinsics,
            &observed,
            &pose,
            &point,
            &mut residual,
            Some(&mut d_pose),
            Some(&mut d_point),
        );
        for (column, value) in output
            .iter_mut()
            .zip(residual.iter().chain(&d_pose).chain(&d_point))
        {
            value.store(&mut column[i..]);
        }
        i += L::LANES;
    }
}

/// [`point_batch`] compiled for AVX2 and FMA, whatever the build's target.
///
/// # Safety
/// The CPU must have AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub unsafe fn point_batch_avx2<L: Batchable>(
    input: &[Vec<L::Scalar>],
    output: &mut [Vec<L::Scalar>],
) {
    point_batch::<L>(input, output)
}

/// [`point_batch`] compiled for AVX-512 (F, DQ, VL), whatever the build's target.
///
/// # Safety
/// The CPU must have AVX-512 F, DQ and VL, AVX2 and FMA.
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2,fma")]
pub unsafe fn point_batch_avx512<L: Batchable>(
    input: &[Vec<L::Scalar>],
    output: &mut [Vec<L::Scalar>],
) {
    point_batch::<L>(input, output)
}
