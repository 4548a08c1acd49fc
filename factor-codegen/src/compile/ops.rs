//! The compiler's working form: n-ary operations over shared operands
//! ([`Op`]), interned in an arena ([`Compiler`]), and the queries every stage
//! makes of it (operands, liveness, use counts).

use std::collections::HashMap;

use factor_symbolic::graph::{Expr, Graph, Real};

/// An operation over shared operands, before lowering to binary instructions.
#[derive(Clone, Debug)]
pub(super) enum Op {
    /// An input or a literal, or a unary or binary function of other ops.
    Leaf(LeafOp),
    /// `1 / x`.
    Recip(usize),
    /// `coefficient · Π factors` (a sorted multiset).
    Product {
        coefficient: f64,
        factors: Vec<usize>,
    },
    /// `constant + Σ coefficient · term`, terms sorted and distinct.
    Sum {
        constant: f64,
        terms: Vec<(usize, f64)>,
    },
}

#[derive(Clone, Copy, Debug)]
pub(super) enum LeafOp {
    Input(u32),
    Const(f64),
    Sqrt(usize),
    Sin(usize),
    Cos(usize),
    Atan2(usize, usize),
    Exp(usize),
    Ln(usize),
    Acos(usize),
    Asin(usize),
    Atan(usize),
    Select([usize; 4]),
}

pub(super) struct Compiler<'g> {
    pub(super) graph: &'g Graph,
    pub(super) ops: Vec<Op>,
    pub(super) of_expr: HashMap<Expr, usize>,
    pub(super) recip_of: HashMap<usize, usize>,
    pub(super) interned: HashMap<OpKey, usize>,
}

/// The identity of a product or sum, for interning ops made by rewrites.
#[derive(PartialEq, Eq, Hash)]
pub(super) enum OpKey {
    Product(u64, Vec<usize>),
    Sum(u64, Vec<(usize, u64)>),
}

impl Compiler<'_> {
    pub(super) fn push(&mut self, op: Op) -> usize {
        let key = match &op {
            Op::Product {
                coefficient,
                factors,
            } => Some(OpKey::Product(
                Real::new(*coefficient).bits(),
                factors.clone(),
            )),
            Op::Sum { constant, terms } => Some(OpKey::Sum(
                Real::new(*constant).bits(),
                terms
                    .iter()
                    .map(|(t, c)| (*t, Real::new(*c).bits()))
                    .collect(),
            )),
            _ => None,
        };
        if let Some(&id) = key.as_ref().and_then(|k| self.interned.get(k)) {
            return id;
        }
        self.ops.push(op);
        let id = self.ops.len() - 1;
        if let Some(key) = key {
            self.interned.insert(key, id);
        }
        id
    }

    /// `coefficient · Π factors` as an op: a literal, a bare factor, or a product.
    pub(super) fn product(&mut self, coefficient: f64, mut factors: Vec<usize>) -> Option<usize> {
        factors.sort_unstable();
        match factors.len() {
            0 => None,
            1 if coefficient == 1.0 => Some(factors[0]),
            _ => Some(self.push(Op::Product {
                coefficient,
                factors,
            })),
        }
    }

    /// Calls `f` with each operand of `op`, in order (repeated factors of a
    /// product repeatedly).
    pub(super) fn each_operand(&self, op: usize, mut f: impl FnMut(usize)) {
        match &self.ops[op] {
            Op::Leaf(leaf) => match *leaf {
                LeafOp::Input(_) | LeafOp::Const(_) => {}
                LeafOp::Sqrt(x)
                | LeafOp::Sin(x)
                | LeafOp::Cos(x)
                | LeafOp::Exp(x)
                | LeafOp::Ln(x)
                | LeafOp::Acos(x)
                | LeafOp::Asin(x)
                | LeafOp::Atan(x) => f(x),
                LeafOp::Atan2(y, x) => {
                    f(y);
                    f(x);
                }
                LeafOp::Select(args) => args.into_iter().for_each(f),
            },
            Op::Recip(x) => f(*x),
            Op::Product { factors, .. } => factors.iter().copied().for_each(f),
            Op::Sum { terms, .. } => terms.iter().for_each(|(t, _)| f(*t)),
        }
    }

    /// Whether each op is reachable from `from` (the ops themselves
    /// included). The rewrites ask this once per extraction, so it is a flag
    /// per op rather than a set.
    fn reachable(&self, from: impl IntoIterator<Item = usize>) -> Vec<bool> {
        let mut seen = vec![false; self.ops.len()];
        let mut stack: Vec<usize> = from.into_iter().collect();
        while let Some(op) = stack.pop() {
            if !std::mem::replace(&mut seen[op], true) {
                self.each_operand(op, |x| stack.push(x));
            }
        }
        seen
    }

    /// Ops reachable from the roots, in increasing id order.
    pub(super) fn live(&self, roots: &[usize]) -> Vec<usize> {
        let seen = self.reachable(roots.iter().copied());
        (0..seen.len()).filter(|op| seen[*op]).collect()
    }

    /// Whether each op is one a live reciprocal or square root depends on.
    pub(super) fn urgent(&self, live: &[usize]) -> Vec<bool> {
        let mut operands = Vec::new();
        for &op in live {
            if matches!(self.ops[op], Op::Recip(_) | Op::Leaf(LeafOp::Sqrt(_))) {
                self.each_operand(op, |x| operands.push(x));
            }
        }
        self.reachable(operands)
    }

    /// How many times the live ops use each op (indexed by op).
    pub(super) fn use_counts(&self, live: &[usize]) -> Vec<usize> {
        let mut uses = vec![0; self.ops.len()];
        for &op in live {
            self.each_operand(op, |x| uses[x] += 1);
        }
        uses
    }
}
