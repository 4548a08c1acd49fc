//! Human-readable rendering of expressions, for debugging and reports.

use std::fmt::Write;

use crate::graph::{Expr, Graph, Node};

/// Renders `e` as an infix formula; inputs print as `x{i}` (or the name
/// `input_name` gives them).
pub fn render(graph: &Graph, e: Expr, input_name: &dyn Fn(u32) -> String) -> String {
    let mut out = String::new();
    write_expr(graph, e, input_name, &mut out);
    out
}

fn write_expr(graph: &Graph, e: Expr, name: &dyn Fn(u32) -> String, out: &mut String) {
    match graph.node(e) {
        Node::Const(c) => {
            let _ = write!(out, "{}", c.get());
        }
        Node::Input(i) => out.push_str(&name(*i)),
        Node::Add { constant, terms } => {
            out.push('(');
            for (k, (t, c)) in terms.iter().enumerate() {
                let c = c.get();
                if k > 0 || c < 0.0 {
                    out.push_str(if c < 0.0 { " - " } else { " + " });
                }
                if c.abs() != 1.0 {
                    let _ = write!(out, "{}*", c.abs());
                }
                write_expr(graph, *t, name, out);
            }
            if constant.get() != 0.0 {
                let _ = write!(out, " + {}", constant.get());
            }
            out.push(')');
        }
        Node::Mul {
            coefficient,
            factors,
        } => {
            if coefficient.get() != 1.0 {
                let _ = write!(out, "{}*", coefficient.get());
            }
            for (k, (b, p)) in factors.iter().enumerate() {
                if k > 0 {
                    out.push('*');
                }
                write_expr(graph, *b, name, out);
                if *p != 1 {
                    let _ = write!(out, "^{p}");
                }
            }
        }
        Node::Sqrt(x) => call(graph, "sqrt", &[*x], name, out),
        Node::Sin(x) => call(graph, "sin", &[*x], name, out),
        Node::Cos(x) => call(graph, "cos", &[*x], name, out),
        Node::Atan2(y, x) => call(graph, "atan2", &[*y, *x], name, out),
        Node::Exp(x) => call(graph, "exp", &[*x], name, out),
        Node::Ln(x) => call(graph, "ln", &[*x], name, out),
        Node::Acos(x) => call(graph, "acos", &[*x], name, out),
        Node::Asin(x) => call(graph, "asin", &[*x], name, out),
        Node::Atan(x) => call(graph, "atan", &[*x], name, out),
        Node::Select {
            lhs,
            rhs,
            if_less,
            otherwise,
        } => call(
            graph,
            "select_lt",
            &[*lhs, *rhs, *if_less, *otherwise],
            name,
            out,
        ),
    }
}

fn call(graph: &Graph, f: &str, args: &[Expr], name: &dyn Fn(u32) -> String, out: &mut String) {
    out.push_str(f);
    out.push('(');
    for (k, a) in args.iter().enumerate() {
        if k > 0 {
            out.push_str(", ");
        }
        write_expr(graph, *a, name, out);
    }
    out.push(')');
}
