//! The compiler's working form: n-ary operations over shared operands
//! ([`Op`]), interned in an arena ([`Compiler`]), and the queries every stage
//! makes of it (operands, liveness, use counts).

use std::collections::{BTreeSet, HashMap};

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

    pub(super) fn operands(&self, op: usize) -> Vec<usize> {
        match &self.ops[op] {
            Op::Leaf(leaf) => match *leaf {
                LeafOp::Input(_) | LeafOp::Const(_) => Vec::new(),
                LeafOp::Sqrt(x)
                | LeafOp::Sin(x)
                | LeafOp::Cos(x)
                | LeafOp::Exp(x)
                | LeafOp::Ln(x)
                | LeafOp::Acos(x)
                | LeafOp::Asin(x)
                | LeafOp::Atan(x) => vec![x],
                LeafOp::Atan2(y, x) => vec![y, x],
                LeafOp::Select(args) => args.to_vec(),
            },
            Op::Recip(x) => vec![*x],
            Op::Product { factors, .. } => factors.clone(),
            Op::Sum { terms, .. } => terms.iter().map(|(t, _)| *t).collect(),
        }
    }

    /// Ops reachable from the roots, in increasing id order.
    pub(super) fn live(&self, roots: &[usize]) -> Vec<usize> {
        let mut seen = BTreeSet::new();
        let mut stack = roots.to_vec();
        while let Some(op) = stack.pop() {
            if seen.insert(op) {
                stack.extend(self.operands(op));
            }
        }
        seen.into_iter().collect()
    }

    /// The live ops a reciprocal or a square root depends on.
    pub(super) fn urgent(&self, live: &[usize]) -> BTreeSet<usize> {
        let mut stack: Vec<usize> = live
            .iter()
            .filter(|op| matches!(self.ops[**op], Op::Recip(_) | Op::Leaf(LeafOp::Sqrt(_))))
            .flat_map(|op| self.operands(*op))
            .collect();
        let mut urgent = BTreeSet::new();
        while let Some(op) = stack.pop() {
            if urgent.insert(op) {
                stack.extend(self.operands(op));
            }
        }
        urgent
    }

    pub(super) fn use_counts(&self, live: &[usize]) -> HashMap<usize, usize> {
        let mut uses = HashMap::new();
        for &op in live {
            for operand in self.operands(op) {
                *uses.entry(operand).or_insert(0) += 1;
            }
        }
        uses
    }
}
