//! Scheduling a lowered kernel: which instructions are live, and under which
//! condition each is computed.
//!
//! Outputs come in groups: the residual (group 0, always computed) and one
//! group per Jacobian block. Every live instruction gets the set of groups
//! that need it (a bit mask). An instruction the residual needs is computed
//! unconditionally; one needed only by Jacobian blocks is computed only when
//! at least one of those blocks is requested. Since an operand is needed by
//! every group its users are needed by, its set is a superset of theirs:
//! emitting the sets by decreasing size, instructions in program order within
//! a set, is a topological order.

use crate::ir::{Instr, Value};
use crate::lower::LoweredKernel;

/// Instructions computed under one condition.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Group {
    /// The blocks (indices into [`LoweredKernel::blocks`]) at least one of
    /// which must be requested for this group to run; empty for the
    /// unconditional group.
    pub blocks: Vec<usize>,
    /// The instructions, in program order (inputs and literals excluded:
    /// they are read where they are used).
    pub instrs: Vec<Value>,
    /// The values of this group used after it (by a later group or by an
    /// output), in program order.
    pub exports: Vec<Value>,
}

/// The order of evaluation of a lowered kernel.
#[derive(Debug, Clone)]
pub struct Schedule {
    /// Needed by the residual: always computed, first.
    pub always: Group,
    /// Needed by several blocks and not by the residual, each set of blocks
    /// once, larger sets first.
    pub shared: Vec<Group>,
    /// Per block, what only that block needs (`blocks == [k]`).
    pub single: Vec<Group>,
}

/// Whether an instruction is computed at all (inputs and literals are
/// operands, not statements).
fn is_statement(instr: &Instr) -> bool {
    !matches!(instr, Instr::Input(_) | Instr::Const(_))
}

/// Schedules `kernel`.
///
/// # Panics
///
/// With more than 63 Jacobian blocks (a bit mask holds the sets).
pub fn schedule(kernel: &LoweredKernel) -> Schedule {
    let block_count = kernel.blocks.len();
    assert!(block_count < 64, "at most 63 Jacobian blocks");
    let n = kernel.instrs.len();
    // Bit 0: the residual; bit k + 1: block k.
    let mut need = vec![0u64; n];
    for v in &kernel.residual {
        need[v.0 as usize] |= 1;
    }
    for (k, block) in kernel.blocks.iter().enumerate() {
        for v in block {
            need[v.0 as usize] |= 1 << (k + 1);
        }
    }
    for i in (0..n).rev() {
        let mask = need[i];
        if mask != 0 {
            for operand in kernel.instrs[i].operands() {
                need[operand.0 as usize] |= mask;
            }
        }
    }
    // The condition of each statement: 0 for "always", else a set of blocks.
    let condition = |i: usize| -> u64 { if need[i] & 1 != 0 { 0 } else { need[i] >> 1 } };
    // Values used outside their own group: by a statement of another group,
    // or by a Jacobian output (residual outputs are stored right after the
    // unconditional group, which computes all of them).
    let mut used_outside = vec![false; n];
    for (i, instr) in kernel.instrs.iter().enumerate() {
        if need[i] == 0 || !is_statement(instr) {
            continue;
        }
        for operand in instr.operands() {
            if condition(operand.0 as usize) != condition(i) {
                used_outside[operand.0 as usize] = true;
            }
        }
    }
    for v in kernel.blocks.iter().flatten() {
        used_outside[v.0 as usize] = true;
    }
    let group = |mask: u64| -> Group {
        let instrs: Vec<Value> = (0..n)
            .filter(|&i| need[i] != 0 && is_statement(&kernel.instrs[i]) && condition(i) == mask)
            .map(|i| Value(i as u32))
            .collect();
        let exports = instrs
            .iter()
            .copied()
            .filter(|v| used_outside[v.0 as usize])
            .collect();
        Group {
            blocks: (0..block_count).filter(|k| mask & (1 << k) != 0).collect(),
            instrs,
            exports,
        }
    };
    let mut masks: Vec<u64> = (0..n)
        .filter(|&i| need[i] != 0 && is_statement(&kernel.instrs[i]))
        .map(condition)
        .filter(|m| m.count_ones() >= 2)
        .collect();
    masks.sort_unstable_by_key(|m| (std::cmp::Reverse(m.count_ones()), *m));
    masks.dedup();
    Schedule {
        always: group(0),
        shared: masks.into_iter().map(group).collect(),
        single: (0..block_count).map(|k| group(1 << k)).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use factor_symbolic::graph::Real;

    /// r = a·b; block 0 = [a·b·c]; block 1 = [a·b·c + c, d]: `a·b` always,
    /// `a·b·c` shared, `+ c` only for block 1.
    #[test]
    fn groups_follow_the_outputs_that_need_them() {
        let instrs = vec![
            Instr::Input(0),                // 0 a
            Instr::Input(1),                // 1 b
            Instr::Input(2),                // 2 c
            Instr::Mul(Value(0), Value(1)), // 3 a·b
            Instr::Mul(Value(3), Value(2)), // 4 a·b·c
            Instr::Add(Value(4), Value(2)), // 5 a·b·c + c
            Instr::Const(Real::new(2.0)),   // 6
            Instr::Mul(Value(6), Value(2)), // 7 dead
        ];
        let kernel = LoweredKernel {
            instrs,
            residual: vec![Value(3)],
            blocks: vec![vec![Value(4)], vec![Value(5), Value(6)]],
        };
        let s = schedule(&kernel);
        assert_eq!(s.always.instrs, vec![Value(3)]);
        assert_eq!(s.always.exports, vec![Value(3)]);
        assert_eq!(s.shared.len(), 1);
        assert_eq!(s.shared[0].blocks, vec![0, 1]);
        assert_eq!(s.shared[0].instrs, vec![Value(4)]);
        assert_eq!(s.shared[0].exports, vec![Value(4)]);
        assert_eq!(s.single[0].instrs, Vec::<Value>::new());
        assert_eq!(s.single[1].instrs, vec![Value(5)]);
    }
}
