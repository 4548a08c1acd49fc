//! A factor traced into symbolic residual and Jacobian expressions.
//!
//! The residual is traced at the first-order retraction of every variable by
//! a symbolic stacked tangent `δ` (inputs after the factor's own scalars),
//! differentiated exactly w.r.t. each coordinate of `δ`, and `δ = 0` is
//! substituted. Only the first-order part of a retraction reaches the
//! derivative, so no retraction branch is traced; the residual's own
//! branches are kept, each arm differentiated.
//!
//! The Jacobian is formed the cheapest of several exact ways: each entry
//! differentiated as a whole, or the chain rule through one of the
//! successive minimum vertex cuts between `δ` and the residual
//! ([`factor_symbolic::cut`]), `∂r/∂δ = ∂r/∂c · ∂c/∂δ` with `∂r/∂c` shared
//! by every tangent column, as a hand derivation through the camera-frame
//! point or line does. Each candidate is compiled with the residual
//! ([`crate::compile::compile`]) and the one with the fewest
//! operations is kept (the direct form on a tie). On the document factors
//! this cuts the Plücker-line kernel from 378 to 268 operations and the
//! orthonormal line kernel from 493 to 393.

use std::collections::HashMap;

use factor_core::{Factor, FieldInfo, VariableInfo};
use factor_symbolic::calculus::substitute;
use factor_symbolic::cut::minimum_cuts;
use factor_symbolic::jacobian::{chained_columns, direct_columns};
use factor_symbolic::trace::{Traced, trace_at_tangent};
use factor_symbolic::{Expr, Graph, Tracer};

use crate::compile::compile;

/// One variable's Jacobian block.
#[derive(Debug, Clone)]
pub struct JacobianBlock {
    /// The variable.
    pub variable: VariableInfo,
    /// `residual_dim × tangent_dim` entries, row-major.
    pub entries: Vec<Expr>,
}

/// Residual and Jacobian expressions of a factor over its input scalars.
#[derive(Debug, Clone)]
pub struct SymbolicKernel {
    /// The factor's name.
    pub name: &'static str,
    /// The graph every expression below lives in.
    pub graph: Graph,
    /// Input fields in order; field `k` occupies the next `scalars` inputs.
    pub fields: Vec<FieldInfo>,
    /// The residual.
    pub residual: Vec<Expr>,
    /// One block per variable.
    pub blocks: Vec<JacobianBlock>,
    /// How the blocks' entries were formed.
    pub jacobian_form: JacobianForm,
}

impl SymbolicKernel {
    /// Number of input scalars.
    pub fn input_len(&self) -> usize {
        self.fields.iter().map(|f| f.scalars).sum()
    }
}

/// Traces factor type `F`: every stored scalar becomes an input, in storage
/// order (no value of the factor is needed). The Jacobian blocks are the
/// cheapest of the exact forms (see the module docs).
pub fn trace<F: Factor>() -> SymbolicKernel {
    let tracer = Tracer::new();
    let traced = trace_at_tangent::<F>();
    assemble(
        tracer,
        F::NAME,
        F::fields(),
        F::variables(),
        traced,
        BlockOrder::RowMajor,
    )
}

/// How a block's entries are ordered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BlockOrder {
    /// Row after row: this project's kernels.
    RowMajor,
    /// Column after column: host kernels, whose consecutive blocks tile a
    /// column-major Jacobian.
    ColumnMajor,
}

/// The kernel of a residual `traced` inside `tracer` over the inputs of
/// `fields`: the residual at `δ = 0` and, per entry of `variables` (which
/// split `δ` in order), its block in the cheapest exact form, ordered by
/// `order`.
pub(crate) fn assemble(
    tracer: Tracer,
    name: &'static str,
    fields: Vec<FieldInfo>,
    variables: Vec<VariableInfo>,
    traced: Traced,
    order: BlockOrder,
) -> SymbolicKernel {
    let Traced {
        residual: traced,
        delta,
        input_len,
        at_zero,
    } = traced;
    let mut substituted = HashMap::new();
    let residual: Vec<Expr> = traced
        .iter()
        .map(|r| substitute(*r, &at_zero, &mut substituted))
        .collect();
    let (columns, jacobian_form) =
        cheapest_columns(&tracer, &traced, &residual, &delta, &at_zero, input_len);
    let rows = traced.len();
    let mut offset = 0;
    let blocks = variables
        .into_iter()
        .map(|variable| {
            let columns = &columns[offset..offset + variable.tangent_dim];
            offset += variable.tangent_dim;
            let entries = match order {
                BlockOrder::RowMajor => (0..rows)
                    .flat_map(|row| columns.iter().map(move |column| column[row]))
                    .collect(),
                BlockOrder::ColumnMajor => columns.iter().flatten().copied().collect(),
            };
            JacobianBlock { variable, entries }
        })
        .collect();
    SymbolicKernel {
        name,
        graph: tracer.finish(),
        fields,
        residual,
        blocks,
        jacobian_form,
    }
}

/// How the Jacobian entries were formed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JacobianForm {
    /// Each entry differentiated as a whole.
    Direct,
    /// By the chain rule through a cut of `width` intermediate values
    /// ([`factor_symbolic::cut`]): `∂r/∂δ = ∂r/∂c · ∂c/∂δ`.
    Chained {
        /// The number of values in the cut.
        width: usize,
    },
}

/// At most this many cuts are tried.
const CUTS_TRIED: usize = 4;

/// The cheapest Jacobian columns (`∂r/∂δₖ` at `δ = 0`, one column over the
/// residual rows per tangent coordinate): the direct derivative, or the chain
/// rule through one of the successive minimum cuts, whichever compiles
/// together with `residual` to the fewest operations (the direct form on a
/// tie). All are exact and equal; they differ in how much work they share.
fn cheapest_columns(
    tracer: &Tracer,
    traced: &[Expr],
    residual: &[Expr],
    delta: &[Expr],
    at_zero: &HashMap<Expr, Expr>,
    input_len: u32,
) -> (Vec<Vec<Expr>>, JacobianForm) {
    let mut substituted = HashMap::new();
    let mut candidates = vec![(
        direct_columns(traced, delta, at_zero, &mut substituted),
        JacobianForm::Direct,
    )];
    for cut in minimum_cuts(traced, delta, CUTS_TRIED) {
        let base = input_len + delta.len() as u32;
        let columns = chained_columns(traced, delta, at_zero, &mut substituted, &cut, base);
        candidates.push((columns, JacobianForm::Chained { width: cut.len() }));
    }
    // The candidates compile independently (the graph is a snapshot), one
    // thread each.
    let graph = tracer.graph();
    let costs: Vec<usize> = std::thread::scope(|scope| {
        let workers: Vec<_> = candidates
            .iter()
            .map(|(columns, _)| {
                let outputs: Vec<Expr> = residual
                    .iter()
                    .chain(columns.iter().flatten())
                    .copied()
                    .collect();
                let graph = &graph;
                scope.spawn(move || {
                    let (program, values) = compile(graph, &outputs);
                    program.counts(&values).total()
                })
            })
            .collect();
        workers
            .into_iter()
            .map(|w| w.join().expect("compilation does not panic"))
            .collect()
    });
    candidates
        .into_iter()
        .zip(costs)
        .min_by_key(|(_, cost)| *cost)
        .map(|(candidate, _)| candidate)
        .expect("the direct form is a candidate")
}
