//! The entry points: [`linearize`] (residuals and Jacobian blocks) and
//! [`normal`] (the fused normal equations) of a batch of one factor type.

use core::marker::PhantomData;

use factor_core::WithKernel;
use factor_lanes::{Kernel, Lanes, NormalKernel};

use crate::columns::Columns;
use crate::dispatch::{Isa, run_with};
use crate::error::BatchError;
use crate::outputs::{JacobianColumns, NormalColumns, check_inputs};
use crate::run::{Eval, Jacobian, Normal, Range};
use crate::threads::{Threads, for_each_chunk};

/// How a batch runs: on which threads, with which instruction set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Options {
    /// The calling thread, or rayon's pool.
    pub threads: Threads,
    /// The instruction set of the batch loop: by default the best the CPU
    /// has ([`crate::detected`]); one the CPU lacks falls back to the best
    /// below it that the CPU has. Every choice gives the same results.
    pub isa: Isa,
}

impl Default for Options {
    /// One thread, the best instruction set of the CPU.
    fn default() -> Self {
        Options {
            threads: Threads::One,
            isa: crate::dispatch::detected(),
        }
    }
}

impl Options {
    /// The default options on rayon's pool.
    pub fn rayon() -> Self {
        Options {
            threads: Threads::Rayon,
            ..Options::default()
        }
    }
}

/// The columns of `columns`, each as an output slot.
fn slots<S>(columns: &mut Columns<S>) -> impl Iterator<Item = Option<&mut [S]>> {
    columns.columns_mut().map(Some)
}

/// The slots of an optional block of `width` columns: its columns, or
/// `width` unwanted slots.
fn block_slots<S>(block: &mut Option<Columns<S>>, width: usize) -> Vec<Option<&mut [S]>> {
    match block {
        Some(columns) => slots(columns).collect(),
        None => (0..width).map(|_| None).collect(),
    }
}

/// Runs `eval` over every row of `range` with lanes `L`, as `options` say.
fn evaluate<L, E>(eval: &E, range: Range<'_, L::Scalar>, options: Options)
where
    L: Lanes,
    E: Eval<L> + Eval<L::Scalar>,
{
    for_each_chunk(range, options.threads, |chunk| {
        run_with::<L, E>(options.isa, eval, chunk);
    });
}

/// The residual and the Jacobian blocks of `inputs.len()` factors of type
/// `F` (one per row of `inputs`: one column per stored scalar, in
/// [`factor_core::Storage`] order, see [`Columns::from_factors`]) through
/// `F`'s generated kernel, `L::LANES` factors per evaluation and the rows
/// left over one at a time with `L::Scalar`, written into `outputs`. The
/// blocks of the variables whose entry in `outputs.blocks` is `None` are
/// not computed, nor the work only they need.
///
/// `L` is `f64` or `f32` (one factor per evaluation) or a lane type of
/// `factor-lanes` (`F64x4`, `F64x8`, `F32x8`); the columns hold its scalar.
/// `F`'s kernel crate must be built with its `lanes` feature.
///
/// No factor is validated: a degenerate configuration gives the kernel's
/// non-finite outputs, as the kernel does one at a time.
///
/// # Errors
///
/// [`BatchError`] when the columns do not fit `F` or the number of rows.
pub fn linearize<F, L>(
    inputs: &Columns<L::Scalar>,
    outputs: &mut JacobianColumns<L::Scalar>,
    options: Options,
) -> Result<(), BatchError>
where
    F: WithKernel,
    L: Lanes,
    F::Kernel: Kernel<L> + Kernel<L::Scalar>,
{
    check_inputs::<F, _>(inputs)?;
    let len = inputs.len();
    outputs.check::<F>(len)?;
    let free = outputs.free();
    let r = F::RESIDUAL_DIM;
    let mut out: Vec<Option<&mut [L::Scalar]>> = slots(&mut outputs.residual).collect();
    for (block, v) in outputs.blocks.iter_mut().zip(F::variables()) {
        out.extend(block_slots(block, r * v.tangent_dim));
    }
    let range = Range {
        len,
        inputs: inputs.columns().collect(),
        weights: None,
        outputs: out,
    };
    let eval = Jacobian::<F::Kernel> {
        blocks: &free,
        kernel: PhantomData,
    };
    if len > 0 {
        evaluate::<L, _>(&eval, range, options);
    }
    Ok(())
}

/// The Gauss–Newton normal equations of `inputs.len()` factors of type `F`
/// through `F`'s fused normal-equation kernel (generated with
/// `KernelSpec::with_normal_equations()`), as [`linearize`] evaluates the
/// Jacobian: per factor the cost `½ w rᵀr`, the gradient blocks `Jᵢᵀ w r`
/// and the upper triangle of `JᵀwJ`, block by block, with `w` the factor's
/// entry of `weights` (all 1 when `None`: a whitening scale, or a robust
/// IRLS weight computed from the residuals at the same configuration).
/// Blocks whose entry in `outputs` is `None` (a fixed variable's) are not
/// computed.
///
/// # Errors
///
/// [`BatchError`] when the columns or the weights do not fit `F` or the
/// number of rows.
pub fn normal<F, L>(
    inputs: &Columns<L::Scalar>,
    weights: Option<&[L::Scalar]>,
    outputs: &mut NormalColumns<L::Scalar>,
    options: Options,
) -> Result<(), BatchError>
where
    F: WithKernel,
    L: Lanes,
    F::Kernel: NormalKernel<L> + NormalKernel<L::Scalar>,
{
    check_inputs::<F, _>(inputs)?;
    let len = inputs.len();
    if let Some(w) = weights
        && w.len() != len
    {
        return Err(BatchError::Length {
            factor: F::NAME,
            what: "weights".into(),
            found: w.len(),
            expected: len,
        });
    }
    outputs.check::<F>(len)?;
    let free = outputs.free();
    let tangents: Vec<usize> = F::variables().iter().map(|v| v.tangent_dim).collect();
    let mut out: Vec<Option<&mut [L::Scalar]>> = slots(&mut outputs.cost).collect();
    for (block, d) in outputs.gradient.iter_mut().zip(&tangents) {
        out.extend(block_slots(block, *d));
    }
    for (block, (i, j)) in outputs
        .hessian
        .iter_mut()
        .zip(crate::outputs::pairs(tangents.len()))
    {
        let width = if i == j {
            tangents[i] * (tangents[i] + 1) / 2
        } else {
            tangents[i] * tangents[j]
        };
        out.extend(block_slots(block, width));
    }
    let range = Range {
        len,
        inputs: inputs.columns().collect(),
        weights,
        outputs: out,
    };
    let eval = Normal::<F::Kernel> {
        free: &free,
        kernel: PhantomData,
    };
    if len > 0 {
        evaluate::<L, _>(&eval, range, options);
    }
    Ok(())
}
