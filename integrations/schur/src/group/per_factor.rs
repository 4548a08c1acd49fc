//! The per-factor path of a group: each factor rebuilt from its stored
//! scalars, validated and evaluated in `f64`, or linearized by its own
//! `linearize_stored_validated_into` (its generated kernel where it has
//! one, dual numbers otherwise) or by dual numbers ([`Jacobians`]); a
//! chunk's residuals and Jacobians are whitened and formed into the fused
//! kernels' normal-block layout (`whitened`), so the same scatter adds
//! them.

use std::ops::Range;
use std::time::Instant;

use factor_batch::JacobianColumns;
use factor_core::Factor;

use super::{CHUNK, FactorGroup, Rejected, Values};
use crate::layout::{MAX_SCALARS, MAX_SLOTS};
use crate::linearization::Jacobians;
use crate::sink::Sink;
use crate::structure::Structure;

impl<F: Factor> FactorGroup<F> {
    /// Factor `i`'s stored scalars at `values`, into `row`.
    fn stored_row(&self, i: usize, values: Values<'_>, row: &mut [f64]) {
        self.for_each_field(i, values, |start, source| {
            row[start..start + source.len()].copy_from_slice(source);
        });
    }

    /// `‖Sᵢ rᵢ‖²` of factors `range` into `squared`: NaN for a factor its
    /// validation refuses, recorded in `rejected`.
    pub(super) fn evaluate_each(
        &self,
        range: Range<usize>,
        values: Values<'_>,
        squared: &mut [f64],
        rejected: &mut Rejected,
    ) {
        let mut row = [0.0; MAX_SCALARS];
        let row = &mut row[..F::SCALARS];
        let mut residual = vec![0.0; F::RESIDUAL_DIM];
        for (out, i) in squared.iter_mut().zip(range) {
            self.stored_row(i, values, row);
            *out = match F::from_scalars(row).validate() {
                Ok(()) => {
                    F::residual_over_into(row, &mut residual);
                    self.whitening.squared(i, &residual)
                }
                Err(error) => {
                    rejected.record(&error);
                    f64::NAN
                }
            };
        }
    }

    /// The whitened normal equations of factors `range` (weights
    /// `weights`, or 1) added into `sink`, each factor's residual and
    /// Jacobians by `jacobians`. The values were evaluated, each factor
    /// validated there, so the kernel path skips the validation
    /// (`linearize_stored_validated_into`, as the batch path does) and only
    /// a non-finite output can fail: it leaves NaN in its residual, which
    /// the solver's finiteness check of the normal equations reports.
    pub(super) fn linearize_each(
        &self,
        jacobians: Jacobians,
        range: Range<usize>,
        values: Values<'_>,
        weights: Option<&[f64]>,
        structure: &Structure,
        sink: &mut Sink<'_>,
    ) {
        let mut row = [0.0; MAX_SCALARS];
        let row = &mut row[..F::SCALARS];
        let mut residual = vec![0.0; F::RESIDUAL_DIM];
        let mut blocks: Vec<Vec<f64>> = self
            .tangents
            .iter()
            .map(|d| vec![0.0; F::RESIDUAL_DIM * d])
            .collect();
        let mut size = CHUNK.min(range.len());
        let mut outputs = JacobianColumns::<f64>::new::<F>(size, &[]);
        let mut at = range.start;
        while at < range.end {
            let n = CHUNK.min(range.end - at);
            if n != size {
                size = n;
                outputs = JacobianColumns::new::<F>(n, &[]);
            }
            let start = Instant::now();
            for r in 0..n {
                self.stored_row(at + r, values, row);
                let k = blocks.len();
                let mut out: [Option<&mut [f64]>; MAX_SLOTS] = std::array::from_fn(|_| None);
                for (o, b) in out.iter_mut().zip(blocks.iter_mut()) {
                    *o = Some(b.as_mut_slice());
                }
                let out = &mut out[..k];
                let linearized = match jacobians {
                    Jacobians::Kernel => {
                        F::linearize_stored_validated_into(row, &mut residual, out)
                    }
                    Jacobians::Dual => F::from_scalars(row).linearize_dual_into(&mut residual, out),
                };
                if linearized.is_err() {
                    residual.fill(f64::NAN);
                }
                for (column, x) in outputs.residual.columns_mut().zip(&residual) {
                    column[r] = *x;
                }
                for (block, computed) in outputs.blocks.iter_mut().zip(&blocks) {
                    let block = block.as_mut().expect("every block computed");
                    for (column, x) in block.columns_mut().zip(computed) {
                        column[r] = *x;
                    }
                }
            }
            sink.kernels += start.elapsed();
            let w = weights.map(|w| &w[at - range.start..at - range.start + n]);
            self.scatter_jacobians(at, &outputs, w, structure, sink);
            at += n;
        }
    }
}
