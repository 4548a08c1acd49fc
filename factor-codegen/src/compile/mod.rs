//! Compiles a kernel's outputs (expressions of the symbolic DAG) into a
//! short straight-line [`Program`], in three stages:
//!
//! 1. `convert`: the live DAG becomes n-ary operations over shared
//!    operands (`ops`);
//! 2. `rewrite`: common pairs and factors are extracted;
//! 3. `select`: each operation becomes binary instructions, ordered by
//!    readiness.
//!
//! Several rewrite orders ([`Strategy`]) are tried and the shortest program
//! is kept.

mod convert;
mod ops;
mod pairs;
mod rewrite;
mod select;

use std::collections::HashMap;

use factor_symbolic::graph::{Expr, Graph};

use crate::ir::{Program, Value};
use ops::Compiler;
use select::Emitter;

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

/// The rewrites a strategy runs one after the other, each to a fixed point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    /// Pair extraction.
    Pairs,
    /// Distributive factoring of single-use product terms, then pairs.
    Factor,
    /// Distributive factoring of every product term, then pairs.
    FactorShared,
}

impl Strategy {
    fn phases(self) -> &'static [Phase] {
        match self {
            Strategy::Pairs => &[Phase::Pairs],
            Strategy::FactorFirst => &[Phase::Factor],
            Strategy::PairsThenFactor => &[Phase::Pairs, Phase::Factor],
            Strategy::FactorShared => &[Phase::FactorShared],
        }
    }
}

/// Compiles `outputs` (of `graph`) with every [`Strategy`] and keeps the
/// program with the fewest operations (the first on a tie). The outputs
/// are converted once, and a strategy whose phases begin with another's
/// continues from its result (`PairsThenFactor` from `Pairs`).
pub fn compile(graph: &Graph, outputs: &[Expr]) -> (Program, Vec<Value>) {
    let (converted, roots) = convert(graph, outputs);
    let mut rewritten: Vec<(&[Phase], Compiler)> = Vec::new();
    let mut programs = Vec::new();
    for strategy in STRATEGIES {
        let phases = strategy.phases();
        let (done, mut c) = rewritten
            .iter()
            .filter(|(before, _)| phases.starts_with(before))
            .max_by_key(|(before, _)| before.len())
            .map_or((0, converted.clone()), |(before, c)| {
                (before.len(), c.clone())
            });
        for phase in &phases[done..] {
            c.rewrite(*phase);
        }
        programs.push(emit(&c, &roots));
        rewritten.push((phases, c));
    }
    programs
        .into_iter()
        .min_by_key(|(program, values)| program.counts(values).total())
        .expect("at least one strategy")
}

/// Compiles `outputs` with one strategy.
pub fn compile_with(graph: &Graph, outputs: &[Expr], strategy: Strategy) -> (Program, Vec<Value>) {
    let (mut c, roots) = convert(graph, outputs);
    for phase in strategy.phases() {
        c.rewrite(*phase);
    }
    emit(&c, &roots)
}

/// Stage 1: `outputs` as ops, tracked from their roots (returned).
fn convert<'g>(graph: &'g Graph, outputs: &[Expr]) -> (Compiler<'g>, Vec<usize>) {
    let mut c = Compiler::new(graph);
    let roots: Vec<usize> = outputs.iter().map(|e| c.op_of(*e)).collect();
    c.track(&roots);
    (c, roots)
}

/// Stage 3: the program computing `roots`.
fn emit(c: &Compiler, roots: &[usize]) -> (Program, Vec<Value>) {
    let live = c.live();
    let mut emitter = Emitter {
        ops: &c.ops,
        uses: c.uses.clone(),
        program: Program::default(),
        values: HashMap::new(),
        ready: Vec::new(),
        urgent: c.urgent(&live),
    };
    let values = roots.iter().map(|r| emitter.emit(*r)).collect();
    (emitter.program, values)
}
