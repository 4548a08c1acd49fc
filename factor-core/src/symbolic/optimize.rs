//! Compiles a kernel's outputs into a short straight-line [`Program`].
//!
//! 1. The live DAG becomes n-ary sums and products over shared operands; a
//!    negative power `x⁻ᵏ` becomes `k` factors of one shared reciprocal.
//! 2. Common pairs are extracted greedily, the most frequent first, until
//!    no pair occurs twice: operand pairs `a·b` across all products, and
//!    term pairs `a + r·b` (up to a common coefficient) across all sums. This
//!    is the classic pairwise common-subexpression heuristic; canonical
//!    operand order makes it deterministic.
//! 3. Each n-ary operation is emitted as a tree of binary instructions:
//!    signs become subtractions, equal coefficients are applied once, and a
//!    reciprocal used by a single product turns back into a division. The
//!    tree combines the operands ready first first (by the latency model of
//!    [`Instr::latency`]), and a literal joins a product as one more factor,
//!    so it meets an early operand instead of waiting for a late one. The
//!    operation count is that of any tree; what shrinks is the longest
//!    dependency chain, which bounds a kernel of a few hundred operations
//!    more than their number does. Before a reciprocal or a square root
//!    (which everything after it waits for), a literal shared by several
//!    terms is applied to each term when that makes the sum ready sooner,
//!    at the price of an operation.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use crate::symbolic::graph::{Expr, Graph, Node, Real};
use crate::symbolic::lower::{Instr, Program, Value};

/// An operation over shared operands, before lowering to binary instructions.
#[derive(Clone, Debug)]
enum Op {
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
enum LeafOp {
    Input(u32),
    Const(f64),
    Sqrt(usize),
    Sin(usize),
    Cos(usize),
    Atan2(usize, usize),
    Select([usize; 4]),
}

struct Compiler<'g> {
    graph: &'g Graph,
    ops: Vec<Op>,
    of_expr: HashMap<Expr, usize>,
    recip_of: HashMap<usize, usize>,
    interned: HashMap<OpKey, usize>,
}

/// The identity of a product or sum, for interning ops made by rewrites.
#[derive(PartialEq, Eq, Hash)]
enum OpKey {
    Product(u64, Vec<usize>),
    Sum(u64, Vec<(usize, u64)>),
}

/// The order in which the rewrites are tried; [`compile`] keeps the best.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Pair extraction only.
    Pairs,
    /// Distributive factoring before pair extraction.
    FactorFirst,
    /// Pair extraction to a fixed point, then factoring and pairs again.
    PairsThenFactor,
    /// Factoring of every product term, shared or not, before pairs.
    FactorShared,
}

/// Every strategy, in the order ties are broken.
pub const STRATEGIES: [Strategy; 4] = [
    Strategy::Pairs,
    Strategy::FactorFirst,
    Strategy::PairsThenFactor,
    Strategy::FactorShared,
];

/// Compiles `outputs` (of `graph`) with every [`Strategy`] and keeps the
/// program with the fewest operations (the first on a tie).
pub fn compile(graph: &Graph, outputs: &[Expr]) -> (Program, Vec<Value>) {
    STRATEGIES
        .iter()
        .map(|s| compile_with(graph, outputs, *s))
        .min_by_key(|(program, values)| program.counts(values).total())
        .expect("at least one strategy")
}

/// Compiles `outputs` with one strategy.
pub fn compile_with(graph: &Graph, outputs: &[Expr], strategy: Strategy) -> (Program, Vec<Value>) {
    let mut c = Compiler {
        graph,
        ops: Vec::new(),
        of_expr: HashMap::new(),
        recip_of: HashMap::new(),
        interned: HashMap::new(),
    };
    let roots: Vec<usize> = outputs.iter().map(|e| c.op_of(*e)).collect();
    let pairs =
        |c: &mut Compiler, live: &[usize]| c.extract_product_pair(live) || c.extract_sum_pair(live);
    let mut factoring = matches!(strategy, Strategy::FactorFirst | Strategy::FactorShared);
    let shared = strategy == Strategy::FactorShared;
    loop {
        let live = c.live(&roots);
        let changed = (factoring && c.factor_sum(&live, shared)) || pairs(&mut c, &live);
        if !changed {
            if strategy == Strategy::PairsThenFactor && !factoring {
                factoring = true;
                continue;
            }
            break;
        }
    }
    let live = c.live(&roots);
    let uses = c.use_counts(&live);
    let mut emitter = Emitter {
        ops: &c.ops,
        uses,
        program: Program::default(),
        values: HashMap::new(),
        ready: Vec::new(),
        urgent: c.urgent(&live),
    };
    let values = roots.iter().map(|r| emitter.emit(*r)).collect();
    (emitter.program, values)
}

impl Compiler<'_> {
    fn push(&mut self, op: Op) -> usize {
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
    fn product(&mut self, coefficient: f64, mut factors: Vec<usize>) -> Option<usize> {
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

    /// Factors the most common factor out of one live sum's product terms
    /// (only single-use ones unless `shared`): `Σ cᵢ f gᵢ = f · Σ cᵢ gᵢ` saves a multiplication per
    /// term beyond the first.
    fn factor_sum(&mut self, live: &[usize], shared: bool) -> bool {
        let uses = self.use_counts(live);
        for &op in live {
            let Op::Sum { constant, terms } = self.ops[op].clone() else {
                continue;
            };
            // Each term as (coefficient inside, factor multiset), if eligible.
            let split: Vec<Option<(f64, Vec<usize>)>> = terms
                .iter()
                .map(|(t, _)| match &self.ops[*t] {
                    Op::Product {
                        coefficient,
                        factors,
                    } if shared || uses.get(t) == Some(&1) => Some((*coefficient, factors.clone())),
                    Op::Product { .. } => None,
                    _ => Some((1.0, vec![*t])),
                })
                .collect();
            let mut counts: BTreeMap<usize, usize> = BTreeMap::new();
            for (_, factors) in split.iter().flatten() {
                for f in factors.iter().collect::<BTreeSet<_>>() {
                    *counts.entry(*f).or_insert(0) += 1;
                }
            }
            let Some((&f, _)) = counts
                .iter()
                .filter(|(_, n)| **n >= 2)
                .max_by_key(|(f, n)| (**n, std::cmp::Reverse(**f)))
            else {
                continue;
            };
            let mut inner_constant = 0.0;
            let mut inner: BTreeMap<usize, f64> = BTreeMap::new();
            let mut outer: Vec<(usize, f64)> = Vec::new();
            for ((t, c), parts) in terms.iter().zip(split) {
                match parts {
                    Some((k, mut factors)) if factors.contains(&f) => {
                        let i = factors.iter().position(|x| *x == f).expect("contains");
                        factors.remove(i);
                        match self.product(k, factors) {
                            Some(cofactor) => *inner.entry(cofactor).or_insert(0.0) += c,
                            None => inner_constant += c * k,
                        }
                    }
                    _ => outer.push((*t, *c)),
                }
            }
            let mut inner: Vec<(usize, f64)> =
                inner.into_iter().filter(|(_, c)| *c != 0.0).collect();
            // A sum whose terms are all negative would cost a negation: carry
            // its sign out to this sum's coefficient instead.
            let sign = if inner.iter().all(|(_, c)| *c < 0.0) && inner_constant <= 0.0 {
                -1.0
            } else {
                1.0
            };
            inner.iter_mut().for_each(|(_, c)| *c *= sign);
            let inner_sum = self.push(Op::Sum {
                constant: inner_constant * sign,
                terms: inner,
            });
            let factored = self.push(Op::Product {
                coefficient: 1.0,
                factors: {
                    let mut v = vec![f, inner_sum];
                    v.sort_unstable();
                    v
                },
            });
            outer.push((factored, sign));
            outer.sort_unstable_by_key(|(t, _)| *t);
            self.ops[op] = Op::Sum {
                constant,
                terms: outer,
            };
            return true;
        }
        false
    }

    fn recip(&mut self, x: usize) -> usize {
        if let Some(&r) = self.recip_of.get(&x) {
            return r;
        }
        let r = self.push(Op::Recip(x));
        self.recip_of.insert(x, r);
        r
    }

    fn op_of(&mut self, e: Expr) -> usize {
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

    fn operands(&self, op: usize) -> Vec<usize> {
        match &self.ops[op] {
            Op::Leaf(leaf) => match *leaf {
                LeafOp::Input(_) | LeafOp::Const(_) => Vec::new(),
                LeafOp::Sqrt(x) | LeafOp::Sin(x) | LeafOp::Cos(x) => vec![x],
                LeafOp::Atan2(y, x) => vec![y, x],
                LeafOp::Select(args) => args.to_vec(),
            },
            Op::Recip(x) => vec![*x],
            Op::Product { factors, .. } => factors.clone(),
            Op::Sum { terms, .. } => terms.iter().map(|(t, _)| *t).collect(),
        }
    }

    /// Ops reachable from the roots, in increasing id order.
    fn live(&self, roots: &[usize]) -> Vec<usize> {
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
    fn urgent(&self, live: &[usize]) -> BTreeSet<usize> {
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

    fn use_counts(&self, live: &[usize]) -> HashMap<usize, usize> {
        let mut uses = HashMap::new();
        for &op in live {
            for operand in self.operands(op) {
                *uses.entry(operand).or_insert(0) += 1;
            }
        }
        uses
    }

    /// Extracts the most frequent operand pair of the live products.
    fn extract_product_pair(&mut self, live: &[usize]) -> bool {
        let mut counts: BTreeMap<(usize, usize), usize> = BTreeMap::new();
        for &op in live {
            if let Op::Product { factors, .. } = &self.ops[op] {
                let mut pairs = BTreeSet::new();
                for i in 0..factors.len() {
                    for j in i + 1..factors.len() {
                        pairs.insert((factors[i], factors[j]));
                    }
                }
                for pair in pairs {
                    *counts.entry(pair).or_insert(0) += 1;
                }
            }
        }
        let Some((&(a, b), _)) = counts
            .iter()
            .filter(|(_, n)| **n >= 2)
            .max_by_key(|(pair, n)| (**n, std::cmp::Reverse(**pair)))
        else {
            return false;
        };
        let pair = self.push(Op::Product {
            coefficient: 1.0,
            factors: vec![a, b],
        });
        for &op in live {
            if op == pair {
                continue;
            }
            if let Op::Product { factors, .. } = &mut self.ops[op] {
                {
                    if let Some(i) = factors.iter().position(|f| *f == a) {
                        let rest: Vec<usize> = factors
                            .iter()
                            .enumerate()
                            .filter(|(k, _)| *k != i)
                            .map(|(_, f)| *f)
                            .collect();
                        if let Some(j) = rest.iter().position(|f| *f == b) {
                            let mut next: Vec<usize> = rest
                                .iter()
                                .enumerate()
                                .filter(|(k, _)| *k != j)
                                .map(|(_, f)| *f)
                                .collect();
                            next.push(pair);
                            next.sort_unstable();
                            *factors = next;
                        }
                    }
                }
            }
        }
        true
    }

    /// Extracts the most frequent term pair `a + r·b` of the live sums.
    fn extract_sum_pair(&mut self, live: &[usize]) -> bool {
        let mut counts: BTreeMap<(usize, usize, u64), usize> = BTreeMap::new();
        for &op in live {
            if let Op::Sum { terms, .. } = &self.ops[op] {
                let mut pairs = BTreeSet::new();
                for i in 0..terms.len() {
                    for j in i + 1..terms.len() {
                        let ratio = Real::new(terms[j].1 / terms[i].1);
                        pairs.insert((terms[i].0, terms[j].0, ratio.bits()));
                    }
                }
                for pair in pairs {
                    *counts.entry(pair).or_insert(0) += 1;
                }
            }
        }
        let Some((&(a, b, ratio_bits), _)) = counts
            .iter()
            .filter(|(_, n)| **n >= 2)
            .max_by_key(|(pair, n)| (**n, std::cmp::Reverse(**pair)))
        else {
            return false;
        };
        let ratio = f64::from_bits(ratio_bits);
        let pair = self.push(Op::Sum {
            constant: 0.0,
            terms: vec![(a, 1.0), (b, ratio)],
        });
        for &op in live {
            if op == pair {
                continue;
            }
            if let Op::Sum { terms, .. } = &mut self.ops[op] {
                let ia = terms.iter().position(|(t, _)| *t == a);
                let ib = terms.iter().position(|(t, _)| *t == b);
                if let (Some(ia), Some(ib)) = (ia, ib) {
                    let ca = terms[ia].1;
                    if Real::new(terms[ib].1 / ca) == Real::new(ratio) {
                        terms.retain(|(t, _)| *t != a && *t != b);
                        terms.push((pair, ca));
                        terms.sort_unstable_by_key(|(t, _)| *t);
                    }
                }
            }
        }
        true
    }
}

struct Emitter<'a> {
    ops: &'a [Op],
    uses: HashMap<usize, usize>,
    program: Program,
    values: HashMap<usize, Value>,
    /// Estimated ready time of each instruction emitted so far
    /// ([`Instr::latency`] along its longest operand path).
    ready: Vec<u32>,
    /// Ops a reciprocal or a square root depends on: everything after those
    /// waits for them, so their latency is worth an operation.
    urgent: BTreeSet<usize>,
}

impl Emitter<'_> {
    fn constant(&mut self, c: f64) -> Value {
        self.program.push(Instr::Const(Real::new(c)))
    }

    fn emit(&mut self, op: usize) -> Value {
        if let Some(&v) = self.values.get(&op) {
            return v;
        }
        let v = match self.ops[op].clone() {
            Op::Leaf(leaf) => self.emit_leaf(leaf),
            Op::Recip(x) => {
                let one = self.constant(1.0);
                let x = self.emit(x);
                self.program.push(Instr::Div(one, x))
            }
            Op::Product {
                coefficient,
                factors,
            } => self.emit_product(coefficient, &factors),
            Op::Sum { constant, terms } => self.emit_sum(op, constant, &terms),
        };
        self.values.insert(op, v);
        v
    }

    fn emit_leaf(&mut self, leaf: LeafOp) -> Value {
        match leaf {
            LeafOp::Input(i) => self.program.push(Instr::Input(i)),
            LeafOp::Const(c) => self.constant(c),
            LeafOp::Sqrt(x) => {
                let x = self.emit(x);
                self.program.push(Instr::Sqrt(x))
            }
            LeafOp::Sin(x) => {
                let x = self.emit(x);
                self.program.push(Instr::Sin(x))
            }
            LeafOp::Cos(x) => {
                let x = self.emit(x);
                self.program.push(Instr::Cos(x))
            }
            LeafOp::Atan2(y, x) => {
                let (y, x) = (self.emit(y), self.emit(x));
                self.program.push(Instr::Atan2(y, x))
            }
            LeafOp::Select([lhs, rhs, if_less, otherwise]) => {
                let (lhs, rhs) = (self.emit(lhs), self.emit(rhs));
                let (if_less, otherwise) = (self.emit(if_less), self.emit(otherwise));
                self.program.push(Instr::Select {
                    lhs,
                    rhs,
                    if_less,
                    otherwise,
                })
            }
        }
    }

    /// When `v` is ready, by the latency model of [`Instr::latency`].
    fn ready(&mut self, v: Value) -> u32 {
        while self.ready.len() < self.program.instrs.len() {
            let instr = self.program.instrs[self.ready.len()];
            let start = instr
                .operands()
                .iter()
                .map(|o| self.ready[o.0 as usize])
                .max()
                .unwrap_or(0);
            self.ready.push(start + instr.latency());
        }
        self.ready[v.0 as usize]
    }

    /// `Σ ±vᵢ` (`true` marks a negative member), as a signed value.
    ///
    /// The two members ready first are combined first (Huffman's rule on
    /// ready times): the same `n − 1` operations as any binary tree, and the
    /// result is ready as early as the operands allow, so work that waits on
    /// a late value (a division, a square root) is as short as it can be.
    /// With equal ready times this is a balanced tree. Signs become
    /// subtractions; the result is negative only when every member is (the
    /// caller may absorb the sign).
    fn signed_tree(&mut self, members: &[(Value, bool)]) -> Option<(Value, bool)> {
        self.ready_first_tree(
            members.to_vec(),
            |e, (a, a_negative), (b, b_negative)| match (a_negative, b_negative) {
                (false, false) => (e.program.push(Instr::Add(a, b)), false),
                (false, true) => (e.program.push(Instr::Sub(a, b)), false),
                (true, false) => (e.program.push(Instr::Sub(b, a)), false),
                (true, true) => (e.program.push(Instr::Add(a, b)), true),
            },
        )
    }

    /// `Π vᵢ` by the same rule as [`Emitter::signed_tree`].
    fn product_tree(&mut self, values: impl IntoIterator<Item = Value>) -> Option<Value> {
        let members = values.into_iter().map(|v| (v, ())).collect();
        self.ready_first_tree(members, |e, (a, ()), (b, ())| {
            (e.program.push(Instr::Mul(a, b)), ())
        })
        .map(|(v, ())| v)
    }

    /// Combines the two members ready first, with `combine`, until one is
    /// left (ties by order of appearance, so the result is deterministic).
    fn ready_first_tree<M: Copy>(
        &mut self,
        members: Vec<(Value, M)>,
        combine: impl Fn(&mut Self, (Value, M), (Value, M)) -> (Value, M),
    ) -> Option<(Value, M)> {
        let mut pending: Vec<(u32, usize, (Value, M))> = Vec::new();
        for (order, member) in members.into_iter().enumerate() {
            pending.push((self.ready(member.0), order, member));
        }
        let mut order = pending.len();
        while pending.len() > 1 {
            pending.sort_unstable_by_key(|(ready, order, _)| std::cmp::Reverse((*ready, *order)));
            let (_, _, a) = pending.pop().expect("two members");
            let (_, _, b) = pending.pop().expect("two members");
            let combined = combine(self, a, b);
            pending.push((self.ready(combined.0), order, combined));
            order += 1;
        }
        pending.pop().map(|(_, _, member)| member)
    }

    fn emit_product(&mut self, coefficient: f64, factors: &[usize]) -> Value {
        // `c · (private sum)`: the coefficient goes into the sum's terms when
        // that costs no more multiplications (`−2 (½a + b)` is `−a − 2b`).
        if let [f] = *factors
            && coefficient.abs() != 1.0
            && let Some((k, terms)) = self.private_sum(f)
        {
            let scaled: Vec<(usize, f64)> =
                terms.iter().map(|(t, c)| (*t, c * coefficient)).collect();
            if scaling_multiplications(&scaled) <= scaling_multiplications(&terms) + 1 {
                return self.emit_sum(f, k * coefficient, &scaled);
            }
        }
        // A reciprocal no other op uses is folded back into a division.
        let mut numerator = Vec::new();
        let mut denominator = Vec::new();
        for &f in factors {
            match self.ops[f] {
                Op::Recip(x) if self.uses.get(&f) == Some(&1) && !self.values.contains_key(&f) => {
                    denominator.push(x)
                }
                _ => numerator.push(f),
            }
        }
        // Signs are absorbed by single-use sum factors, emitted negated: an
        // all-negative sum flips for free, and a remaining minus sign flips
        // one mixed sum (`−(a − b)` is `b − a`).
        let mut negate = coefficient < 0.0;
        let mut flipped = BTreeSet::new();
        for &f in &numerator {
            if self
                .private_sum(f)
                .is_some_and(|(k, terms)| k <= 0.0 && terms.iter().all(|(_, c)| *c < 0.0))
            {
                flipped.insert(f);
                negate = !negate;
            }
        }
        if negate
            && coefficient.abs() == 1.0
            && let Some(&f) = numerator
                .iter()
                .find(|f| !flipped.contains(*f) && self.private_sum(**f).is_some())
        {
            flipped.insert(f);
            negate = false;
        }
        let mut numerator: Vec<Value> = numerator
            .into_iter()
            .map(|f| match self.private_sum(f) {
                Some((k, terms)) if flipped.contains(&f) => {
                    let negated: Vec<(usize, f64)> = terms.iter().map(|(t, c)| (*t, -c)).collect();
                    self.emit_sum(f, -k, &negated)
                }
                _ => self.emit(f),
            })
            .collect();
        let denominator: Vec<Value> = denominator.into_iter().map(|f| self.emit(f)).collect();
        let magnitude = coefficient.abs();
        // The literal is one more factor (it is ready at once, so it meets
        // the earliest factor, off the critical path), carrying the sign.
        // A sign without a literal to ride on is a final negation (measured
        // faster than negating the earliest factor instead).
        let signed = if negate { -magnitude } else { magnitude };
        let sign_flip = negate && magnitude == 1.0 && !numerator.is_empty();
        if magnitude != 1.0 || numerator.is_empty() {
            numerator.push(self.constant(signed));
        }
        let mut value = self
            .product_tree(numerator)
            .expect("a factor or the literal");
        if let Some(d) = self.product_tree(denominator) {
            value = self.program.push(Instr::Div(value, d));
        }
        if sign_flip {
            value = self.program.push(Instr::Neg(value));
        }
        value
    }

    /// A sum op only this use reads and not yet emitted: `(constant, terms)`.
    fn private_sum(&self, op: usize) -> Option<(f64, Vec<(usize, f64)>)> {
        match &self.ops[op] {
            Op::Sum { constant, terms }
                if self.uses.get(&op) == Some(&1) && !self.values.contains_key(&op) =>
            {
                Some((*constant, terms.clone()))
            }
            _ => None,
        }
    }

    /// The sum `op` (possibly rescaled or negated by its only user).
    fn emit_sum(&mut self, op: usize, constant: f64, terms: &[(usize, f64)]) -> Value {
        // Terms sharing a coefficient magnitude are summed before one multiply.
        let mut groups: BTreeMap<u64, Vec<(usize, f64)>> = BTreeMap::new();
        for &(t, c) in terms {
            groups.entry(c.abs().to_bits()).or_default().push((t, c));
        }
        let mut signed: Vec<(Value, bool)> = Vec::new();
        for (bits, group) in groups {
            let magnitude = f64::from_bits(bits);
            // A literal applied to each term early (`(2x)·a + (2y)·b`) or to
            // the group's sum late (`2·(x·a + y·b)`): both are emitted, and
            // the unused one is dead code. Early wins when it costs no more
            // instructions (its products may exist already) and is ready
            // sooner, or, before a division or a square root (which all
            // later work waits for), whenever it is ready sooner.
            if magnitude != 1.0 && group.len() > 1 {
                let start = self.program.instrs.len();
                let early = self.scaled_terms(magnitude, &group);
                let early = self.signed_tree(&early).expect("a term");
                let late = self.scaled_group(magnitude, &group);
                let (early_cost, late_cost) = (
                    self.cost_since(early.0, start),
                    self.cost_since(late.0, start),
                );
                let sooner = self.ready(early.0) < self.ready(late.0);
                let urgent = self.urgent.contains(&op);
                signed.push(if sooner && (urgent || early_cost <= late_cost) {
                    early
                } else {
                    late
                });
                continue;
            }
            // A lone scaled product only this sum reads takes the literal
            // among its own factors, where it is applied early.
            signed.extend(self.scaled_terms(magnitude, &group));
        }
        if constant != 0.0 {
            let c = self.constant(constant.abs());
            signed.push((c, constant < 0.0));
        }
        match self.signed_tree(&signed).expect("a sum has a term") {
            (v, false) => v,
            (v, true) => self.program.push(Instr::Neg(v)),
        }
    }

    /// Instructions from index `start` on that `v` depends on: what choosing
    /// `v` adds to the program.
    fn cost_since(&self, v: Value, start: usize) -> usize {
        let mut seen = BTreeSet::new();
        let mut stack = vec![v];
        while let Some(v) = stack.pop() {
            if (v.0 as usize) >= start && seen.insert(v) {
                stack.extend(self.program.instrs[v.0 as usize].operands());
            }
        }
        seen.iter()
            .filter(|v| {
                !matches!(
                    self.program.instrs[v.0 as usize],
                    Instr::Input(_) | Instr::Const(_)
                )
            })
            .count()
    }

    /// `Σ cᵢ tᵢ` over terms of one coefficient magnitude, summed, then
    /// multiplied by the magnitude once; signed.
    fn scaled_group(&mut self, magnitude: f64, group: &[(usize, f64)]) -> (Value, bool) {
        // Oriented negative only when every term is: a mixed group is
        // `a − b`, never `−(b − a)`.
        let lead_negative = group.iter().all(|(_, c)| *c < 0.0);
        let members: Vec<(Value, bool)> = group
            .iter()
            .map(|&(t, c)| (self.emit(t), (c < 0.0) != lead_negative))
            .collect();
        let (inner, inner_negative) = self.signed_tree(&members).expect("a term");
        let scaled = if magnitude == 1.0 {
            inner
        } else {
            let c = self.constant(magnitude);
            self.program.push(Instr::Mul(c, inner))
        };
        (scaled, lead_negative != inner_negative)
    }

    /// Each `cᵢ tᵢ` of one coefficient magnitude on its own, signed: a
    /// product only this sum reads takes the literal among its factors
    /// (applied to its earliest one), any other term is multiplied by it.
    fn scaled_terms(&mut self, magnitude: f64, group: &[(usize, f64)]) -> Vec<(Value, bool)> {
        group
            .iter()
            .map(|&(t, c)| {
                let value = match self.private_product(t) {
                    Some((k, factors)) => self.emit_product(k * magnitude, &factors),
                    None => {
                        let term = self.emit(t);
                        if magnitude == 1.0 {
                            term
                        } else {
                            let literal = self.constant(magnitude);
                            self.program.push(Instr::Mul(literal, term))
                        }
                    }
                };
                (value, c < 0.0)
            })
            .collect()
    }

    /// A product op only this use reads and not yet emitted:
    /// `(coefficient, factors)`.
    fn private_product(&self, op: usize) -> Option<(f64, Vec<usize>)> {
        match &self.ops[op] {
            Op::Product {
                coefficient,
                factors,
            } if self.uses.get(&op) == Some(&1) && !self.values.contains_key(&op) => {
                Some((*coefficient, factors.clone()))
            }
            _ => None,
        }
    }
}

/// Multiplications by literals that [`Emitter::emit_sum`] spends on `terms`:
/// one per distinct coefficient magnitude other than 1.
fn scaling_multiplications(terms: &[(usize, f64)]) -> usize {
    let magnitudes: BTreeSet<u64> = terms
        .iter()
        .map(|(_, c)| c.abs())
        .filter(|m| *m != 1.0)
        .map(f64::to_bits)
        .collect();
    magnitudes.len()
}
