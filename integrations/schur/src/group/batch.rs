//! The lane-batch path of a group whose factor type has fused
//! normal-equation kernels: factors gathered in chunks of [`CHUNK`] into
//! structure-of-arrays columns and run through `factor_batch::normal` (or,
//! under full noise models, the per-lane Jacobian kernel, whitened after).

use std::borrow::Cow;
use std::ops::Range;
use std::time::Instant;

use factor_batch::{Columns, JacobianColumns, NormalColumns, Options};
use factor_core::{Factor, WithKernel};
use factor_lanes::NormalKernel;

use super::{CHUNK, FactorGroup, Rejected, Values};
use crate::layout::Lane;
use crate::noise::Whitening;
use crate::sink::Sink;
use crate::structure::Structure;

/// A factor type's batch kernels, as plain functions (so that a group
/// needs no kernel bound beyond its constructor's).
#[derive(Clone, Copy)]
pub(crate) struct Kernels {
    /// The fused normal equations of a chunk, with its weights.
    normal: fn(&Columns<f64>, Option<&[f64]>, &mut NormalColumns<f64>),
    /// The residuals and Jacobians of a chunk.
    jacobian: fn(&Columns<f64>, &mut JacobianColumns<f64>),
}

impl Kernels {
    /// `F`'s kernels on [`Lane`]s.
    pub(crate) fn of<F>() -> Self
    where
        F: WithKernel,
        F::Kernel: NormalKernel<Lane> + NormalKernel<f64>,
    {
        Kernels {
            normal: |inputs, weights, outputs| {
                factor_batch::normal::<F, Lane>(inputs, weights, outputs, Options::default())
                    .expect("the columns fit the factor");
            },
            jacobian: |inputs, outputs| {
                factor_batch::linearize::<F, Lane>(inputs, outputs, Options::default())
                    .expect("the columns fit the factor");
            },
        }
    }
}

impl<F: Factor> FactorGroup<F> {
    /// Factors `range` gathered into `inputs` (one column per stored
    /// scalar), each validated when `check` is given: a degenerate one is
    /// recorded and flagged in `bad`.
    fn gather_chunk(
        &self,
        range: Range<usize>,
        values: Values<'_>,
        inputs: &mut Columns<f64>,
        mut check: Option<(&mut Rejected, &mut [bool])>,
    ) {
        let mut columns: Vec<&mut [f64]> = inputs.columns_mut().collect();
        for (r, i) in range.enumerate() {
            self.for_each_field(i, values, |start, source| {
                for (column, x) in columns[start..start + source.len()].iter_mut().zip(source) {
                    column[r] = *x;
                }
            });
            if let Some((rejected, bad)) = check.as_mut() {
                let mut next = columns.iter().map(|column| column[r]);
                let factor = F::read_scalars(&mut || next.next().unwrap_or(f64::NAN));
                if let Err(error) = factor.validate() {
                    rejected.record(&error);
                    bad[r] = true;
                }
            }
        }
    }

    pub(super) fn evaluate_batch(
        &self,
        kernels: Kernels,
        range: Range<usize>,
        values: Values<'_>,
        squared: &mut [f64],
        rejected: &mut Rejected,
    ) {
        let none = vec![false; self.tangents.len()];
        // Columns of a whole chunk, or of the whole range when it is
        // shorter (a small problem allocates no more than it uses).
        let mut size = CHUNK.min(range.len());
        let mut inputs = Columns::zeros(F::SCALARS, size);
        let mut outputs = ChunkOutputs::new::<F>(&self.whitening, size, &none);
        let mut bad = [false; CHUNK];
        let mut at = range.start;
        while at < range.end {
            let n = CHUNK.min(range.end - at);
            if n != size {
                size = n;
                inputs = Columns::zeros(F::SCALARS, n);
                outputs = ChunkOutputs::new::<F>(&self.whitening, n, &none);
            }
            bad[..n].fill(false);
            self.gather_chunk(
                at..at + n,
                values,
                &mut inputs,
                Some((rejected, &mut bad[..n])),
            );
            let out = &mut squared[at - range.start..at - range.start + n];
            match (&self.whitening, &mut outputs) {
                (Whitening::Scales(scales), ChunkOutputs::Normal(outputs)) => {
                    let w = (!scales.is_empty()).then(|| &scales[at..at + n]);
                    (kernels.normal)(&inputs, w, outputs);
                    // The kernel's cost is ½ w rᵀr = ½ ‖S r‖².
                    for (s, c) in out.iter_mut().zip(outputs.cost.column(0)) {
                        *s = 2.0 * c;
                    }
                }
                (Whitening::Full { .. }, ChunkOutputs::Jacobian(outputs)) => {
                    (kernels.jacobian)(&inputs, outputs);
                    let residual: Vec<&[f64]> = outputs.residual.columns().collect();
                    let mut r = vec![0.0; F::RESIDUAL_DIM];
                    for (row, squared) in out.iter_mut().enumerate() {
                        for (x, column) in r.iter_mut().zip(&residual) {
                            *x = column[row];
                        }
                        *squared = self.whitening.squared(at + row, &r);
                    }
                }
                _ => unreachable!("the outputs are made for the group's whitening"),
            }
            for (s, bad) in out.iter_mut().zip(&bad[..n]) {
                if *bad {
                    *s = f64::NAN;
                }
            }
            at += n;
        }
    }

    pub(super) fn linearize_batch(
        &self,
        kernels: Kernels,
        range: Range<usize>,
        values: Values<'_>,
        weights: Option<&[f64]>,
        structure: &Structure,
        sink: &mut Sink<'_>,
    ) {
        // Columns of a whole chunk, or of the whole range when it is
        // shorter (a small problem allocates no more than it uses).
        let mut size = CHUNK.min(range.len());
        let mut inputs = Columns::zeros(F::SCALARS, size);
        let mut outputs = ChunkOutputs::new::<F>(&self.whitening, size, &[]);
        let mut at = range.start;
        while at < range.end {
            let n = CHUNK.min(range.end - at);
            if n != size {
                size = n;
                inputs = Columns::zeros(F::SCALARS, n);
                outputs = ChunkOutputs::new::<F>(&self.whitening, n, &[]);
            }
            self.gather_chunk(at..at + n, values, &mut inputs, None);
            let w = weights.map(|w| &w[at - range.start..at - range.start + n]);
            let start = Instant::now();
            match (&self.whitening, &mut outputs) {
                (Whitening::Scales(scales), ChunkOutputs::Normal(outputs)) => {
                    // The weight is the loss's times the isotropic 1/σ².
                    let combined: Option<Cow<'_, [f64]>> = if scales.is_empty() {
                        w.map(Cow::Borrowed)
                    } else {
                        Some(Cow::Owned(
                            (0..n)
                                .map(|r| w.map_or(1.0, |w| w[r]) * scales[at + r])
                                .collect(),
                        ))
                    };
                    (kernels.normal)(&inputs, combined.as_deref(), outputs);
                    sink.kernels += start.elapsed();
                    let (g, h) = (columns(&outputs.gradient), columns(&outputs.hessian));
                    self.scatter(at, n, &g, &h, structure, sink);
                }
                (Whitening::Full { .. }, ChunkOutputs::Jacobian(outputs)) => {
                    (kernels.jacobian)(&inputs, outputs);
                    sink.kernels += start.elapsed();
                    self.scatter_jacobians(at, outputs, w, structure, sink);
                }
                _ => unreachable!("the outputs are made for the group's whitening"),
            }
            at += n;
        }
    }
}

/// The batch kernel's outputs for one chunk: the fused normal equations'
/// while the group's noise is isotropic, the Jacobian kernel's once it is
/// whitened by full matrices (`crate::noise`). Made once per range and
/// reused chunk after chunk.
enum ChunkOutputs {
    Normal(NormalColumns<f64>),
    Jacobian(JacobianColumns<f64>),
}

impl ChunkOutputs {
    /// Outputs for `n` factors of type `F` under `whitening`, the blocks of
    /// the variables `free` says (all when empty) computed.
    fn new<F: Factor>(whitening: &Whitening, n: usize, free: &[bool]) -> Self {
        match whitening {
            Whitening::Scales(_) => ChunkOutputs::Normal(NormalColumns::new::<F>(n, free)),
            Whitening::Full { .. } => ChunkOutputs::Jacobian(JacobianColumns::new::<F>(n, free)),
        }
    }
}

/// Every column of each computed block.
fn columns(blocks: &[Option<Columns<f64>>]) -> Vec<Vec<&[f64]>> {
    blocks
        .iter()
        .map(|c| {
            c.as_ref()
                .expect("every block computed")
                .columns()
                .collect()
        })
        .collect()
}
