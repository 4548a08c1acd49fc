//! A factor traced into symbolic residual and Jacobian expressions.
//!
//! The residual is traced at the first-order retraction of every variable by
//! a symbolic stacked tangent `δ` (inputs after the factor's own scalars),
//! differentiated exactly w.r.t. each coordinate of `δ`, and `δ = 0` is
//! substituted. Only the first-order part of a retraction reaches the
//! derivative, so no retraction branch is traced; the residual's own
//! branches are kept, each arm differentiated.

use std::collections::HashMap;

use crate::factor::{Factor, FieldInfo, VariableInfo};
use crate::symbolic::calculus::{derivative, substitute};
use crate::symbolic::graph::{Expr, Graph, Tracer};

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
}

impl SymbolicKernel {
    /// Number of input scalars.
    pub fn input_len(&self) -> usize {
        self.fields.iter().map(|f| f.scalars).sum()
    }
}

/// Traces `template`'s factor type. The values in `template` are not used,
/// only its structure: every stored scalar becomes an input.
pub fn trace<F: Factor>(template: &F) -> SymbolicKernel {
    let tracer = Tracer::new();
    let fields = F::fields();
    let input_len: usize = fields.iter().map(|f| f.scalars).sum();
    let input_len = u32::try_from(input_len).expect("fewer than 2³² inputs");
    let delta: Vec<Expr> = (0..F::TANGENT_DIM as u32)
        .map(|j| Expr::input(input_len + j))
        .collect();
    let mut next = 0;
    let traced = template.trace_residual(
        &mut |_| {
            next += 1;
            Expr::input(next - 1)
        },
        &delta,
    );
    let at_zero: HashMap<Expr, Expr> = delta.iter().map(|d| (*d, Expr::constant(0.0))).collect();
    let mut substituted = HashMap::new();
    let residual = traced
        .iter()
        .map(|r| substitute(*r, &at_zero, &mut substituted))
        .collect();
    let mut offset = 0;
    let blocks = F::variables()
        .into_iter()
        .map(|variable| {
            let columns: Vec<Vec<Expr>> = (offset..offset + variable.tangent_dim)
                .map(|j| {
                    let mut memo = HashMap::new();
                    traced
                        .iter()
                        .map(|r| {
                            let d = derivative(*r, delta[j], &mut memo);
                            substitute(d, &at_zero, &mut substituted)
                        })
                        .collect()
                })
                .collect();
            offset += variable.tangent_dim;
            let entries = (0..traced.len())
                .flat_map(|row| columns.iter().map(move |column| column[row]))
                .collect();
            JacobianBlock { variable, entries }
        })
        .collect();
    SymbolicKernel {
        name: F::NAME,
        graph: tracer.finish(),
        fields,
        residual,
        blocks,
    }
}
