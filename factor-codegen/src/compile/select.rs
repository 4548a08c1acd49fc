//! Stage 3, instruction selection: each n-ary operation becomes a tree of
//! binary instructions. Signs become subtractions, equal coefficients are
//! applied once, and a reciprocal used by a single product turns back into a
//! division. The tree combines the operands ready first first (by the
//! latency model of [`Instr::latency`]), and a literal joins a product as one
//! more factor, so it meets an early operand instead of waiting for a late
//! one. The operation count is that of any tree; what shrinks is the longest
//! dependency chain, which bounds a kernel of a few hundred operations more
//! than their number does. Before a reciprocal or a square root (which
//! everything after it waits for), a literal shared by several terms is
//! applied to each term when that makes the sum ready sooner, at the price
//! of an operation.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use factor_symbolic::graph::Real;

use super::ops::{LeafOp, Op};
use crate::ir::{Instr, Program, Value};

pub(super) struct Emitter<'a> {
    pub(super) ops: &'a [Op],
    /// How many times the program's ops use each op (indexed by op).
    pub(super) uses: Vec<usize>,
    pub(super) program: Program,
    pub(super) values: HashMap<usize, Value>,
    /// Estimated ready time of each instruction emitted so far
    /// ([`Instr::latency`] along its longest operand path).
    pub(super) ready: Vec<u32>,
    /// Whether a reciprocal or a square root depends on each op (indexed by
    /// op): everything after those waits for them, so their latency is worth
    /// an operation.
    pub(super) urgent: Vec<bool>,
}

impl Emitter<'_> {
    fn constant(&mut self, c: f64) -> Value {
        self.program.push(Instr::Const(Real::new(c)))
    }

    pub(super) fn emit(&mut self, op: usize) -> Value {
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
            LeafOp::Sqrt(x) => self.unary(x, Instr::Sqrt),
            LeafOp::Sin(x) => self.unary(x, Instr::Sin),
            LeafOp::Cos(x) => self.unary(x, Instr::Cos),
            LeafOp::Exp(x) => self.unary(x, Instr::Exp),
            LeafOp::Ln(x) => self.unary(x, Instr::Ln),
            LeafOp::Acos(x) => self.unary(x, Instr::Acos),
            LeafOp::Asin(x) => self.unary(x, Instr::Asin),
            LeafOp::Atan(x) => self.unary(x, Instr::Atan),
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

    /// `f(x)` for a one-operand instruction `f`.
    fn unary(&mut self, x: usize, f: fn(Value) -> Instr) -> Value {
        let x = self.emit(x);
        self.program.push(f(x))
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
                Op::Recip(x) if self.uses[f] == 1 && !self.values.contains_key(&f) => {
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
            Op::Sum { constant, terms } if self.uses[op] == 1 && !self.values.contains_key(&op) => {
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
                let urgent = self.urgent[op];
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
            } if self.uses[op] == 1 && !self.values.contains_key(&op) => {
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
