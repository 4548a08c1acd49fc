//! Lowering a traced kernel to one program: the residual and every Jacobian
//! block compiled together ([`crate::compile`]), so work is shared across
//! them, with the value of each output.

use factor_symbolic::{Expr, Graph};

use crate::compile::compile;
use crate::ir::{self, Instr, OpCounts, Value};

/// A lowered kernel: the program and the value of every output.
#[derive(Debug, Clone)]
pub struct LoweredKernel {
    /// Instructions; operands precede their users.
    pub instrs: Vec<Instr>,
    /// The residual's values.
    pub residual: Vec<Value>,
    /// Each Jacobian block's values, row-major.
    pub blocks: Vec<Vec<Value>>,
}

impl LoweredKernel {
    /// Every output value: the residual, then the blocks in order.
    pub fn outputs(&self) -> Vec<Value> {
        let mut all = self.residual.clone();
        all.extend(self.blocks.iter().flatten().copied());
        all
    }

    /// Which instructions `outputs` depend on.
    pub fn live(&self, outputs: &[Value]) -> Vec<bool> {
        ir::live(&self.instrs, outputs)
    }

    /// Operation counts of the instructions `outputs` depend on.
    pub fn counts(&self, outputs: &[Value]) -> OpCounts {
        ir::counts(&self.instrs, outputs)
    }
}

/// Lowers `residual` and `blocks` (expressions of `graph`) into one program,
/// residual first.
pub fn lower(graph: &Graph, residual: &[Expr], blocks: &[Vec<Expr>]) -> LoweredKernel {
    // All outputs are compiled together, so the optimizer shares work across
    // the residual and every block; the schedule then skips what an absent
    // block alone needs.
    let outputs: Vec<Expr> = residual
        .iter()
        .chain(blocks.iter().flatten())
        .copied()
        .collect();
    let (program, values) = compile(graph, &outputs);
    let (residual_values, mut rest) = values.split_at(residual.len());
    let blocks = blocks
        .iter()
        .map(|block| {
            let (head, tail) = rest.split_at(block.len());
            rest = tail;
            head.to_vec()
        })
        .collect();
    LoweredKernel {
        instrs: program.instrs,
        residual: residual_values.to_vec(),
        blocks,
    }
}
