//! The factors of one type: their constants and variables, and the two
//! passes over them, both through `factor_batch::normal` in chunks of
//! [`CHUNK`] factors, inputs gathered from the variables' current values
//! into structure-of-arrays columns:
//!
//! - [`Group::evaluate`]: each factor's `‖r‖²` (the kernel's cost output,
//!   no block asked for), after its validation;
//! - [`Group::linearize`]: the fused normal equations with each factor's
//!   IRLS weight, scattered straight into the blocks of the Schur system
//!   ([`Sink`]): no Jacobian is stored.

use std::any::Any;
use std::borrow::Cow;
use std::marker::PhantomData;
use std::ops::Range;
use std::time::{Duration, Instant};

use factor_apex::problems::Robust;
use factor_batch::{Columns, JacobianColumns, NormalColumns, Options, pairs};
use factor_core::noise::Noise;
use factor_core::{Factor, WithKernel};
use factor_lanes::NormalKernel;

use crate::layout::{Lane, MAX_SCALARS, MAX_SLOTS, SlotInfo, Topology};
use crate::noise::Whitening;
use crate::structure::{Role, Structure};
use crate::whitened;

/// Factors per call of the batch kernel: the inputs and the 91 output
/// columns of a Snavely chunk (about 200 KB) stay in the L2 cache, and the
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
}

/// Where one thread's linearization writes: its own accumulators of the
/// reduced blocks (`u`: the entries of `S`'s structure off the diagonal
/// blocks, `diagonal`: the diagonal blocks whole, where a factor's entries
/// go at fixed strides, `g_reduced`: the reduced gradient), and the slices of the eliminated variables' data of
/// its range, which starts at eliminated variable `first`.
pub(crate) struct Sink<'a> {
    pub(crate) u: &'a mut [f64],
    /// The diagonal blocks of `U`, each kept whole (`BlockCsc::dense`).
    pub(crate) diagonal: &'a mut [f64],
    pub(crate) g_reduced: &'a mut [f64],
    pub(crate) first: usize,
    pub(crate) g_eliminated: &'a mut [f64],
    pub(crate) v: &'a mut [f64],
    pub(crate) w: &'a mut [f64],
    /// The first eliminated variable whose data are not zeroed yet.
    pub(crate) cleared: usize,
    /// Time spent in the batch kernels.
    pub(crate) kernels: Duration,
}

impl Sink<'_> {
    /// Zeroes the data of the eliminated variables of this range up to
    /// `e` not zeroed yet: each variable's blocks are zeroed as its first
    /// factor's are added, while they are in the cache.
    #[inline]
    pub(crate) fn clear_through(&mut self, e: usize, structure: &Structure) {
        if e < self.cleared {
            return;
        }
        let el = &structure.eliminated;
        let (from, to) = (self.cleared, e + 1);
        let f = self.first;
        self.g_eliminated[el.tangent[from] - el.tangent[f]..el.tangent[to] - el.tangent[f]]
            .fill(0.0);
        self.v[el.packed[from] - el.packed[f]..el.packed[to] - el.packed[f]].fill(0.0);
        self.w[el.cross[from] - el.cross[f]..el.cross[to] - el.cross[f]].fill(0.0);
        self.cleared = to;
    }

    /// Adds a factor's gradient block (`g[a][row]`) of a variable with
    /// `role`.
    #[inline]
    fn add_gradient(&mut self, role: Role, g: &[&[f64]], row: usize, structure: &Structure) {
        let target = match role {
            Role::Reduced { block, offset } => {
                let o = structure.csc.offsets[block as usize] + offset as usize;
                &mut self.g_reduced[o..o + g.len()]
            }
            Role::Eliminated { index } => {
                let el = &structure.eliminated;
                let o = el.tangent[index as usize] - el.tangent[self.first];
                &mut self.g_eliminated[o..o + g.len()]
            }
            Role::Fixed => return,
        };
        for (t, column) in target.iter_mut().zip(g) {
            *t += column[row];
        }
    }

    /// Adds a factor's diagonal Hessian block of a variable with `role` and
    /// tangent dimension `d`: the kernel's upper triangle (`a ≤ b`) row by
    /// row.
    #[inline]
    fn add_diagonal(
        &mut self,
        role: Role,
        d: usize,
        h: &[&[f64]],
        row: usize,
        structure: &Structure,
    ) {
        match role {
            // Rows a of the kernel's upper triangle, into the whole block.
            Role::Reduced { block, offset } => {
                let csc = &structure.csc;
                let (b, o) = (block as usize, offset as usize);
                let db = csc.dims[b];
                let whole = &mut self.diagonal[csc.dense[b]..csc.dense[b + 1]];
                let mut c = 0;
                for a in 0..d {
                    let at = (o + a) * db + o + a;
                    for (t, column) in whole[at..at + d - a].iter_mut().zip(&h[c..c + d - a]) {
                        *t += column[row];
                    }
                    c += d - a;
                }
            }
            // V is packed as the kernel packs it.
            Role::Eliminated { index } => {
                let el = &structure.eliminated;
                let o = el.packed[index as usize] - el.packed[self.first];
                for (t, column) in self.v[o..o + h.len()].iter_mut().zip(h) {
                    *t += column[row];
                }
            }
            Role::Fixed => {}
        }
    }

    /// Adds a factor's off-diagonal Hessian block `J_iᵀ J_j` (`d_i × d_j`,
    /// row-major) of variables with roles `i` and `j`, at `target`
    /// ([`Structure`]: the block's prefix in `S`, or the cross block's
    /// offset).
    #[inline]
    fn add_pair(
        &mut self,
        (i, di): (Role, usize),
        (j, dj): (Role, usize),
        target: u32,
        h: &[&[f64]],
        row: usize,
        structure: &Structure,
    ) {
        let csc = &structure.csc;
        match (i, j) {
            // Both in one block: J_iᵀ J_j at their offsets in the whole
            // diagonal block.
            (
                Role::Reduced {
                    block: bi,
                    offset: oi,
                },
                Role::Reduced {
                    block: bj,
                    offset: oj,
                },
            ) if bi == bj => {
                let b = bi as usize;
                let db = csc.dims[b];
                let whole = &mut self.diagonal[csc.dense[b]..csc.dense[b + 1]];
                for a in 0..di {
                    let at = (oi as usize + a) * db + oj as usize;
                    for (t, column) in whole[at..at + dj].iter_mut().zip(&h[a * dj..(a + 1) * dj]) {
                        *t += column[row];
                    }
                }
            }
            // Block (u, v), u > v, of S holds J_uᵀ J_v at the variables'
            // offsets: the kernel's block when u is slot i's, else its
            // transpose.
            (
                Role::Reduced {
                    block: bi,
                    offset: oi,
                },
                Role::Reduced {
                    block: bj,
                    offset: oj,
                },
            ) => {
                let (oi, oj) = (oi as usize, oj as usize);
                for a in 0..di {
                    for b in 0..dj {
                        let index = if bi > bj {
                            csc.below(bj as usize, target, oi + a, oj + b)
                        } else {
                            csc.below(bi as usize, target, oj + b, oi + a)
                        };
                        self.u[index] += h[a * dj + b][row];
                    }
                }
            }
            // W_re (d_r × d_e, row-major) is J_rᵀ J_e: the kernel's block
            // when the reduced variable is slot i, else its transpose.
            (Role::Reduced { .. }, Role::Eliminated { index: e })
            | (Role::Eliminated { index: e }, Role::Reduced { .. }) => {
                let el = &structure.eliminated;
                let o = el.cross[e as usize] - el.cross[self.first] + target as usize;
                let w = &mut self.w[o..o + di * dj];
                if matches!(i, Role::Reduced { .. }) {
                    for (t, column) in w.iter_mut().zip(h) {
                        *t += column[row];
                    }
                } else {
                    for a in 0..di {
                        for b in 0..dj {
                            w[b * di + a] += h[a * dj + b][row];
                        }
                    }
                }
            }
            _ => {}
        }
    }
}

/// The factors of one type, behind an object-safe interface.
pub(crate) trait Group: Topology + Send + Sync {
    fn as_any_mut(&mut self) -> &mut dyn Any;
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

/// The factors of type `F`.
pub(crate) struct FactorGroup<F> {
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

impl<F: Factor> FactorGroup<F> {
    pub(crate) fn new() -> Self {
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
        let k = self.tangents.len();
        for (r, i) in range.enumerate() {
            let constants = &self.constants[i * self.constant_scalars..];
            let ids = &self.ids[i * k..(i + 1) * k];
            for field in &self.fields {
                let (start, scalars, source) = match *field {
                    Field::Constant { start, scalars, at } => (start, scalars, &constants[at..]),
                    Field::Variable {
                        start,
                        scalars,
                        slot,
                    } => (
                        start,
                        scalars,
                        &values.scalars[values.offsets[ids[slot] as usize]..],
                    ),
                };
                for (column, x) in columns[start..start + scalars].iter_mut().zip(source) {
                    column[r] = *x;
                }
            }
            if let Some((rejected, bad)) = check.as_mut() {
                let mut next = columns.iter().map(|column| column[r]);
                let factor = F::read_scalars(&mut || next.next().unwrap_or(f64::NAN));
                if let Err(error) = factor.validate() {
                    rejected.count += 1;
                    rejected.first.get_or_insert_with(|| error.to_string());
                    bad[r] = true;
                }
            }
        }
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

impl<F> Group for FactorGroup<F>
where
    F: WithKernel + Send + Sync + 'static,
    F::Kernel: NormalKernel<Lane> + NormalKernel<f64>,
{
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
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
                    factor_batch::normal::<F, Lane>(&inputs, w, outputs, Options::default())
                        .expect("the columns fit the factor");
                    // The kernel's cost is ½ w rᵀr = ½ ‖S r‖².
                    for (s, c) in out.iter_mut().zip(outputs.cost.column(0)) {
                        *s = 2.0 * c;
                    }
                }
                (Whitening::Full { dim, s }, ChunkOutputs::Jacobian(outputs)) => {
                    factor_batch::linearize::<F, Lane>(&inputs, outputs, Options::default())
                        .expect("the columns fit the factor");
                    let residual: Vec<&[f64]> = outputs.residual.columns().collect();
                    for (row, squared) in out.iter_mut().enumerate() {
                        let s = &s[(at + row) * dim * dim..(at + row + 1) * dim * dim];
                        *squared = (0..*dim)
                            .map(|a| {
                                let sr: f64 =
                                    (0..*dim).map(|b| s[a * dim + b] * residual[b][row]).sum();
                                sr * sr
                            })
                            .sum();
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

    fn linearize(
        &self,
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
                    factor_batch::normal::<F, Lane>(
                        &inputs,
                        combined.as_deref(),
                        outputs,
                        Options::default(),
                    )
                    .expect("the columns fit the factor");
                    sink.kernels += start.elapsed();
                    let (g, h) = (columns(&outputs.gradient), columns(&outputs.hessian));
                    self.scatter(at, n, &g, &h, structure, sink);
                }
                (Whitening::Full { dim, s }, ChunkOutputs::Jacobian(outputs)) => {
                    factor_batch::linearize::<F, Lane>(&inputs, outputs, Options::default())
                        .expect("the columns fit the factor");
                    sink.kernels += start.elapsed();
                    let (g, h) = whitened::normal_columns(
                        outputs,
                        &self.tangents,
                        *dim,
                        &s[at * dim * dim..(at + n) * dim * dim],
                        w,
                    );
                    let g: Vec<Vec<&[f64]>> = g.iter().map(|b| b.chunks(n).collect()).collect();
                    let h: Vec<Vec<&[f64]>> = h.iter().map(|b| b.chunks(n).collect()).collect();
                    self.scatter(at, n, &g, &h, structure, sink);
                }
                _ => unreachable!("the outputs are made for the group's whitening"),
            }
            at += n;
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
