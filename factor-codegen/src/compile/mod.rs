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
    let mut c = Compiler::new(graph);
    let roots: Vec<usize> = outputs.iter().map(|e| c.op_of(*e)).collect();
    c.track(&roots);
    let mut factoring = matches!(strategy, Strategy::FactorFirst | Strategy::FactorShared);
    let shared = strategy == Strategy::FactorShared;
    loop {
        let changed =
            (factoring && c.factor_sum(shared)) || c.extract_product_pair() || c.extract_sum_pair();
        if !changed {
            if strategy == Strategy::PairsThenFactor && !factoring {
                factoring = true;
                continue;
            }
            break;
        }
    }
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
