//! The compiler's working form: n-ary operations over shared operands
//! ([`Op`]), interned in an arena ([`Compiler`]), and the queries every stage
//! makes of it (operands, liveness, use counts), kept up to date as the
//! rewrites change ops ([`Compiler::replace`]).

use std::collections::HashMap;

use factor_symbolic::graph::{Expr, Graph, Real};

use super::pairs::{PairIndex, ProductPair, SumPair, pairs_of};

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

#[derive(Clone)]
pub(super) struct Compiler<'g> {
    pub(super) graph: &'g Graph,
    pub(super) ops: Vec<Op>,
    pub(super) of_expr: HashMap<Expr, usize>,
    pub(super) recip_of: HashMap<usize, usize>,
    pub(super) interned: HashMap<OpKey, usize>,
    /// How many times the live ops use each op (indexed by op), once
    /// [`Compiler::track`] is called.
    pub(super) uses: Vec<usize>,
    /// Whether each op is an output.
    rooted: Vec<bool>,
    /// The operand pairs of the live products.
    pub(super) product_pairs: PairIndex<ProductPair>,
    /// The term pairs of the live sums.
    pub(super) sum_pairs: PairIndex<SumPair>,
    /// Counts the changes to ops and to their uses.
    clock: u64,
    /// When each op last changed, or how often it is used (on `clock`).
    changed: Vec<u64>,
    /// When each op was last found to have no common factor (on `clock`).
    factorless_at: Vec<Option<u64>>,
}

/// The identity of a product or sum, for interning ops made by rewrites.
#[derive(Clone, PartialEq, Eq, Hash)]
pub(super) enum OpKey {
    Product(u64, Vec<usize>),
    Sum(u64, Vec<(usize, u64)>),
}

impl<'g> Compiler<'g> {
    /// An empty arena over `graph`.
    pub(super) fn new(graph: &'g Graph) -> Self {
        Compiler {
            graph,
            ops: Vec::new(),
            of_expr: HashMap::new(),
            recip_of: HashMap::new(),
            interned: HashMap::new(),
            uses: Vec::new(),
            rooted: Vec::new(),
            product_pairs: PairIndex::default(),
            sum_pairs: PairIndex::default(),
            clock: 0,
            changed: Vec::new(),
            factorless_at: Vec::new(),
        }
    }
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
        self.uses.push(0);
        self.rooted.push(false);
        self.changed.push(0);
        self.factorless_at.push(None);
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

    /// Calls `f` with each operand of op `op` (see [`each_operand`]).
    pub(super) fn each_operand(&self, op: usize, f: impl FnMut(usize)) {
        each_operand(&self.ops[op], f);
    }

    /// Whether each op is reachable from `from` (the ops themselves
    /// included).
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

    /// Marks `roots` as the outputs. From then on the ops reachable from
    /// them are live, and [`Compiler::replace`] keeps up to date which ops
    /// are, how often they use each op, and the pairs they hold.
    pub(super) fn track(&mut self, roots: &[usize]) {
        for &root in roots {
            let was_live = self.is_live(root);
            self.rooted[root] = true;
            if !was_live {
                self.revive(root);
            }
        }
    }

    /// Whether `op` is reachable from the outputs.
    pub(super) fn is_live(&self, op: usize) -> bool {
        self.rooted[op] || self.uses[op] > 0
    }

    /// The live ops, in increasing id order.
    pub(super) fn live(&self) -> Vec<usize> {
        (0..self.ops.len()).filter(|op| self.is_live(*op)).collect()
    }

    /// Rewrites `op` as `new`, updating liveness, uses and pairs: the ops
    /// only `op` used die, the ops it starts to use live.
    pub(super) fn replace(&mut self, op: usize, new: Op) {
        self.touch(op);
        if !self.is_live(op) {
            self.ops[op] = new;
            return;
        }
        let old = std::mem::replace(&mut self.ops[op], new);
        self.reindex(op, &old);
        // The new operands first, so that those both use stay live.
        let mut added = Vec::new();
        self.each_operand(op, |x| added.push(x));
        for x in added {
            self.add_use(x);
        }
        let mut removed = Vec::new();
        each_operand(&old, |x| removed.push(x));
        for x in removed {
            self.drop_use(x);
        }
    }

    /// One more use of `x`: a dead `x` comes alive, and with it what it uses.
    fn add_use(&mut self, x: usize) {
        let was_live = self.is_live(x);
        self.uses[x] += 1;
        self.touch(x);
        if !was_live {
            self.revive(x);
        }
    }

    /// One use of `x` fewer: an `x` left unused dies, and with it what only
    /// it used.
    fn drop_use(&mut self, x: usize) {
        self.uses[x] -= 1;
        self.touch(x);
        if self.is_live(x) {
            return;
        }
        let mut stack = vec![x];
        while let Some(op) = stack.pop() {
            self.index(op, false);
            let mut operands = Vec::new();
            self.each_operand(op, |x| operands.push(x));
            for x in operands {
                self.uses[x] -= 1;
                self.touch(x);
                if !self.is_live(x) {
                    stack.push(x);
                }
            }
        }
    }

    /// `op`, just come alive: its pairs are indexed and its operands used,
    /// the dead ones coming alive in turn.
    fn revive(&mut self, op: usize) {
        let mut stack = vec![op];
        while let Some(op) = stack.pop() {
            self.index(op, true);
            let mut operands = Vec::new();
            self.each_operand(op, |x| operands.push(x));
            for x in operands {
                if !self.is_live(x) {
                    stack.push(x);
                }
                self.uses[x] += 1;
                self.touch(x);
            }
        }
    }

    /// Records that `op`, or how often it is used, changed.
    fn touch(&mut self, op: usize) {
        self.clock += 1;
        self.changed[op] = self.clock;
    }

    /// Records that `op` has no common factor to take out (as it is now).
    pub(super) fn set_factorless(&mut self, op: usize) {
        self.factorless_at[op] = Some(self.clock);
    }

    /// Forgets which ops were found to have no common factor.
    pub(super) fn forget_factorless(&mut self) {
        self.factorless_at.fill(None);
    }

    /// Whether `op` was found to have no common factor and neither it nor
    /// its terms (their factors, their uses) changed since: what decides
    /// whether it has one.
    pub(super) fn factorless(&self, op: usize) -> bool {
        self.factorless_at[op].is_some_and(|at| {
            self.changed[op] <= at
                && match &self.ops[op] {
                    Op::Sum { terms, .. } => terms.iter().all(|(t, _)| self.changed[*t] <= at),
                    _ => true,
                }
        })
    }

    /// Updates the indices for `op`, which held the pairs of `old` (an op
    /// whose content is `old`) and now holds its own.
    fn reindex(&mut self, op: usize, old: &Op) {
        let (old_products, old_sums) = pairs_of(old);
        let (products, sums) = pairs_of(&self.ops[op]);
        self.product_pairs.update(op, &old_products, &products);
        self.sum_pairs.update(op, &old_sums, &sums);
    }

    /// Adds `op`'s pairs to the indices (removes them unless `add`).
    fn index(&mut self, op: usize, add: bool) {
        let (products, sums) = pairs_of(&self.ops[op]);
        if add {
            self.product_pairs.update(op, &[], &products);
            self.sum_pairs.update(op, &[], &sums);
        } else {
            self.product_pairs.update(op, &products, &[]);
            self.sum_pairs.update(op, &sums, &[]);
        }
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
}

/// Calls `f` with each operand of `op`, in order (repeated factors of a
/// product repeatedly).
fn each_operand(op: &Op, mut f: impl FnMut(usize)) {
    match op {
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
