//! Stage 1: the live DAG as n-ary sums and products over shared operands; a
//! negative power `x⁻ᵏ` becomes `k` factors of one shared reciprocal.

use factor_symbolic::graph::{Expr, Node};

use super::ops::{Compiler, LeafOp, Op};

impl Compiler<'_> {
    pub(super) fn recip(&mut self, x: usize) -> usize {
        if let Some(&r) = self.recip_of.get(&x) {
            return r;
        }
        let r = self.push(Op::Recip(x));
        self.recip_of.insert(x, r);
        r
    }

    pub(super) fn op_of(&mut self, e: Expr) -> usize {
        if let Some(&op) = self.of_expr.get(&e) {
            return op;
        }
        let op = match self.graph.node(e).clone() {
            Node::Const(c) => Op::Leaf(LeafOp::Const(c.get())),
            Node::Input(i) => Op::Leaf(LeafOp::Input(i)),
            Node::Add { constant, terms } => Op::Sum {
                constant: constant.get(),
                terms: terms
                    .iter()
                    .map(|(t, k)| (self.op_of(*t), k.get()))
                    .collect(),
            },
            Node::Mul {
                coefficient,
                factors,
            } => {
                let mut list = Vec::new();
                for (b, k) in factors.iter() {
                    let base = self.op_of(*b);
                    let operand = if *k < 0 { self.recip(base) } else { base };
                    list.extend(std::iter::repeat_n(operand, k.unsigned_abs() as usize));
                }
                list.sort_unstable();
                Op::Product {
                    coefficient: coefficient.get(),
                    factors: list,
                }
            }
            Node::Sqrt(x) => Op::Leaf(LeafOp::Sqrt(self.op_of(x))),
            Node::Sin(x) => Op::Leaf(LeafOp::Sin(self.op_of(x))),
            Node::Cos(x) => Op::Leaf(LeafOp::Cos(self.op_of(x))),
            Node::Atan2(y, x) => Op::Leaf(LeafOp::Atan2(self.op_of(y), self.op_of(x))),
            Node::Exp(x) => Op::Leaf(LeafOp::Exp(self.op_of(x))),
            Node::Ln(x) => Op::Leaf(LeafOp::Ln(self.op_of(x))),
            Node::Acos(x) => Op::Leaf(LeafOp::Acos(self.op_of(x))),
            Node::Asin(x) => Op::Leaf(LeafOp::Asin(self.op_of(x))),
            Node::Atan(x) => Op::Leaf(LeafOp::Atan(self.op_of(x))),
            Node::Select {
                lhs,
                rhs,
                if_less,
                otherwise,
            } => Op::Leaf(LeafOp::Select([
                self.op_of(lhs),
                self.op_of(rhs),
                self.op_of(if_less),
                self.op_of(otherwise),
            ])),
        };
        let id = self.push(op);
        self.of_expr.insert(e, id);
        id
    }
}
