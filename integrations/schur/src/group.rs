//! The factors of one type: their constants, variables, noise models and
//! losses, and the two passes over them, inputs gathered from the
//! variables' current values:
//!
//! - [`Group::evaluate`]: each factor's `‖S r‖²`, after its validation;
//! - [`Group::linearize`]: the whitened normal equations with each
//!   factor's IRLS weight, scattered straight into the blocks of the Schur
//!   system ([`Sink`]): no Jacobian outlives its chunk.
//!
//! A group linearizes its factors in one of two ways ([`Linearization`]):
//!
//! - `batch`: a factor type with fused normal-equation kernels goes
//!   through `factor_batch` in lane chunks of [`CHUNK`] factors,
//!   structure-of-arrays columns (the bundle-adjustment speed);
//! - `per_factor`: any other factor, one at a time through its own
//!   `linearize_stored_validated_into` (its generated kernel where it has
//!   one, dual numbers otherwise) or by dual numbers ([`Jacobians`]), the
//!   Jacobians whitened and formed into the same normal blocks
//!   (`whitened`).

mod batch;
mod per_factor;

use std::any::Any;
use std::marker::PhantomData;
use std::ops::Range;

use factor_batch::{JacobianColumns, pairs};
use factor_core::noise::Noise;
use factor_core::{Factor, WithKernel};
use factor_lanes::NormalKernel;
use slam_problems::Robust;

use crate::layout::{Lane, MAX_SCALARS, MAX_SLOTS, SlotInfo, Topology};
use crate::linearization::{Jacobians, Linearized};
use crate::noise::Whitening;
use crate::sink::Sink;
use crate::structure::{Role, Structure};
use crate::whitened;

/// Factors per chunk: the inputs and the 91 output columns of a Snavely
/// chunk of the batch kernel (about 200 KB) stay in the L2 cache, and the
/// scatter reads them back from there.
pub(crate) const CHUNK: usize = 256;

/// The variables' values: every stored scalar, and where each variable's
/// start.
#[derive(Clone, Copy)]
pub(crate) struct Values<'a> {
    pub(crate) scalars: &'a [f64],
    pub(crate) offsets: &'a [usize],
}

/// Evaluations a factor rejected (a degenerate configuration).
#[derive(Debug, Clone, Default)]
pub(crate) struct Rejected {
    pub(crate) count: usize,
    pub(crate) first: Option<String>,
}

impl Rejected {
    pub(crate) fn merge(&mut self, other: Rejected) {
        self.count += other.count;
        if self.first.is_none() {
            self.first = other.first;
        }
    }

    /// Records a factor's refusal.
    fn record(&mut self, error: &impl std::fmt::Display) {
        self.count += 1;
        self.first.get_or_insert_with(|| error.to_string());
    }
}

/// The factors of one type, behind an object-safe interface.
pub(crate) trait Group: Topology + Send + Sync {
    fn as_any_mut(&mut self) -> &mut dyn Any;
    /// How the group's factors are linearized.
    fn linearized(&self) -> Linearized;
    /// Every factor's own loss (`None`: the problem's), in order.
    fn losses(&self) -> &[Option<Robust>];
    /// `‖Sᵢ rᵢ‖²` of factors `range` into `squared` (NaN for a factor whose
    /// configuration is degenerate, counted in `rejected`).
    fn evaluate(
        &self,
        range: Range<usize>,
        values: Values<'_>,
        squared: &mut [f64],
        rejected: &mut Rejected,
    );
    /// The whitened normal equations of factors `range` (weights
    /// `ρ'(‖Sᵢ rᵢ‖²)`, or 1), added into `sink`.
    fn linearize(
        &self,
        range: Range<usize>,
        values: Values<'_>,
        weights: Option<&[f64]>,
        structure: &Structure,
        sink: &mut Sink<'_>,
    );
    /// The stored scalars of the variable of slot `slot` whose stored
    /// scalars are `stored`, retracted by `delta` with the slot's manifold
    /// and side, into `out`.
    fn retract(&self, slot: usize, stored: &[f64], delta: &[f64], out: &mut [f64]);
}

/// A field of the factor: a constant, kept per factor at `at` among the
/// constants, or the variable of slot `slot`; `start` is its first stored
/// scalar.
#[derive(Debug, Clone, Copy)]
enum Field {
    Constant {
        start: usize,
        scalars: usize,
        at: usize,
    },
    Variable {
        start: usize,
        scalars: usize,
        slot: usize,
    },
}

/// How a group's factors are linearized.
#[derive(Clone, Copy)]
pub(crate) enum Linearization {
    /// In lane chunks by the factor type's batch kernels.
    Batch(batch::Kernels),
    /// One factor at a time.
    PerFactor(Jacobians),
}

/// The factors of type `F`.
pub(crate) struct FactorGroup<F> {
    linearization: Linearization,
    slots: Vec<SlotInfo>,
    fields: Vec<Field>,
    tangents: Vec<usize>,
    /// Constant scalars per factor.
    constant_scalars: usize,
    constants: Vec<f64>,
    ids: Vec<u32>,
    targets: Vec<u32>,
    /// The first factor's stored scalars: a factor to retract variables with.
    template: Vec<f64>,
    whitening: Whitening,
    losses: Vec<Option<Robust>>,
    _factor: PhantomData<fn() -> F>,
}

impl<F> FactorGroup<F>
where
    F: WithKernel + Send + Sync + 'static,
    F::Kernel: NormalKernel<Lane> + NormalKernel<f64>,
{
    /// An empty group linearized by `F`'s batch kernels.
    pub(crate) fn batch() -> Self {
        FactorGroup::new(Linearization::Batch(batch::Kernels::of::<F>()))
    }
}

impl<F: Factor> FactorGroup<F> {
    /// An empty group linearized one factor at a time by `jacobians`.
    pub(crate) fn per_factor(jacobians: Jacobians) -> Self {
        FactorGroup::new(Linearization::PerFactor(jacobians))
    }

    fn new(linearization: Linearization) -> Self {
        let mut fields = Vec::new();
        let (mut start, mut at) = (0, 0);
        for field in F::fields() {
            let scalars = field.scalars;
            fields.push(match field.variable {
                Some(slot) => Field::Variable {
                    start,
                    scalars,
                    slot,
                },
                None => {
                    at += scalars;
                    Field::Constant {
                        start,
                        scalars,
                        at: at - scalars,
                    }
                }
            });
            start += scalars;
        }
        FactorGroup {
            linearization,
            slots: SlotInfo::of::<F>(),
            fields,
            tangents: F::variables().iter().map(|v| v.tangent_dim).collect(),
            constant_scalars: at,
            constants: Vec::new(),
            ids: Vec::new(),
            targets: Vec::new(),
            template: Vec::new(),
            whitening: Whitening::new(),
            losses: Vec::new(),
            _factor: PhantomData,
        }
    }

    /// Whether `noise` fits `F`'s residual (what [`FactorGroup::push`]
    /// would refuse).
    pub(crate) fn check_noise(&self, noise: &Noise) -> Result<(), String> {
        Whitening::new().push(noise, F::RESIDUAL_DIM, 0)
    }

    /// Appends `factor` (its constants) on the variables `ids`, with its
    /// noise model and its own loss (`None`: the problem's).
    ///
    /// # Errors
    ///
    /// A noise model that does not fit the residual (nothing is added).
    pub(crate) fn push(
        &mut self,
        factor: &F,
        ids: &[u32],
        noise: &Noise,
        robust: Option<Robust>,
    ) -> Result<(), String> {
        let count = self.losses.len();
        self.whitening.push(noise, F::RESIDUAL_DIM, count)?;
        self.losses.push(robust);
        let mut stored = [0.0; MAX_SCALARS];
        let stored = &mut stored[..F::SCALARS];
        factor.write_scalars(stored);
        for field in &self.fields {
            if let Field::Constant { start, scalars, .. } = *field {
                self.constants
                    .extend_from_slice(&stored[start..start + scalars]);
            }
        }
        self.ids.extend_from_slice(ids);
        if self.template.is_empty() {
            self.template = stored.to_vec();
        }
        Ok(())
    }

    /// Calls `each(start, scalars)` for every field of factor `i` at
    /// `values`: its stored scalars, which begin at scalar `start` of the
    /// factor's storage.
    #[inline]
    fn for_each_field(&self, i: usize, values: Values<'_>, mut each: impl FnMut(usize, &[f64])) {
        let k = self.tangents.len();
        let constants = &self.constants[i * self.constant_scalars..];
        let ids = &self.ids[i * k..(i + 1) * k];
        for field in &self.fields {
            match *field {
                Field::Constant { start, scalars, at } => each(start, &constants[at..at + scalars]),
                Field::Variable {
                    start,
                    scalars,
                    slot,
                } => {
                    let offset = values.offsets[ids[slot] as usize];
                    each(start, &values.scalars[offset..offset + scalars]);
                }
            }
        }
    }

    /// Adds the normal blocks of factors `at..at + n` from their residuals
    /// and Jacobians `outputs` (`n` rows): whitened by their noise models and
    /// weighted by `weights` (1 when `None`) into the fused kernels' layout
    /// (`whitened`), then scattered as theirs are.
    fn scatter_jacobians(
        &self,
        at: usize,
        outputs: &JacobianColumns<f64>,
        weights: Option<&[f64]>,
        structure: &Structure,
        sink: &mut Sink<'_>,
    ) {
        let n = outputs.residual.len();
        let (g, h) =
            whitened::normal_columns(outputs, &self.tangents, &self.whitening, at, weights);
        let g: Vec<Vec<&[f64]>> = g.iter().map(|b| b.chunks(n).collect()).collect();
        let h: Vec<Vec<&[f64]>> = h.iter().map(|b| b.chunks(n).collect()).collect();
        self.scatter(at, n, &g, &h, structure, sink);
    }

    /// Adds the normal blocks of factors `at..at + n` (`gradient[slot]`
    /// and `hessian[pair]`, one column per entry, a row per factor as the
    /// batch kernels lay them out) into `sink`, by their variables' roles.
    fn scatter(
        &self,
        at: usize,
        n: usize,
        gradient: &[Vec<&[f64]>],
        hessian: &[Vec<&[f64]>],
        structure: &Structure,
        sink: &mut Sink<'_>,
    ) {
        let k = self.tangents.len();
        let n_pairs = k * (k - 1) / 2;
        let pairs = pairs(k);
        for row in 0..n {
            let i = at + row;
            let mut roles = [Role::Fixed; MAX_SLOTS];
            for (role, &id) in roles.iter_mut().zip(&self.ids[i * k..(i + 1) * k]) {
                *role = structure.roles[id as usize];
                if let Role::Eliminated { index } = *role {
                    sink.clear_through(index as usize, structure);
                }
            }
            for slot in 0..k {
                sink.add_gradient(roles[slot], &gradient[slot], row, structure);
            }
            let targets = &self.targets[i * n_pairs..(i + 1) * n_pairs];
            let mut off = 0;
            for (&(si, sj), h) in pairs.iter().zip(hessian) {
                if si == sj {
                    sink.add_diagonal(roles[si], self.tangents[si], h, row, structure);
                } else {
                    let (di, dj) = (self.tangents[si], self.tangents[sj]);
                    sink.add_pair(
                        (roles[si], di),
                        (roles[sj], dj),
                        targets[off],
                        h,
                        row,
                        structure,
                    );
                    off += 1;
                }
            }
        }
    }
}

impl<F: Factor> Topology for FactorGroup<F> {
    fn name(&self) -> &'static str {
        F::NAME
    }

    fn len(&self) -> usize {
        self.ids.len() / self.tangents.len().max(1)
    }

    fn slots(&self) -> usize {
        self.tangents.len()
    }

    fn slot_info(&self) -> &[SlotInfo] {
        &self.slots
    }

    fn variable_ids(&self) -> &[u32] {
        &self.ids
    }

    fn reorder(&mut self, order: &[usize], rename: &[u32]) {
        let (k, c) = (self.tangents.len(), self.constant_scalars);
        let ids = order.iter().flat_map(|&i| {
            self.ids[i * k..(i + 1) * k]
                .iter()
                .map(|&id| rename[id as usize])
        });
        self.ids = ids.collect();
        let constants = order
            .iter()
            .flat_map(|&i| self.constants[i * c..(i + 1) * c].iter().copied());
        self.constants = constants.collect();
        self.losses = order.iter().map(|&i| self.losses[i]).collect();
        self.whitening.reorder(order);
    }

    fn set_targets(&mut self, targets: Vec<u32>) {
        self.targets = targets;
    }
}
impl<F: Factor + Send + Sync + 'static> Group for FactorGroup<F> {
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }

    fn linearized(&self) -> Linearized {
        match self.linearization {
            Linearization::Batch(_) => Linearized::Batch,
            Linearization::PerFactor(jacobians) => Linearized::per_factor::<F>(jacobians),
        }
    }

    fn losses(&self) -> &[Option<Robust>] {
        &self.losses
    }

    fn evaluate(
        &self,
        range: Range<usize>,
        values: Values<'_>,
        squared: &mut [f64],
        rejected: &mut Rejected,
    ) {
        match self.linearization {
            Linearization::Batch(kernels) => {
                self.evaluate_batch(kernels, range, values, squared, rejected);
            }
            Linearization::PerFactor(_) => self.evaluate_each(range, values, squared, rejected),
        }
    }

    fn linearize(
        &self,
        range: Range<usize>,
        values: Values<'_>,
        weights: Option<&[f64]>,
        structure: &Structure,
        sink: &mut Sink<'_>,
    ) {
        match self.linearization {
            Linearization::Batch(kernels) => {
                self.linearize_batch(kernels, range, values, weights, structure, sink);
            }
            Linearization::PerFactor(jacobians) => {
                self.linearize_each(jacobians, range, values, weights, structure, sink);
            }
        }
    }

    fn retract(&self, slot: usize, stored: &[f64], delta: &[f64], out: &mut [f64]) {
        let mut row = [0.0; MAX_SCALARS];
        let row = &mut row[..F::SCALARS];
        row.copy_from_slice(&self.template);
        let Some(&Field::Variable { start, scalars, .. }) = self
            .fields
            .iter()
            .find(|f| matches!(f, Field::Variable { slot: s, .. } if *s == slot))
        else {
            unreachable!("slot {slot} is a variable of {}", F::NAME)
        };
        row[start..start + scalars].copy_from_slice(stored);
        F::from_scalars(row)
            .with_retracted(slot, delta)
            .write_scalars(row);
        out.copy_from_slice(&row[start..start + scalars]);
    }
}
