//! Lowering of the canonical DAG to straight-line binary instructions.
//!
//! Each n-ary sum or product becomes a chain of binary operations; binary
//! instructions are interned too, so a sub-chain two nodes share is computed
//! once. Coefficients of ±1 cost nothing (an add becomes a subtract), and a
//! negative power `x⁻ᵏ` is a power of the one shared reciprocal `1/x`.

use std::collections::HashMap;

use crate::symbolic::graph::{Expr, Graph, Node, Real};

/// An SSA value: the index of the instruction that computes it.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
pub struct Value(pub u32);

/// One instruction.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Instr {
    /// Input scalar `i`.
    Input(u32),
    /// A literal.
    Const(Real),
    /// `a + b`.
    Add(Value, Value),
    /// `a − b`.
    Sub(Value, Value),
    /// `a · b`.
    Mul(Value, Value),
    /// `a / b`.
    Div(Value, Value),
    /// `−a`.
    Neg(Value),
    /// `√a`.
    Sqrt(Value),
    /// `sin a`.
    Sin(Value),
    /// `cos a`.
    Cos(Value),
    /// `atan2(a, b)`.
    Atan2(Value, Value),
    /// `if lhs < rhs { if_less } else { otherwise }`.
    Select {
        /// Left side of the comparison.
        lhs: Value,
        /// Right side.
        rhs: Value,
        /// Value when `lhs < rhs`.
        if_less: Value,
        /// Value otherwise.
        otherwise: Value,
    },
}

impl Instr {
    /// Operands, in order.
    pub fn operands(&self) -> Vec<Value> {
        match *self {
            Instr::Input(_) | Instr::Const(_) => Vec::new(),
            Instr::Neg(a) | Instr::Sqrt(a) | Instr::Sin(a) | Instr::Cos(a) => vec![a],
            Instr::Add(a, b)
            | Instr::Sub(a, b)
            | Instr::Mul(a, b)
            | Instr::Div(a, b)
            | Instr::Atan2(a, b) => {
                vec![a, b]
            }
            Instr::Select {
                lhs,
                rhs,
                if_less,
                otherwise,
            } => vec![lhs, rhs, if_less, otherwise],
        }
    }
}

/// Operation counts by kind, SymForce-style: every arithmetic instruction is
/// one operation, loads and literals are free.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OpCounts {
    /// Additions and subtractions.
    pub add: usize,
    /// Multiplications.
    pub mul: usize,
    /// Divisions.
    pub div: usize,
    /// Negations.
    pub neg: usize,
    /// Square roots.
    pub sqrt: usize,
    /// `sin`, `cos`, `atan2`.
    pub trig: usize,
    /// Conditional selections.
    pub branch: usize,
}

impl OpCounts {
    /// The sum of all kinds.
    pub fn total(&self) -> usize {
        self.add + self.mul + self.div + self.neg + self.sqrt + self.trig + self.branch
    }

    /// Counts one instruction.
    pub fn count(&mut self, instr: &Instr) {
        match instr {
            Instr::Input(_) | Instr::Const(_) => {}
            Instr::Add(..) | Instr::Sub(..) => self.add += 1,
            Instr::Mul(..) => self.mul += 1,
            Instr::Div(..) => self.div += 1,
            Instr::Neg(_) => self.neg += 1,
            Instr::Sqrt(_) => self.sqrt += 1,
            Instr::Sin(_) | Instr::Cos(_) | Instr::Atan2(..) => self.trig += 1,
            Instr::Select { .. } => self.branch += 1,
        }
    }
}

/// A straight-line program being built from DAG nodes.
#[derive(Default)]
pub struct Program {
    /// Instructions; operands always precede their users.
    pub instrs: Vec<Instr>,
    interned: HashMap<Instr, Value>,
    lowered: HashMap<Expr, Value>,
}

impl Program {
    /// Interns an instruction, ordering the operands of `+` and `·`.
    pub fn push(&mut self, instr: Instr) -> Value {
        let instr = match instr {
            Instr::Add(a, b) if b < a => Instr::Add(b, a),
            Instr::Mul(a, b) if b < a => Instr::Mul(b, a),
            other => other,
        };
        if let Some(&v) = self.interned.get(&instr) {
            return v;
        }
        let v = Value(u32::try_from(self.instrs.len()).expect("fewer than 2³² instructions"));
        self.instrs.push(instr);
        self.interned.insert(instr, v);
        v
    }

    fn constant(&mut self, c: f64) -> Value {
        self.push(Instr::Const(Real::new(c)))
    }

    /// The value of `e`, lowering what is not lowered yet.
    pub fn lower(&mut self, graph: &Graph, e: Expr) -> Value {
        if let Some(&v) = self.lowered.get(&e) {
            return v;
        }
        let v = match graph.node(e).clone() {
            Node::Const(c) => self.push(Instr::Const(c)),
            Node::Input(i) => self.push(Instr::Input(i)),
            Node::Add { constant, terms } => self.lower_sum(graph, constant.get(), &terms),
            Node::Mul {
                coefficient,
                factors,
            } => self.lower_product(graph, coefficient.get(), &factors),
            Node::Sqrt(x) => {
                let x = self.lower(graph, x);
                self.push(Instr::Sqrt(x))
            }
            Node::Sin(x) => {
                let x = self.lower(graph, x);
                self.push(Instr::Sin(x))
            }
            Node::Cos(x) => {
                let x = self.lower(graph, x);
                self.push(Instr::Cos(x))
            }
            Node::Atan2(y, x) => {
                let (y, x) = (self.lower(graph, y), self.lower(graph, x));
                self.push(Instr::Atan2(y, x))
            }
            Node::Select {
                lhs,
                rhs,
                if_less,
                otherwise,
            } => {
                let (lhs, rhs) = (self.lower(graph, lhs), self.lower(graph, rhs));
                let (if_less, otherwise) =
                    (self.lower(graph, if_less), self.lower(graph, otherwise));
                self.push(Instr::Select {
                    lhs,
                    rhs,
                    if_less,
                    otherwise,
                })
            }
        };
        self.lowered.insert(e, v);
        v
    }

    /// `|c| · t`, free when `|c| = 1`.
    fn scaled(&mut self, graph: &Graph, term: Expr, c: f64) -> Value {
        let t = self.lower(graph, term);
        if c.abs() == 1.0 {
            t
        } else {
            let c = self.constant(c.abs());
            self.push(Instr::Mul(c, t))
        }
    }

    fn lower_sum(&mut self, graph: &Graph, constant: f64, terms: &[(Expr, Real)]) -> Value {
        let mut acc: Option<Value> = None;
        for &(t, c) in terms.iter().filter(|(_, c)| c.get() > 0.0) {
            let term = self.scaled(graph, t, c.get());
            acc = Some(match acc {
                Some(a) => self.push(Instr::Add(a, term)),
                None => term,
            });
        }
        if constant != 0.0 {
            let k = self.constant(constant);
            acc = Some(match acc {
                Some(a) => self.push(Instr::Add(a, k)),
                None => k,
            });
        }
        let mut negatives: Option<Value> = None;
        for &(t, c) in terms.iter().filter(|(_, c)| c.get() < 0.0) {
            let term = self.scaled(graph, t, c.get());
            match acc {
                Some(a) => acc = Some(self.push(Instr::Sub(a, term))),
                None => {
                    negatives = Some(match negatives {
                        Some(n) => self.push(Instr::Add(n, term)),
                        None => term,
                    })
                }
            }
        }
        match (acc, negatives) {
            (Some(a), None) => a,
            (None, Some(n)) => self.push(Instr::Neg(n)),
            _ => unreachable!("a canonical sum has at least one term"),
        }
    }

    /// `b^k` for `k ≥ 1` by repeated squaring.
    fn power(&mut self, b: Value, k: u32) -> Value {
        if k == 1 {
            return b;
        }
        let half = self.power(b, k / 2);
        let square = self.push(Instr::Mul(half, half));
        if k % 2 == 1 {
            self.push(Instr::Mul(square, b))
        } else {
            square
        }
    }

    fn product_of(
        &mut self,
        graph: &Graph,
        factors: impl Iterator<Item = (Expr, u32)>,
    ) -> Option<Value> {
        let mut acc: Option<Value> = None;
        for (b, k) in factors {
            let b = self.lower(graph, b);
            let p = self.power(b, k);
            acc = Some(match acc {
                Some(a) => self.push(Instr::Mul(a, p)),
                None => p,
            });
        }
        acc
    }

    /// `1 / x`, one division shared by every product that divides by `x`.
    fn reciprocal(&mut self, graph: &Graph, x: Expr) -> Value {
        let one = self.constant(1.0);
        let x = self.lower(graph, x);
        self.push(Instr::Div(one, x))
    }

    fn lower_product(&mut self, graph: &Graph, coefficient: f64, factors: &[(Expr, i32)]) -> Value {
        let numerator = self.product_of(
            graph,
            factors
                .iter()
                .filter(|(_, k)| *k > 0)
                .map(|(b, k)| (*b, k.unsigned_abs())),
        );
        let mut denominator: Option<Value> = None;
        for &(b, k) in factors.iter().filter(|(_, k)| *k < 0) {
            let r = self.reciprocal(graph, b);
            let p = self.power(r, k.unsigned_abs());
            denominator = Some(match denominator {
                Some(d) => self.push(Instr::Mul(d, p)),
                None => p,
            });
        }
        // `denominator` holds reciprocals: multiply, never divide again.
        let magnitude = coefficient.abs();
        let value = match (numerator, denominator) {
            (Some(n), d) => {
                let n = if magnitude == 1.0 {
                    n
                } else {
                    let c = self.constant(magnitude);
                    self.push(Instr::Mul(c, n))
                };
                match d {
                    Some(d) => self.push(Instr::Mul(n, d)),
                    None => n,
                }
            }
            (None, Some(d)) if magnitude == 1.0 => d,
            (None, Some(d)) => {
                let c = self.constant(magnitude);
                self.push(Instr::Mul(c, d))
            }
            (None, None) => unreachable!("a canonical product has a factor"),
        };
        if coefficient < 0.0 {
            self.push(Instr::Neg(value))
        } else {
            value
        }
    }

    /// Operation counts of the instructions `outputs` depend on.
    pub fn counts(&self, outputs: &[Value]) -> OpCounts {
        let mut live = vec![false; self.instrs.len()];
        let mut stack: Vec<Value> = outputs.to_vec();
        while let Some(v) = stack.pop() {
            if !std::mem::replace(&mut live[v.0 as usize], true) {
                stack.extend(self.instrs[v.0 as usize].operands());
            }
        }
        let mut counts = OpCounts::default();
        for (instr, _) in self.instrs.iter().zip(&live).filter(|(_, l)| **l) {
            counts.count(instr);
        }
        counts
    }
}

impl Program {
    /// Runs the program on `inputs` and returns the values of `outputs`: the
    /// reference the emitted Rust is tested against.
    pub fn evaluate(&self, inputs: &[f64], outputs: &[Value]) -> Vec<f64> {
        let mut values = vec![0.0; self.instrs.len()];
        for (i, instr) in self.instrs.iter().enumerate() {
            let v = |x: &Value| values[x.0 as usize];
            values[i] = match instr {
                Instr::Input(k) => inputs[*k as usize],
                Instr::Const(c) => c.get(),
                Instr::Add(a, b) => v(a) + v(b),
                Instr::Sub(a, b) => v(a) - v(b),
                Instr::Mul(a, b) => v(a) * v(b),
                Instr::Div(a, b) => v(a) / v(b),
                Instr::Neg(a) => -v(a),
                Instr::Sqrt(a) => v(a).sqrt(),
                Instr::Sin(a) => v(a).sin(),
                Instr::Cos(a) => v(a).cos(),
                Instr::Atan2(a, b) => v(a).atan2(v(b)),
                Instr::Select {
                    lhs,
                    rhs,
                    if_less,
                    otherwise,
                } => {
                    if v(lhs) < v(rhs) {
                        v(if_less)
                    } else {
                        v(otherwise)
                    }
                }
            };
        }
        outputs.iter().map(|o| values[o.0 as usize]).collect()
    }
}
