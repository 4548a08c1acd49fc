//! Walking the `doc-latex` syntax tree by paths: the children of each node
//! in one fixed order, read or changed in place (the erratum search edits
//! a printed formula this way).

use doc_latex::ast::{Expr, Sign};

/// A node's place: the child indices from the root.
pub type Path = Vec<usize>;

/// The children of `e` that formulas are edited in, in order. Exponents,
/// a root's index, derivatives and symbols' scripts are not descended.
pub fn children(e: &Expr) -> Vec<&Expr> {
    match e {
        Expr::Number(_)
        | Expr::Symbol(_)
        | Expr::Text(_)
        | Expr::Placeholder
        | Expr::Ellipsis
        | Expr::Derivative { .. } => Vec::new(),
        Expr::Neg(x)
        | Expr::Pos(x)
        | Expr::Differential(x)
        | Expr::Skew(x)
        | Expr::Sqrt { body: x, .. }
        | Expr::Norm { body: x, .. }
        | Expr::Power { base: x, .. }
        | Expr::Postfix { base: x, .. }
        | Expr::Indexed { base: x, .. }
        | Expr::Shaped { base: x, .. }
        | Expr::Primed { base: x, .. }
        | Expr::At { body: x, .. } => vec![x],
        Expr::Sum { first, rest } => std::iter::once(first.as_ref())
            .chain(rest.iter().map(|(_, t)| t))
            .collect(),
        Expr::Product { first, rest } => std::iter::once(first.as_ref())
            .chain(rest.iter().map(|(_, t)| t))
            .collect(),
        Expr::Relation { first, rest } => std::iter::once(first.as_ref())
            .chain(rest.iter().map(|(_, t)| t))
            .collect(),
        Expr::Fraction { num, den } => vec![num, den],
        Expr::Limit { under, body } => vec![under, body],
        Expr::Apply { args, .. } | Expr::Tuple(args) => args.iter().collect(),
        Expr::Matrix(m) => m.rows.iter().flatten().collect(),
        Expr::Cases(cases) => cases.iter().map(|c| &c.value).collect(),
    }
}

/// Child `i` of `e` (in the order of [`children`]), to change.
pub fn child_mut(e: &mut Expr, i: usize) -> Option<&mut Expr> {
    match e {
        Expr::Number(_)
        | Expr::Symbol(_)
        | Expr::Text(_)
        | Expr::Placeholder
        | Expr::Ellipsis
        | Expr::Derivative { .. } => None,
        Expr::Neg(x)
        | Expr::Pos(x)
        | Expr::Differential(x)
        | Expr::Skew(x)
        | Expr::Sqrt { body: x, .. }
        | Expr::Norm { body: x, .. }
        | Expr::Power { base: x, .. }
        | Expr::Postfix { base: x, .. }
        | Expr::Indexed { base: x, .. }
        | Expr::Shaped { base: x, .. }
        | Expr::Primed { base: x, .. }
        | Expr::At { body: x, .. } => (i == 0).then_some(x.as_mut()),
        Expr::Sum { first, rest } => match i {
            0 => Some(first.as_mut()),
            _ => rest.get_mut(i - 1).map(|(_, t)| t),
        },
        Expr::Product { first, rest } => match i {
            0 => Some(first.as_mut()),
            _ => rest.get_mut(i - 1).map(|(_, t)| t),
        },
        Expr::Relation { first, rest } => match i {
            0 => Some(first.as_mut()),
            _ => rest.get_mut(i - 1).map(|(_, t)| t),
        },
        Expr::Fraction { num, den } => match i {
            0 => Some(num.as_mut()),
            1 => Some(den.as_mut()),
            _ => None,
        },
        Expr::Limit { under, body } => match i {
            0 => Some(under.as_mut()),
            1 => Some(body.as_mut()),
            _ => None,
        },
        Expr::Apply { args, .. } | Expr::Tuple(args) => args.get_mut(i),
        Expr::Matrix(m) => m.rows.iter_mut().flatten().nth(i),
        Expr::Cases(cases) => cases.get_mut(i).map(|c| &mut c.value),
    }
}

/// The node at `path`.
pub fn at<'e>(e: &'e Expr, path: &[usize]) -> Option<&'e Expr> {
    path.iter()
        .try_fold(e, |node, i| children(node).get(*i).copied())
}

/// The node at `path`, to change.
pub fn at_mut<'e>(e: &'e mut Expr, path: &[usize]) -> Option<&'e mut Expr> {
    path.iter().try_fold(e, |node, i| child_mut(node, *i))
}

/// Every node with its path, parents before children.
pub fn nodes(e: &Expr) -> Vec<(Path, &Expr)> {
    let mut out = Vec::new();
    let mut stack = vec![(Vec::new(), e)];
    while let Some((path, node)) = stack.pop() {
        let kids = children(node);
        for (i, k) in kids.into_iter().enumerate().rev() {
            let mut p = path.clone();
            p.push(i);
            stack.push((p, k));
        }
        out.push((path, node));
    }
    out
}

/// Every derivative node (not looking inside them), in order.
pub fn derivatives(e: &Expr) -> Vec<&Expr> {
    let mut out = Vec::new();
    let mut stack = vec![e];
    while let Some(node) = stack.pop() {
        if matches!(node, Expr::Derivative { .. }) {
            out.push(node);
            continue;
        }
        stack.extend(children(node).into_iter().rev());
    }
    out
}

/// Most terms gathered from the formula's line for the erratum search's
/// additions (`super::edits::additions`).
pub const MAX_NEARBY_TERMS: usize = 24;

/// The terms printed in the claim's display (the other sides of its chain,
/// its other lines, a value's left side, the sums inside its right side),
/// each with its sign, except the right side's own: what a term missing
/// from the right side may be.
pub fn nearby_terms(others: &[&Expr], rhs: &Expr) -> Vec<Expr> {
    let own: Vec<String> = sum_terms(rhs).iter().map(|t| t.to_string()).collect();
    let mut out: Vec<Expr> = Vec::new();
    for e in others.iter().copied().chain(std::iter::once(rhs)) {
        for (_, node) in nodes(e) {
            for t in sum_terms(node) {
                let key = t.to_string();
                if out.len() < MAX_NEARBY_TERMS
                    && !own.contains(&key)
                    && !out.iter().any(|o| o.to_string() == key)
                {
                    out.push(t);
                }
            }
        }
    }
    out
}

/// The terms of a sum with their signs (`Neg` for a subtracted one); none
/// for another node.
fn sum_terms(e: &Expr) -> Vec<Expr> {
    if !matches!(e, Expr::Sum { .. }) {
        return Vec::new();
    }
    e.terms()
        .into_iter()
        .map(|(sign, t)| match sign {
            Sign::Minus => Expr::Neg(Box::new(t.clone())),
            Sign::Plus => t.clone(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_read_and_change_the_same_nodes() {
        let mut e = doc_latex::parse_expr("a + \\frac{b}{c} d").unwrap();
        let all = nodes(&e);
        for (path, node) in &all {
            assert_eq!(at(&e, path), Some(*node));
        }
        let path = all
            .iter()
            .find(|(_, n)| n.to_string() == "c")
            .map(|(p, _)| p.clone())
            .unwrap();
        *at_mut(&mut e, &path).unwrap() = Expr::Number("2".into());
        assert_eq!(e.to_string(), "a + \\frac{b}{2} d");
        let d = doc_latex::parse_expr(
            "\\frac{\\partial y}{\\partial x} \\frac{\\partial x}{\\partial t}",
        )
        .unwrap();
        assert_eq!(derivatives(&d).len(), 2);
    }
}
