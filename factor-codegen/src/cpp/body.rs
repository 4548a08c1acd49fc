//! A C++ function body from a lowered program and its
//! [`Schedule`]: what [`crate::emit`]'s body is in Rust, statement for
//! statement in the same order. One `const T vN = …;` per instruction,
//! inputs read where they are used (`pose[3]`), literals `T(2.5)` with
//! round-trip precision; the unconditional outputs stored after the
//! unconditional statements; a group shared by several optional outputs
//! inside `if (a != nullptr || b != nullptr) { … }`, its values used later
//! declared before it; each optional output's own statements and stores
//! inside `if (a != nullptr) { … }`.
//!
//! Math functions are called unqualified after `using std::sqrt;` (and
//! whichever others the body calls), so that `T = float`, `double` or a
//! user's number type found by argument-dependent lookup (Ceres' `Jet`)
//! all work; `select_lt` is `lhs < rhs ? a : b`.

use std::collections::{BTreeSet, HashMap};
use std::fmt::Write;

use crate::ir::{Instr, Value};
use crate::lower::LoweredKernel;
use crate::schedule::{Group, Schedule};

/// `T(c)` with `c` printed so that it parses back to the same `f64`
/// (`T(-0.5)`, `std::numeric_limits<T>::infinity()`).
pub fn literal(c: f64) -> String {
    if c.is_nan() {
        "std::numeric_limits<T>::quiet_NaN()".to_owned()
    } else if c.is_infinite() {
        let sign = if c < 0.0 { "-" } else { "" };
        format!("{sign}std::numeric_limits<T>::infinity()")
    } else {
        format!("T({c:?})")
    }
}

/// What a body reads and writes.
pub struct Signature<'a> {
    /// How input `i` is read (`pose[3]`).
    pub inputs: &'a [String],
    /// Where each unconditional output (the program's `residual` values)
    /// is stored (`residual[0]`).
    pub always: &'a [String],
    /// The optional outputs (the program's `blocks`): pointer arguments,
    /// `nullptr` when not wanted.
    pub optional: &'a [String],
}

/// The body's builder: names values as they are defined.
struct Body<'a> {
    lowered: &'a LoweredKernel,
    inputs: &'a [String],
    names: HashMap<Value, String>,
    functions: BTreeSet<&'static str>,
    out: String,
}

impl Body<'_> {
    /// An operand: a name, an input or a literal.
    fn operand(&self, v: Value) -> String {
        match self.lowered.instrs[v.0 as usize] {
            Instr::Input(i) => self.inputs[i as usize].clone(),
            Instr::Const(c) => literal(c.get()),
            _ => self.names[&v].clone(),
        }
    }

    /// `f(a)`, a call of a one-argument function of `<cmath>`.
    fn call(&mut self, f: &'static str, a: Value) -> String {
        self.functions.insert(f);
        format!("{f}({})", self.operand(a))
    }

    /// The expression instruction `v` computes.
    fn expression(&mut self, v: Value) -> String {
        let o = |body: &Self, v: Value| body.operand(v);
        match self.lowered.instrs[v.0 as usize] {
            Instr::Add(a, b) => format!("{} + {}", o(self, a), o(self, b)),
            Instr::Sub(a, b) => format!("{} - {}", o(self, a), o(self, b)),
            Instr::Mul(a, b) => format!("{} * {}", o(self, a), o(self, b)),
            Instr::Div(a, b) => format!("{} / {}", o(self, a), o(self, b)),
            Instr::Neg(a) => format!("-{}", o(self, a)),
            Instr::Sqrt(a) => self.call("sqrt", a),
            Instr::Sin(a) => self.call("sin", a),
            Instr::Cos(a) => self.call("cos", a),
            Instr::Exp(a) => self.call("exp", a),
            Instr::Ln(a) => self.call("log", a),
            Instr::Acos(a) => self.call("acos", a),
            Instr::Asin(a) => self.call("asin", a),
            Instr::Atan(a) => self.call("atan", a),
            Instr::Atan2(y, x) => {
                self.functions.insert("atan2");
                format!("atan2({}, {})", o(self, y), o(self, x))
            }
            Instr::Select {
                lhs,
                rhs,
                if_less,
                otherwise,
            } => format!(
                "{} < {} ? {} : {}",
                o(self, lhs),
                o(self, rhs),
                o(self, if_less),
                o(self, otherwise)
            ),
            Instr::Input(_) | Instr::Const(_) => unreachable!("not scheduled as statements"),
        }
    }

    /// The next free name, bound to `v`.
    fn name(&mut self, v: Value) -> String {
        let name = format!("v{}", self.names.len());
        self.names.insert(v, name.clone());
        name
    }

    /// `const T vN = …;` for every statement of `group` at `indent`; the
    /// values in `declared` (named already) are assigned instead.
    fn statements(&mut self, group: &Group, indent: &str, declared: &[Value]) {
        for v in &group.instrs {
            let expr = self.expression(*v);
            if declared.contains(v) {
                let name = self.names[v].clone();
                let _ = writeln!(self.out, "{indent}{name} = {expr};");
            } else {
                let name = self.name(*v);
                let _ = writeln!(self.out, "{indent}const T {name} = {expr};");
            }
        }
    }
}

/// The statements of `lowered` in the order of `schedule`, reading and
/// writing as `signature` says, indented by two spaces; the `using`
/// declarations of the math functions it calls come first.
pub fn body(lowered: &LoweredKernel, schedule: &Schedule, signature: &Signature) -> String {
    let mut body = Body {
        lowered,
        inputs: signature.inputs,
        names: HashMap::new(),
        functions: BTreeSet::new(),
        out: String::new(),
    };
    body.statements(&schedule.always, "  ", &[]);
    for (target, v) in signature.always.iter().zip(&lowered.residual) {
        let value = body.operand(*v);
        let _ = writeln!(body.out, "  {target} = {value};");
    }
    for group in &schedule.shared {
        for v in &group.exports {
            let name = body.name(*v);
            let _ = writeln!(body.out, "  T {name} = T(0);");
        }
        let requested: Vec<String> = group
            .blocks
            .iter()
            .map(|k| format!("{} != nullptr", signature.optional[*k]))
            .collect();
        let _ = writeln!(body.out, "  if ({}) {{", requested.join(" || "));
        body.statements(group, "    ", &group.exports);
        body.out.push_str("  }\n");
    }
    for ((group, values), d) in schedule
        .single
        .iter()
        .zip(&lowered.blocks)
        .zip(signature.optional)
    {
        let _ = writeln!(body.out, "  if ({d} != nullptr) {{");
        body.statements(group, "    ", &[]);
        for (i, v) in values.iter().enumerate() {
            let value = body.operand(*v);
            let _ = writeln!(body.out, "    {d}[{i}] = {value};");
        }
        body.out.push_str("  }\n");
    }
    let mut out = String::new();
    for f in &body.functions {
        let _ = writeln!(out, "  using std::{f};");
    }
    out.push_str(&body.out);
    out
}
