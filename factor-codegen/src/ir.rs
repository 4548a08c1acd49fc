//! Straight-line binary instructions: what the canonical DAG is compiled to
//! ([`crate::compile`]), what the emitter prints, and what
//! operation counts are taken on. Instructions are interned, so an
//! instruction two users share is computed once.

use std::collections::HashMap;

use factor_symbolic::graph::Real;

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
    /// `eᵃ`.
    Exp(Value),
    /// `ln a`.
    Ln(Value),
    /// `acos a`.
    Acos(Value),
    /// `asin a`.
    Asin(Value),
    /// `atan a`.
    Atan(Value),
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
    /// Estimated cycles from the operands' availability to the result's, on
    /// a recent x86-64 core (scalar `f64`: add and multiply 3, divide 13,
    /// square root 20, a sign flip 1, a libm call (`sin`, `cos`, `atan2`,
    /// `exp`, `ln`, `acos`, `asin`, `atan`) 60; inputs and literals are there
    /// from the start). Only the emitter's ordering uses it.
    pub fn latency(&self) -> u32 {
        match self {
            Instr::Input(_) | Instr::Const(_) => 0,
            Instr::Neg(_) | Instr::Select { .. } => 1,
            Instr::Add(..) | Instr::Sub(..) | Instr::Mul(..) => 3,
            Instr::Div(..) => 13,
            Instr::Sqrt(_) => 20,
            Instr::Sin(_)
            | Instr::Cos(_)
            | Instr::Atan2(..)
            | Instr::Exp(_)
            | Instr::Ln(_)
            | Instr::Acos(_)
            | Instr::Asin(_)
            | Instr::Atan(_) => 60,
        }
    }

    /// Operands, in order.
    pub fn operands(&self) -> Vec<Value> {
        match *self {
            Instr::Input(_) | Instr::Const(_) => Vec::new(),
            Instr::Neg(a)
            | Instr::Sqrt(a)
            | Instr::Sin(a)
            | Instr::Cos(a)
            | Instr::Exp(a)
            | Instr::Ln(a)
            | Instr::Acos(a)
            | Instr::Asin(a)
            | Instr::Atan(a) => vec![a],
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
    /// Calls of the math library's functions: `sin`, `cos`, `atan2`, `exp`,
    /// `ln`, `acos`, `asin`, `atan`.
    pub func: usize,
    /// Conditional selections.
    pub branch: usize,
}

impl OpCounts {
    /// The sum of all kinds.
    pub fn total(&self) -> usize {
        self.add + self.mul + self.div + self.neg + self.sqrt + self.func + self.branch
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
            Instr::Sin(_)
            | Instr::Cos(_)
            | Instr::Atan2(..)
            | Instr::Exp(_)
            | Instr::Ln(_)
            | Instr::Acos(_)
            | Instr::Asin(_)
            | Instr::Atan(_) => self.func += 1,
            Instr::Select { .. } => self.branch += 1,
        }
    }
}

/// A straight-line program, built by [`crate::compile::compile`].
#[derive(Default)]
pub struct Program {
    /// Instructions; operands always precede their users.
    pub instrs: Vec<Instr>,
    interned: HashMap<Instr, Value>,
}

impl Program {
    /// A program of `instrs` (no two equal, operands before their users, as
    /// a compiled program's), to extend with [`Program::push`].
    pub fn from_instrs(instrs: Vec<Instr>) -> Program {
        let interned = instrs
            .iter()
            .enumerate()
            .map(|(i, instr)| (*instr, Value(i as u32)))
            .collect();
        Program { instrs, interned }
    }

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

    /// Operation counts of the instructions `outputs` depend on.
    pub fn counts(&self, outputs: &[Value]) -> OpCounts {
        counts(&self.instrs, outputs)
    }
}

/// Which of `instrs` the `outputs` depend on.
pub fn live(instrs: &[Instr], outputs: &[Value]) -> Vec<bool> {
    let mut live = vec![false; instrs.len()];
    let mut stack: Vec<Value> = outputs.to_vec();
    while let Some(v) = stack.pop() {
        if !std::mem::replace(&mut live[v.0 as usize], true) {
            stack.extend(instrs[v.0 as usize].operands());
        }
    }
    live
}

/// Operation counts of the instructions of `instrs` that `outputs` depend on.
pub fn counts(instrs: &[Instr], outputs: &[Value]) -> OpCounts {
    let mut counts = OpCounts::default();
    for (instr, _) in instrs.iter().zip(live(instrs, outputs)).filter(|(_, l)| *l) {
        counts.count(instr);
    }
    counts
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
                Instr::Exp(a) => v(a).exp(),
                Instr::Ln(a) => v(a).ln(),
                Instr::Acos(a) => v(a).acos(),
                Instr::Asin(a) => v(a).asin(),
                Instr::Atan(a) => v(a).atan(),
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
