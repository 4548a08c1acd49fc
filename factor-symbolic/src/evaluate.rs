//! Numeric evaluation of a DAG: the reference the simplifier and the emitted
//! code are tested against.

use crate::graph::{Expr, Graph, Node};

/// Values of every node up to the largest of `outputs`, given the inputs.
pub fn evaluate(graph: &Graph, inputs: &[f64], outputs: &[Expr]) -> Vec<f64> {
    let last = outputs.iter().map(|e| e.index()).max().map_or(0, |m| m + 1);
    // Only what the outputs depend on: a traced graph also holds nodes of
    // inputs the outputs no longer use (the tangent `δ` after substitution).
    let mut needed = vec![false; last];
    let mut stack: Vec<Expr> = outputs.to_vec();
    while let Some(e) = stack.pop() {
        if !std::mem::replace(&mut needed[e.index()], true) {
            stack.extend(graph.node(e).children());
        }
    }
    let mut values = vec![0.0; last];
    for i in (0..last).filter(|i| needed[*i]) {
        values[i] = match graph.node(Expr(i as u32)) {
            Node::Const(c) => c.get(),
            Node::Input(k) => inputs[*k as usize],
            Node::Add { constant, terms } => terms.iter().fold(constant.get(), |acc, (t, c)| {
                acc + c.get() * values[t.index()]
            }),
            Node::Mul {
                coefficient,
                factors,
            } => factors.iter().fold(coefficient.get(), |acc, (b, k)| {
                acc * values[b.index()].powi(*k)
            }),
            Node::Sqrt(x) => values[x.index()].sqrt(),
            Node::Sin(x) => values[x.index()].sin(),
            Node::Cos(x) => values[x.index()].cos(),
            Node::Atan2(y, x) => values[y.index()].atan2(values[x.index()]),
            Node::Exp(x) => values[x.index()].exp(),
            Node::Ln(x) => values[x.index()].ln(),
            Node::Acos(x) => values[x.index()].acos(),
            Node::Asin(x) => values[x.index()].asin(),
            Node::Atan(x) => values[x.index()].atan(),
            Node::Select {
                lhs,
                rhs,
                if_less,
                otherwise,
            } => {
                if values[lhs.index()] < values[rhs.index()] {
                    values[if_less.index()]
                } else {
                    values[otherwise.index()]
                }
            }
        };
    }
    outputs.iter().map(|e| values[e.index()]).collect()
}
