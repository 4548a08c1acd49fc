//! A lowered formula written back as LaTeX with every grouping explicit:
//! what the audit evaluates, shown so that a reader sees how each operator
//! was scoped (`R \left(\left(R Q\right)^{\top}\right)` against
//! `\left(R \left(R Q\right)\right)^{\top}`), which function a name was read
//! as and what a symbol before parentheses became (a call, a product, or
//! the symbol written with its variables). Unlike the canonical rendering
//! of the printed tree (`doc_latex::render`), nothing here echoes the
//! input: every compound operand is bracketed, every product's operator
//! is written (`\cdot`, `\times`, `\otimes`, `/`).

use super::context::Context;
use super::functions::Builtin;
use super::term::{Op, Term};

/// How the names of a context's terms are written.
pub struct Names<'a> {
    ctx: &'a Context,
}

impl<'a> Names<'a> {
    /// The names of `ctx`'s symbols, operators and links.
    pub fn of(ctx: &'a Context) -> Self {
        Names { ctx }
    }

    /// `term` with every grouping explicit.
    pub fn render(&self, term: &Term) -> String {
        match term {
            Term::Number(x) => number(*x),
            Term::Symbol(id) => self.ctx.table.key(*id).to_string(),
            Term::Neg(x) => format!("-{}", self.operand(x)),
            Term::Sum(terms) => {
                let mut out = String::new();
                for (i, (minus, t)) in terms.iter().enumerate() {
                    match (i, minus) {
                        (0, false) => {}
                        (0, true) => out.push('-'),
                        (_, false) => out.push_str(" + "),
                        (_, true) => out.push_str(" - "),
                    }
                    out.push_str(&self.operand(t));
                }
                out
            }
            Term::Product(factors) => {
                let mut out = String::new();
                for (i, (op, t)) in factors.iter().enumerate() {
                    if i > 0 {
                        out.push_str(match op {
                            Op::Mul | Op::Dot => " \\cdot ",
                            Op::Cross => " \\times ",
                            Op::Oplus { jpl: false } => " \\oplus ",
                            Op::Oplus { jpl: true } => " \\oplus_{\\text{JPL}} ",
                            Op::Otimes { jpl: false } => " \\otimes ",
                            Op::Otimes { jpl: true } => " \\otimes_{\\text{JPL}} ",
                            Op::Div => " / ",
                        });
                    }
                    out.push_str(&self.operand(t));
                }
                out
            }
            Term::Fraction {
                num,
                den,
                stack: false,
            } => format!("\\frac{{{}}}{{{}}}", self.render(num), self.render(den)),
            Term::Fraction { num, den, .. } => {
                format!(
                    "\\begin{{bmatrix}} {} \\\\ {} \\end{{bmatrix}}",
                    self.render(num),
                    self.render(den)
                )
            }
            Term::Power(x, p) => format!("{}^{{{}}}", self.scripted(x), number(*p)),
            Term::Norm(x) => format!("\\left\\| {} \\right\\|", self.render(x)),
            Term::Hat(x) => format!("{}^{{\\wedge}}", self.scripted(x)),
            Term::Vee(x) => format!("{}^{{\\vee}}", self.scripted(x)),
            Term::Transpose(x) => format!("{}^{{\\top}}", self.scripted(x)),
            Term::Call(b, args) => format!("{}\\left({}\\right)", function(*b), self.list(args)),
            Term::Blocks(rows) => {
                let rows: Vec<String> = rows
                    .iter()
                    .map(|r| {
                        r.iter()
                            .map(|t| self.render(t))
                            .collect::<Vec<_>>()
                            .join(" & ")
                    })
                    .collect();
                format!(
                    "\\begin{{bmatrix}} {} \\end{{bmatrix}}",
                    rows.join(" \\\\ ")
                )
            }
            Term::Zero => "0".into(),
            Term::BlockZero(rows, cols) => match (rows, cols) {
                (Some(r), Some(c)) => format!("0_{{{r} \\times {c}}}"),
                (Some(n), None) | (None, Some(n)) => format!("0_{{{n}}}"),
                (None, None) => "0".into(),
            },
            Term::Identity(None) => "I".into(),
            Term::Identity(Some(n)) => format!("I_{{{n}}}"),
            Term::Shaped(x, (r, c)) => format!("{}_{{{r} \\times {c}}}", self.scripted(x)),
            Term::Stack(items) => {
                let items: Vec<String> = items.iter().map(|t| self.render(t)).collect();
                format!(
                    "\\begin{{bmatrix}} {} \\end{{bmatrix}}",
                    items.join(" \\\\ ")
                )
            }
            Term::Quotient {
                numerator,
                tangent,
                limit,
            } => {
                let over = self.ctx.table.key(*tangent);
                let quotient = format!("\\frac{{{}}}{{{over}}}", self.render(numerator));
                if *limit {
                    format!("\\lim_{{{over} \\to 0}} {quotient}")
                } else {
                    quotient
                }
            }
            Term::Link(k) => match self.ctx.links.iter().find(|(_, c)| *c == k) {
                Some((key, _)) => format!("\\left[{key}\\right]"),
                None => format!("\\left[\\text{{claim {}}}\\right]", k + 1),
            },
            Term::TruthLink(k) => format!("\\left[{}\\right]", self.ctx.truth_links[*k].key),
            Term::At { body, bindings } => {
                let at: Vec<String> = bindings
                    .iter()
                    .map(|(id, t)| format!("{} = {}", self.ctx.table.key(*id), self.render(t)))
                    .collect();
                format!(
                    "\\left. {} \\right|_{{{}}}",
                    self.render(body),
                    at.join(", ")
                )
            }
            Term::Template(t, args) => {
                let template = &self.ctx.templates[*t];
                let (key, shown) = (&template.key, &template.written);
                match (key.strip_prefix('^'), args.as_slice()) {
                    (Some(op), [x]) => format!("{}^{{{op}}}", self.scripted(x)),
                    (None, [a, b]) if key.starts_with('\\') && !template.subscripted => {
                        format!("{} {shown} {}", self.operand(a), self.operand(b))
                    }
                    (None, [sub, rest @ ..]) if template.subscripted => format!(
                        "{{{shown}}}_{{{}}}\\left({}\\right)",
                        self.render(sub),
                        self.list(rest)
                    ),
                    _ => format!("{{{shown}}}\\left({}\\right)", self.list(args)),
                }
            }
        }
    }

    fn list(&self, args: &[Term]) -> String {
        args.iter()
            .map(|t| self.render(t))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// An operand of a sign, a sum or a product: bracketed unless atomic.
    fn operand(&self, t: &Term) -> String {
        if atomic(t) {
            self.render(t)
        } else {
            format!("\\left({}\\right)", self.render(t))
        }
    }

    /// The base of a script: bracketed unless a symbol or a number.
    fn scripted(&self, t: &Term) -> String {
        match t {
            Term::Symbol(_)
            | Term::Number(_)
            | Term::Identity(_)
            | Term::Zero
            | Term::BlockZero(..) => {
                format!("{{{}}}", self.render(t))
            }
            other => format!("\\left({}\\right)", self.render(other)),
        }
    }
}

/// Whether `t` needs no brackets as an operand.
fn atomic(t: &Term) -> bool {
    matches!(
        t,
        Term::Number(_)
            | Term::Symbol(_)
            | Term::Zero
            | Term::BlockZero(..)
            | Term::Identity(_)
            | Term::Norm(_)
            | Term::Call(..)
            | Term::Blocks(_)
            | Term::Stack(_)
            | Term::Link(_)
            | Term::TruthLink(_)
            | Term::Power(..)
            | Term::Hat(_)
            | Term::Vee(_)
            | Term::Transpose(_)
            | Term::Shaped(..)
            | Term::Fraction { .. }
            | Term::At { .. }
    ) && !matches!(t, Term::Number(x) if *x < 0.0)
}

/// A number as printed: integers without a decimal point.
fn number(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{}", x as i64)
    } else {
        format!("{x}")
    }
}

/// A built-in function's name as LaTeX (`\operatorname{left\_jacobian}`).
fn function(b: Builtin) -> String {
    format!("\\operatorname{{{}}}", b.name().replace('_', "\\_"))
}
