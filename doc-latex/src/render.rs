//! The tree back to LaTeX, in one canonical spelling, so a reader sees what
//! was understood: `\frac`, `\begin{bmatrix}` for every matrix,
//! `\left(…\right)` for grouping, `\left|…\right|` for norms, `(…)` only for
//! arguments, every script braced. Parsing the output gives the same tree.

use std::fmt;

use crate::ast::{
    Base, Case, DerivativeKind, Expr, Font, Function, Head, Matrix, MulOp, PostfixOp, Sign,
    Statement, Symbol,
};
use crate::names::{ACCENT_COMMANDS, FONT_COMMANDS, POSTFIX_OPERATORS, function_command, name_of};
pub use crate::names::{mulop_latex, relation_latex};

impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&expr(self))
    }
}

impl fmt::Display for Statement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&statement(self))
    }
}

/// A statement as canonical LaTeX.
pub fn statement(s: &Statement) -> String {
    let mut out = String::new();
    if s.implied {
        out.push_str("\\Rightarrow ");
    }
    if let Some(h) = &s.head {
        out.push_str(&side(h));
    }
    for (rel, rhs) in &s.steps {
        if !out.is_empty() && !out.ends_with(' ') {
            out.push(' ');
        }
        out.push_str(&relation_latex(*rel));
        out.push(' ');
        out.push_str(&side(rhs));
    }
    out
}

/// An expression as canonical LaTeX (a relation chain printed bare).
pub fn expr(e: &Expr) -> String {
    match e {
        Expr::Number(n) => n.clone(),
        Expr::Symbol(s) => symbol(s, &[]),
        Expr::Text(t) => format!("\\text{{{t}}}"),
        // Braced: a bare `\cdot` is read as an operator unless a closer follows.
        Expr::Placeholder => "{\\cdot}".into(),
        Expr::Ellipsis => "\\cdots".into(),
        Expr::Neg(x) => format!("-{}", operand(x)),
        Expr::Pos(x) => format!("+{}", operand(x)),
        Expr::Sum { first, rest } => {
            let mut out = match first.as_ref() {
                Expr::Sum { .. } | Expr::Relation { .. } => parens(first),
                other => expr(other),
            };
            for (sign, t) in rest {
                out.push_str(if *sign == Sign::Plus { " + " } else { " - " });
                out.push_str(&operand(t));
            }
            out
        }
        Expr::Product { first, rest } => {
            let last = rest.len();
            let mut out = factor(first, last == 0);
            for (i, (op, x)) in rest.iter().enumerate() {
                if *op != MulOp::Implicit {
                    out.push(' ');
                    out.push_str(&mulop_latex(*op));
                }
                out.push(' ');
                out.push_str(&factor(x, i + 1 == last));
            }
            out
        }
        Expr::Fraction { num, den } => format!("\\frac{{{}}}{{{}}}", expr(num), expr(den)),
        Expr::Derivative { kind, of, wrt } => {
            let d = if *kind == DerivativeKind::Partial {
                "\\partial"
            } else {
                "d"
            };
            format!("\\frac{{{d} {}}}{{{d} {}}}", operand(of), operand(wrt))
        }
        Expr::Differential(x) => format!("\\partial {}", operand(x)),
        Expr::Limit { under, body } => format!("\\lim_{{{}}} {}", expr(under), operand(body)),
        Expr::Sqrt { index, body } => match index {
            Some(i) => format!("\\sqrt[{}]{{{}}}", expr(i), expr(body)),
            None => format!("\\sqrt{{{}}}", expr(body)),
        },
        Expr::Norm { double, body } => {
            let bar = if *double { "\\|" } else { "|" };
            format!("\\left{bar} {} \\right{bar}", expr(body))
        }
        Expr::Skew(x) => format!("\\lfloor {} \\rfloor_{{\\times}}", expr(x)),
        Expr::Apply {
            head,
            args,
            scripts,
        } => {
            let args: Vec<String> = args.iter().map(expr).collect();
            let head = match head {
                Head::Function(f) => function(f),
                Head::Symbol(s) => symbol(s, &[]),
            };
            let call = match (args.as_slice(), head_is_bare(e)) {
                // `Ad_{T}` standing alone: braced so nothing after it reads
                // as its argument.
                ([], _) => format!("{{{head}}}"),
                // `\sin {\theta}`: applied to one factor, no parentheses.
                ([one], true) => format!("{head} {{{one}}}"),
                _ => format!("{head}({})", args.join(", ")),
            };
            match scripts {
                Some(chain) => call + &closing_scripts(chain),
                None => call,
            }
        }
        Expr::Power { base, exponent } => match base.as_ref() {
            Expr::Symbol(s) if s.sup.is_none() && exponent.reads_as_exponent() => {
                format!("{}^{{{}}}", symbol(s, &[]), script(exponent))
            }
            _ => format!("{}^{{{}}}", script_base(base), script(exponent)),
        },
        Expr::Postfix { .. } => {
            // Collect the chain of postfix operators down to its operand.
            let mut ops = Vec::new();
            let mut base = e;
            while let Expr::Postfix { base: b, op } = base {
                ops.push(*op);
                base = b;
            }
            ops.reverse();
            match base {
                Expr::Symbol(s) => symbol(s, &ops),
                _ => {
                    let markers: Vec<String> = ops.iter().map(|op| marker(*op)).collect();
                    format!("{}^{{{}}}", script_base(base), markers.join(" "))
                }
            }
        }
        // `[p]_x`, `[1]_+`: a symbol or number indexed as a whole was
        // printed in brackets (braces would make the index its own).
        Expr::Indexed { base, index } => match base.as_ref() {
            Expr::Symbol(_) | Expr::Number(_) => {
                format!("\\left[{}\\right]_{{{}}}", expr(base), expr(index))
            }
            _ => format!("{}_{{{}}}", script_base(base), expr(index)),
        },
        Expr::Shaped { base, rows, cols } => {
            format!("{}_{{{rows} \\times {cols}}}", script_base(base))
        }
        Expr::Primed { base, primes } => {
            format!("{}{}", script_base(base), "'".repeat(*primes as usize))
        }
        Expr::Tuple(items) => {
            let items: Vec<String> = items.iter().map(expr).collect();
            format!("\\left({}\\right)", items.join(", "))
        }
        Expr::Matrix(m) => matrix(m),
        Expr::At { body, at } => {
            format!("\\left. {} \\right|_{{{}}}", expr(body), expr(at))
        }
        Expr::Cases(cases) => {
            let rows: Vec<String> = cases.iter().map(case).collect();
            format!("\\begin{{cases}} {} \\end{{cases}}", rows.join(" \\\\ "))
        }
        Expr::Relation { first, rest } => {
            let mut out = side(first);
            for (rel, x) in rest {
                out.push(' ');
                out.push_str(&relation_latex(*rel));
                out.push(' ');
                out.push_str(&side(x));
            }
            out
        }
    }
}

fn parens(e: &Expr) -> String {
    format!("\\left({}\\right)", expr(e))
}

/// A side of a relation: anything but a nested relation.
fn side(e: &Expr) -> String {
    match e {
        Expr::Relation { .. } => parens(e),
        _ => expr(e),
    }
}

/// An operand of a sign, `\partial`, `\lim` or `d`: a product at most,
/// in parentheses when it composes with an operator (`-(a \boxminus b)`,
/// which `-a \boxminus b` would print ambiguously).
fn operand(e: &Expr) -> String {
    match e {
        Expr::Relation { .. } | Expr::Sum { .. } | Expr::Neg(_) | Expr::Pos(_) => parens(e),
        Expr::Product { rest, .. }
            if rest.iter().any(|(op, _)| {
                !matches!(
                    op,
                    MulOp::Implicit | MulOp::Cdot | MulOp::Times | MulOp::Star | MulOp::Slash
                )
            }) =>
        {
            parens(e)
        }
        _ => expr(e),
    }
}

/// A factor of a product; `\partial` and `\lim` take the rest of a product,
/// so they stay bare only as its last factor, and a bare `\delta` before
/// another factor is braced (else it reads as the increment `\delta x`).
fn factor(e: &Expr, last: bool) -> String {
    match e {
        Expr::Differential(_) | Expr::Limit { .. } if last => expr(e),
        Expr::Symbol(s) if !last && is_bare_delta(s) => format!("{{{}}}", expr(e)),
        Expr::Relation { .. }
        | Expr::Sum { .. }
        | Expr::Neg(_)
        | Expr::Pos(_)
        | Expr::Product { .. }
        | Expr::Differential(_)
        | Expr::Limit { .. } => parens(e),
        _ => expr(e),
    }
}

/// Whether `e` is a function applied without parentheses.
fn head_is_bare(e: &Expr) -> bool {
    matches!(
        e,
        Expr::Apply {
            head: Head::Function(Function { bare: true, .. }),
            ..
        }
    )
}

/// The scripts printed on an application's closing parenthesis, from
/// their chain over the placeholder ([`Expr::Apply`]'s `scripts`), in the
/// order the parser reads them back: the subscript, primes, then the
/// superscript (an exponent, then postfix markers).
fn closing_scripts(chain: &Expr) -> String {
    let mut markers = Vec::new();
    let mut node = chain;
    while let Expr::Postfix { base, op } = node {
        markers.push(marker(*op));
        node = base;
    }
    markers.reverse();
    let mut exponent = None;
    if let Expr::Power { base, exponent: x } = node {
        exponent = Some(script(x));
        node = base;
    }
    let mut primes = 0;
    if let Expr::Primed { base, primes: p } = node {
        primes = *p as usize;
        node = base;
    }
    let sub = match node {
        Expr::Indexed { base, index } => {
            node = base;
            Some(expr(index))
        }
        Expr::Shaped { base, rows, cols } => {
            node = base;
            Some(format!("{rows} \\times {cols}"))
        }
        Expr::Skew(base) => {
            node = base;
            Some("\\times".to_string())
        }
        _ => None,
    };
    let mut out = String::new();
    if let Some(sub) = sub {
        out.push_str(&format!("_{{{sub}}}"));
    }
    out.push_str(&"'".repeat(primes));
    let sup: Vec<String> = exponent.into_iter().chain(markers).collect();
    if !sup.is_empty() {
        out.push_str(&format!("^{{{}}}", sup.join(" ")));
    }
    let _ = node; // the placeholder: the parenthesis the scripts are on
    out
}

/// An expression that a script is attached to. A symbol's application is
/// bracketed: a script printed on its parenthesis would apply to the
/// parenthesised group (`R (R Q)^\top`), not to the whole (a function's
/// call keeps the scripts on the call, `\sin(x)^{2}`).
fn script_base(e: &Expr) -> String {
    match e {
        Expr::Apply {
            head: Head::Symbol(_),
            ..
        } => parens(e),
        Expr::Number(_)
        | Expr::Text(_)
        | Expr::Ellipsis
        | Expr::Apply { .. }
        | Expr::Norm { .. }
        | Expr::Matrix(_)
        | Expr::Cases(_)
        | Expr::Sqrt { .. }
        | Expr::At { .. }
        | Expr::Tuple(_) => expr(e),
        Expr::Symbol(_)
        | Expr::Placeholder
        | Expr::Skew(_)
        | Expr::Power { .. }
        | Expr::Postfix { .. }
        | Expr::Indexed { .. }
        | Expr::Shaped { .. }
        | Expr::Primed { .. } => format!("{{{}}}", expr(e)),
        Expr::Relation { .. }
        | Expr::Sum { .. }
        | Expr::Neg(_)
        | Expr::Pos(_)
        | Expr::Product { .. }
        | Expr::Differential(_)
        | Expr::Limit { .. }
        | Expr::Fraction { .. }
        | Expr::Derivative { .. } => parens(e),
    }
}

/// A superscript's content, braced again when it ends in something the
/// parser would strip as a postfix marker or prime.
fn script(e: &Expr) -> String {
    let s = expr(e);
    let ends_in_marker = ["'", "T", "*", "+", "\\top", "\\wedge", "\\vee", "\\prime"]
        .iter()
        .any(|m| s.ends_with(m))
        || POSTFIX_OPERATORS
            .iter()
            .any(|op| s.ends_with(&format!("\\{op}")));
    if ends_in_marker {
        format!("{{{s}}}")
    } else {
        s
    }
}

fn marker(op: PostfixOp) -> String {
    match op {
        PostfixOp::Transpose => "T".into(),
        PostfixOp::Hat => "\\wedge".into(),
        PostfixOp::Vee => "\\vee".into(),
        PostfixOp::Operator(c @ ("*" | "+")) => c.into(),
        PostfixOp::Operator(name) => format!("\\{name}"),
    }
}

/// A symbol, with postfix operators `ops` folded into its superscript.
fn symbol(s: &Symbol, ops: &[PostfixOp]) -> String {
    let mut out = String::new();
    if s.pre_sub.is_some() || s.pre_sup.is_some() {
        out.push_str("{}");
        if let Some(x) = &s.pre_sub {
            out.push_str(&format!("_{{{}}}", expr(x)));
        }
        // Not `script`: a pre-superscript is read as an expression, with no
        // postfix marker stripped, so braces around `\odot` would not parse.
        if let Some(x) = &s.pre_sup {
            out.push_str(&format!("^{{{}}}", expr(x)));
        }
    }
    if let Some(font) = s.delta {
        let delta = if s.capital_delta {
            "\\Delta"
        } else {
            "\\delta"
        };
        out.push_str(&fonted(font, delta));
        out.push(' ');
    }
    let mut core = match &s.base {
        Base::Letter(c) => c.to_string(),
        Base::Command(name) => format!("\\{name}"),
    };
    core = fonted(s.font, &core);
    if let Some(a) = s.accent {
        core = format!("\\{}{{{core}}}", name_of(ACCENT_COMMANDS, a));
    }
    out.push_str(&core);
    if let Some(x) = &s.sub {
        out.push_str(&format!("_{{{}}}", expr(x)));
    }
    // `Z'^{2}`: primes on the symbol before its superscript; those printed
    // inside the superscript (`p_{i}^{1 '}`) stay there.
    out.push_str(&"'".repeat(s.primes as usize));
    if s.sup.is_none() && ops.is_empty() && s.sup_primes == 0 {
        return out;
    }
    let mut sup: Vec<String> = Vec::new();
    if let Some(x) = &s.sup {
        sup.push(script(x));
    }
    if s.sup_primes > 0 {
        sup.push("'".repeat(s.sup_primes as usize));
    }
    sup.extend(ops.iter().map(|op| marker(*op)));
    out.push_str(&format!("^{{{}}}", sup.join(" ")));
    out
}

/// A `\delta` that a following symbol would turn into an increment.
fn is_bare_delta(s: &Symbol) -> bool {
    s.base == Base::Command("delta".into())
        && matches!(s.font, Font::Plain | Font::Bold)
        && s.delta.is_none()
        && s.accent.is_none()
        && s.primes == 0
        && s.sup_primes == 0
        && s.sub.is_none()
        && s.sup.is_none()
}

fn fonted(font: Font, core: &str) -> String {
    match font {
        Font::Plain => core.to_string(),
        Font::BoldCalligraphic => format!("\\boldsymbol{{\\mathcal{{{core}}}}}"),
        f => format!("\\{}{{{core}}}", name_of(FONT_COMMANDS, f)),
    }
}

fn function(f: &Function) -> String {
    let mut out = match function_command(&f.name) {
        Some(c) => format!("\\{c}"),
        None => format!("\\operatorname{{{}}}", f.name),
    };
    if let Some(s) = &f.sub {
        out.push_str(&format!("_{{{}}}", expr(s)));
    }
    if let Some(p) = &f.power {
        out.push_str(&format!("^{{{}}}", expr(p)));
    }
    out
}

fn matrix(m: &Matrix) -> String {
    let rows: Vec<String> = m
        .rows
        .iter()
        .map(|row| row.iter().map(expr).collect::<Vec<_>>().join(" & "))
        .collect();
    format!(
        "\\begin{{bmatrix}} {} \\end{{bmatrix}}",
        rows.join(" \\\\ ")
    )
}

fn case(c: &Case) -> String {
    match &c.condition {
        Some(cond) => format!("{} & {}", expr(&c.value), expr(cond)),
        None => expr(&c.value),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ast::Accent;

    #[test]
    fn symbols_are_written_with_every_decoration() {
        let s = Symbol {
            font: Font::Bold,
            accent: Some(Accent::Tilde),
            pre_sub: Some(Box::new(Expr::Symbol(Symbol::new(Base::Letter('C'))))),
            ..Symbol::new(Base::Letter('n'))
        };
        assert_eq!(
            expr(&Expr::Postfix {
                base: Box::new(Expr::Symbol(s)),
                op: PostfixOp::Transpose
            }),
            "{}_{C}\\tilde{\\boldsymbol{n}}^{T}"
        );
    }
}
