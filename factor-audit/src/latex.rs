//! The correct expression of an audited Jacobian, from the symbolic engine,
//! rendered as LaTeX in the names of the map's inputs and parameters.

use std::collections::HashMap;
use std::fmt::Write;

use crate::derivation::{Claim, Derivation};
use factor_symbolic::calculus::{derivative, substitute};
use factor_symbolic::{Expr, Graph, Node, Tracer};

/// `∂map/∂x` (or, for a value claim, the map itself) as a LaTeX `bmatrix`,
/// simplified by the symbolic engine. Inputs whose point is zero (a tangent
/// at the identity) are set to zero in a Jacobian, so its entries are in the
/// parameters only.
pub fn corrected_latex<D: Derivation>(d: &D) -> String {
    let tracer = Tracer::new();
    let point = d.point();
    let inputs: Vec<Expr> = (0..point.len() as u32).map(Expr::input).collect();
    let parameters: Vec<Expr> = (0..d.parameters().len() as u32)
        .map(|i| Expr::input(point.len() as u32 + i))
        .collect();
    let outputs = d.map(&inputs, &parameters);
    let at_zero: HashMap<Expr, Expr> = inputs
        .iter()
        .zip(&point)
        .filter(|(_, v)| **v == 0.0)
        .map(|(x, _)| (*x, Expr::constant(0.0)))
        .collect();
    let mut substituted = HashMap::new();
    let entries: Vec<Vec<Expr>> = match d.claim() {
        Claim::Value => outputs.iter().map(|y| vec![*y]).collect(),
        Claim::Jacobian => outputs
            .iter()
            .map(|y| {
                inputs
                    .iter()
                    .map(|x| {
                        substitute(
                            derivative(*y, *x, &mut HashMap::new()),
                            &at_zero,
                            &mut substituted,
                        )
                    })
                    .collect()
            })
            .collect(),
    };
    let graph = tracer.finish();
    let mut names = d.input_names();
    names.extend(d.parameters().into_iter().map(|(n, _)| n));
    let rows: Vec<String> = entries
        .iter()
        .map(|row| {
            row.iter()
                .map(|e| latex(&graph, *e, &names))
                .collect::<Vec<_>>()
                .join(" & ")
        })
        .collect();
    let typeset = format!(
        "\\begin{{bmatrix}} {} \\end{{bmatrix}}",
        rows.join(" \\\\ ")
    );
    if typeset.len() <= MAX_TYPESET_CHARS {
        typeset
    } else {
        format!(
            "\\text{{the expanded expression has more than {MAX_TYPESET_CHARS} characters and is \
             not typeset; it is the product of the corrected links of its chain rule}}"
        )
    }
}

/// Longest correction typeset in full: a fully expanded chain rule (document
/// 000 (13) expands to half a megabyte) says nothing a reader can use.
/// Rendering stops soon after it, so an expression whose tree is
/// exponentially larger than its graph costs no more.
pub const MAX_TYPESET_CHARS: usize = 16_000;

/// `e` as LaTeX; input `i` is `names[i]`. Past [`MAX_TYPESET_CHARS`] the
/// text is cut short (the caller sees it is too long).
pub fn latex(graph: &Graph, e: Expr, names: &[String]) -> String {
    let mut out = String::new();
    write_latex(graph, e, names, &mut out);
    out
}

fn number(c: f64) -> String {
    if c.fract() == 0.0 && c.abs() < 1e15 {
        format!("{}", c as i64)
    } else {
        format!("{c}")
    }
}

fn is_sum(graph: &Graph, e: Expr) -> bool {
    matches!(graph.node(e), Node::Add { .. })
}

fn write_factor(graph: &Graph, e: Expr, names: &[String], out: &mut String) {
    if is_sum(graph, e) {
        out.push_str("\\left(");
        write_latex(graph, e, names, out);
        out.push_str("\\right)");
    } else {
        write_latex(graph, e, names, out);
    }
}

fn write_power(graph: &Graph, base: Expr, k: i32, names: &[String], out: &mut String) {
    let atom = matches!(graph.node(base), Node::Input(_) | Node::Const(_));
    if k != 1 && !atom {
        out.push_str("\\left(");
        write_latex(graph, base, names, out);
        out.push_str("\\right)");
    } else {
        write_factor(graph, base, names, out);
    }
    if k != 1 {
        let _ = write!(out, "^{{{k}}}");
    }
}

/// The LaTeX operator of a one-argument function node.
fn function_name(node: &Node) -> &'static str {
    match node {
        Node::Sin(_) => "\\sin",
        Node::Cos(_) => "\\cos",
        Node::Exp(_) => "\\exp",
        Node::Ln(_) => "\\ln",
        Node::Acos(_) => "\\arccos",
        Node::Asin(_) => "\\arcsin",
        Node::Atan(_) => "\\arctan",
        _ => unreachable!("not a one-argument function"),
    }
}

fn write_latex(graph: &Graph, e: Expr, names: &[String], out: &mut String) {
    if out.len() > MAX_TYPESET_CHARS {
        return;
    }
    match graph.node(e) {
        Node::Const(c) => out.push_str(&number(c.get())),
        Node::Input(i) => out.push_str(names.get(*i as usize).map_or("?", String::as_str)),
        Node::Add { constant, terms } => {
            for (k, (t, c)) in terms.iter().enumerate() {
                let c = c.get();
                if k > 0 || c < 0.0 {
                    out.push_str(if c < 0.0 { " - " } else { " + " });
                }
                if c.abs() != 1.0 {
                    let _ = write!(out, "{} ", number(c.abs()));
                }
                write_factor(graph, *t, names, out);
            }
            let k = constant.get();
            if k != 0.0 {
                let _ = write!(
                    out,
                    " {} {}",
                    if k < 0.0 { "-" } else { "+" },
                    number(k.abs())
                );
            }
        }
        Node::Mul {
            coefficient,
            factors,
        } => {
            let c = coefficient.get();
            if c < 0.0 {
                out.push('-');
            }
            let numerator: Vec<(Expr, i32)> =
                factors.iter().filter(|(_, k)| *k > 0).copied().collect();
            let denominator: Vec<(Expr, i32)> = factors
                .iter()
                .filter(|(_, k)| *k < 0)
                .map(|(b, k)| (*b, -k))
                .collect();
            let mut top = String::new();
            if c.abs() != 1.0 || numerator.is_empty() {
                top.push_str(&number(c.abs()));
                if !numerator.is_empty() {
                    top.push_str(" \\, ");
                }
            }
            for (i, (b, k)) in numerator.iter().enumerate() {
                if i > 0 {
                    top.push_str(" \\, ");
                }
                write_power(graph, *b, *k, names, &mut top);
            }
            if denominator.is_empty() {
                out.push_str(&top);
            } else {
                let mut bottom = String::new();
                for (i, (b, k)) in denominator.iter().enumerate() {
                    if i > 0 {
                        bottom.push_str(" \\, ");
                    }
                    write_power(graph, *b, *k, names, &mut bottom);
                }
                let _ = write!(out, "\\frac{{{top}}}{{{bottom}}}");
            }
        }
        Node::Sqrt(x) => {
            out.push_str("\\sqrt{");
            write_latex(graph, *x, names, out);
            out.push('}');
        }
        Node::Sin(x)
        | Node::Cos(x)
        | Node::Exp(x)
        | Node::Ln(x)
        | Node::Acos(x)
        | Node::Asin(x)
        | Node::Atan(x) => {
            out.push_str(function_name(graph.node(e)));
            out.push_str("\\left(");
            write_latex(graph, *x, names, out);
            out.push_str("\\right)");
        }
        Node::Atan2(y, x) => {
            out.push_str("\\operatorname{atan2}\\left(");
            write_latex(graph, *y, names, out);
            out.push_str(", ");
            write_latex(graph, *x, names, out);
            out.push_str("\\right)");
        }
        Node::Select {
            lhs,
            rhs,
            if_less,
            otherwise,
        } => {
            out.push_str("\\begin{cases} ");
            write_latex(graph, *if_less, names, out);
            out.push_str(" & ");
            write_latex(graph, *lhs, names, out);
            out.push_str(" < ");
            write_latex(graph, *rhs, names, out);
            out.push_str(" \\\\ ");
            write_latex(graph, *otherwise, names, out);
            out.push_str(" & \\text{otherwise} \\end{cases}");
        }
    }
}
