//! Exact symbolic derivatives and substitution on the DAG.
//!
//! Both rebuild through the smart constructors, so their results are
//! simplified as they are made. A `select` is differentiated arm by arm (the
//! condition is piecewise constant), so each branch keeps its own exact
//! derivative.

use std::collections::HashMap;

use crate::graph::{Expr, Node, node};

/// `∂e/∂wrt`, where `wrt` is an input. `memo` caches results for one `wrt`.
pub fn derivative(e: Expr, wrt: Expr, memo: &mut HashMap<Expr, Expr>) -> Expr {
    if let Some(&d) = memo.get(&e) {
        return d;
    }
    let zero = Expr::constant(0.0);
    let d = match node(e) {
        Node::Const(_) => zero,
        Node::Input(_) => Expr::constant(if e == wrt { 1.0 } else { 0.0 }),
        Node::Add { terms, .. } => terms.iter().fold(zero, |acc, (t, c)| {
            acc + derivative(*t, wrt, memo).scale(c.get())
        }),
        Node::Mul { factors, .. } => factors.iter().fold(zero, |acc, (b, k)| {
            let db = derivative(*b, wrt, memo);
            if db == zero {
                return acc;
            }
            // ∂(c Π bⱼ^kⱼ) = Σᵢ kᵢ · (e / bᵢ) · ∂bᵢ
            acc + (e / *b * db).scale(f64::from(*k))
        }),
        Node::Sqrt(x) => (derivative(x, wrt, memo) / e).scale(0.5),
        Node::Sin(x) => derivative(x, wrt, memo) * x.cos(),
        Node::Cos(x) => -(derivative(x, wrt, memo) * x.sin()),
        Node::Atan2(y, x) => {
            let (dy, dx) = (derivative(y, wrt, memo), derivative(x, wrt, memo));
            let r2 = x * x + y * y;
            (x * dy - y * dx) / r2
        }
        Node::Exp(x) => derivative(x, wrt, memo) * e,
        Node::Ln(x) => derivative(x, wrt, memo) / x,
        // √((1 − x)(1 + x)), not √(1 − x²): both factors are exact near |x| = 1.
        Node::Acos(x) => -(derivative(x, wrt, memo) / one_minus_square_root(x)),
        Node::Asin(x) => derivative(x, wrt, memo) / one_minus_square_root(x),
        Node::Atan(x) => {
            let one = Expr::constant(1.0);
            derivative(x, wrt, memo) / (one + x * x)
        }
        Node::Select {
            lhs,
            rhs,
            if_less,
            otherwise,
        } => Expr::select_lt(
            lhs,
            rhs,
            derivative(if_less, wrt, memo),
            derivative(otherwise, wrt, memo),
        ),
    };
    memo.insert(e, d);
    d
}

/// `√((1 − x)(1 + x))`, the derivative's denominator of `acos` and `asin`.
fn one_minus_square_root(x: Expr) -> Expr {
    let one = Expr::constant(1.0);
    ((one - x) * (one + x)).sqrt()
}

/// `e` with every key of `map` replaced by its value, rebuilt and simplified.
pub fn substitute(e: Expr, map: &HashMap<Expr, Expr>, memo: &mut HashMap<Expr, Expr>) -> Expr {
    if let Some(&r) = map.get(&e).or_else(|| memo.get(&e)) {
        return r;
    }
    let mut sub = |x: Expr| substitute(x, map, memo);
    let r = match node(e) {
        Node::Const(_) | Node::Input(_) => e,
        Node::Add { constant, terms } => terms
            .iter()
            .fold(Expr::constant(constant.get()), |acc, (t, c)| {
                acc + sub(*t).scale(c.get())
            }),
        Node::Mul {
            coefficient,
            factors,
        } => factors
            .iter()
            .fold(Expr::constant(coefficient.get()), |acc, (b, k)| {
                acc * sub(*b).powi(*k)
            }),
        Node::Sqrt(x) => sub(x).sqrt(),
        Node::Sin(x) => sub(x).sin(),
        Node::Cos(x) => sub(x).cos(),
        Node::Atan2(y, x) => {
            let y = sub(y);
            y.atan2(sub(x))
        }
        Node::Exp(x) => sub(x).exp(),
        Node::Ln(x) => sub(x).ln(),
        Node::Acos(x) => sub(x).acos(),
        Node::Asin(x) => sub(x).asin(),
        Node::Atan(x) => sub(x).atan(),
        Node::Select {
            lhs,
            rhs,
            if_less,
            otherwise,
        } => {
            let (l, r) = (sub(lhs), sub(rhs));
            let (a, b) = (sub(if_less), sub(otherwise));
            Expr::select_lt(l, r, a, b)
        }
    };
    memo.insert(e, r);
    r
}
