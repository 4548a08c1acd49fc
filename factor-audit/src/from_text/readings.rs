//! The other readings of a printed formula: where its notation leaves a
//! choice the parser and the symbol table made one way, the ways a reader
//! may have meant instead. Before a formula is reported `wrong` or
//! `malformed`, each other reading (one choice changed, then two) is
//! lowered and audited at every sample; when one agrees with the truth the
//! verdict is `ambiguous`, with that reading written with every grouping
//! explicit ([`super::understood`]). A false `wrong` would need every
//! reading listed here to be wrong too.
//!
//! The choices:
//! - scripts printed on a symbol's closing parenthesis: on the argument
//!   of a function (`f(x)^2` as `f(x^2)`); after a value, on the
//!   parenthesised group of a product, or on the symbol written with its
//!   variables (`T(ξ)^{-1}` as `T^{-1}`), never on the whole product
//!   (`R (R Q)^\top` is no `(R (R Q))^\top`);
//! - a symbol before parentheses: a product, or the symbol written with its
//!   variables, whichever the symbol table did not choose;
//! - a script on a function's call (`\sin(x)^2`): on its argument instead;
//! - a function without parentheses (`\sin \theta x`): applied to every
//!   factor after it instead of one;
//! - a product mixing `\times` or `/` with juxtaposition (`a \times b c`,
//!   read `a × (b c)`): strictly left to right, and `a / (b c)`;
//! - `exp` and `Exp`, `log` and `Log`: the one the document did not print;
//! - a zero with one size (`\mathbf{0}_3`): a square block of that size.

use doc_latex::ast::{Expr, Function, Head, MulOp, Symbol};

use super::TextAudit;
use super::claims::TextClaim;
use super::context::Context;
use super::errata::{MAX_SEARCHED_NODES, confirmed, lower_variant};
use super::lower::{number, symbol_key};
use super::term::{Meaning, Term};
use super::tree::{Path, at_mut, nodes};
use super::understood::Names;

/// The end of the words of a reading of which function a name is.
const DISPATCH: &str = " (the other function of that name)";

/// Most readings of one formula audited (each agreeing or not at its first
/// samples, almost always).
pub const MAX_READINGS: usize = 400;

/// One choice made the other way: the node at `path` replaced.
#[derive(Debug, Clone, PartialEq)]
pub struct Reading {
    /// Where.
    pub path: Path,
    /// The node read the other way.
    pub replacement: Expr,
    /// The choice, in words about the formula as printed.
    pub words: String,
    /// The choice is which function a name is (`exp` or `Exp`): made by the
    /// types of what the formula multiplies, when only one of the two
    /// evaluates.
    pub dispatch: bool,
}

/// The other reading of each choice in the printed tree `root` (one change
/// each); `is_function` tells which symbols the symbols file makes
/// functions (scripts after a value's parentheses never apply to the
/// whole product: `R (R Q)^\top` is no `(R (R Q))^\top` for a matrix `R`).
pub fn readings(root: &Expr, is_function: impl Fn(&Symbol) -> bool) -> Vec<Reading> {
    let mut out = Vec::new();
    for (path, node) in nodes(root) {
        let mut add = |replacement: Expr, words: String| {
            out.push(Reading {
                path: path.clone(),
                replacement,
                dispatch: words.ends_with(DISPATCH),
                words,
            })
        };
        match node {
            Expr::Apply {
                head: Head::Symbol(s),
                args,
                scripts: Some(chain),
            } => {
                let call = Expr::Apply {
                    head: Head::Symbol(s.clone()),
                    args: args.clone(),
                    scripts: None,
                };
                let shown = call.to_string();
                if is_function(s) {
                    // `f(x)^2` read `f(x^2)`.
                    add(
                        Expr::Apply {
                            head: Head::Symbol(s.clone()),
                            args: vec![Expr::with_scripts_of(chain, group(args))],
                            scripts: None,
                        },
                        format!("the script after `{shown}` on its argument"),
                    );
                } else {
                    add(
                        product(s, Expr::with_scripts_of(chain, group(args))),
                        format!("the script after `{shown}` on its parenthesised group"),
                    );
                    add(
                        Expr::with_scripts_of(chain, Expr::Symbol(s.clone())),
                        format!("`{shown}` as its symbol written with its variables"),
                    );
                }
            }
            Expr::Apply {
                head: Head::Symbol(s),
                args,
                scripts: None,
            } if !is_function(s) && !args.iter().all(|a| *a == Expr::Placeholder) => {
                add(product(s, group(args)), format!("`{node}` as a product"));
                add(
                    Expr::Symbol(s.clone()),
                    format!("`{node}` as its symbol written with its variables"),
                );
            }
            Expr::Power { base, exponent } => {
                if let Some(inner) = on_argument(base, |x| Expr::Power {
                    base: Box::new(x),
                    exponent: exponent.clone(),
                }) {
                    add(inner, format!("the exponent of `{node}` on the argument"));
                }
            }
            Expr::Postfix { base, op } => {
                if let Some(inner) = on_argument(base, |x| Expr::Postfix {
                    base: Box::new(x),
                    op: *op,
                }) {
                    add(inner, format!("the script of `{node}` on the argument"));
                }
            }
            Expr::Apply {
                head: Head::Function(f),
                args,
                scripts,
            } => {
                if let Some(other) = other_function(&f.name) {
                    add(
                        Expr::Apply {
                            head: Head::Function(Function {
                                name: other.into(),
                                ..f.clone()
                            }),
                            args: args.clone(),
                            scripts: scripts.clone(),
                        },
                        format!("`{}` read as `{other}`{DISPATCH}", f.name),
                    );
                }
            }
            Expr::Product { first, rest } => {
                let factors: Vec<(MulOp, &Expr)> = std::iter::once((MulOp::Implicit, &**first))
                    .chain(rest.iter().map(|(op, x)| (*op, x)))
                    .collect();
                for (replacement, words) in product_readings(&factors) {
                    add(replacement, words);
                }
            }
            Expr::Symbol(s) => {
                if let Some(square) = square_zero(s) {
                    add(
                        Expr::Symbol(square),
                        format!("`{node}` as a square zero block"),
                    );
                }
            }
            _ => {}
        }
    }
    out
}

/// `s (group)`: the symbol multiplying the group.
fn product(s: &Symbol, group: Expr) -> Expr {
    Expr::Product {
        first: Box::new(Expr::Symbol(s.clone())),
        rest: vec![(MulOp::Implicit, group)],
    }
}

/// The parenthesised group of an application's arguments.
fn group(args: &[Expr]) -> Expr {
    match args {
        [one] => one.clone(),
        many => Expr::Tuple(many.to_vec()),
    }
}

/// `f(script(x))` for a function's call `f(x)` of one argument.
fn on_argument(call: &Expr, script: impl FnOnce(Expr) -> Expr) -> Option<Expr> {
    match call {
        Expr::Apply {
            head: head @ Head::Function(_),
            args,
            scripts: None,
        } if args.len() == 1 => Some(Expr::Apply {
            head: head.clone(),
            args: vec![script(args[0].clone())],
            scripts: None,
        }),
        _ => None,
    }
}

/// The function a document may have meant by `name`: the group map for
/// the plain one and the reverse.
fn other_function(name: &str) -> Option<&'static str> {
    match name {
        "exp" => Some("Exp"),
        "Exp" => Some("exp"),
        "log" => Some("Log"),
        "Log" => Some("log"),
        _ => None,
    }
}

/// `\mathbf{0}_n` as `\mathbf{0}_{n × n}`.
fn square_zero(s: &Symbol) -> Option<Symbol> {
    if s.base != doc_latex::ast::Base::Letter('0') || s.sup.is_some() {
        return None;
    }
    let n = number(s.sub.as_deref()?)?;
    if n.fract() != 0.0 || n < 2.0 {
        return None;
    }
    let size = Expr::Number(format!("{}", n as usize));
    Some(Symbol {
        sub: Some(Box::new(Expr::Product {
            first: Box::new(size.clone()),
            rest: vec![(MulOp::Times, size)],
        })),
        ..s.clone()
    })
}

/// A product's other groupings: a function printed without parentheses
/// taking every factor after it; `\times` and `/` read strictly left to
/// right; `a / (b c)`.
fn product_readings(factors: &[(MulOp, &Expr)]) -> Vec<(Expr, String)> {
    let mut out = Vec::new();
    let rebuild = |items: Vec<(MulOp, Expr)>| -> Expr {
        let mut it = items.into_iter();
        let (_, first) = it.next().expect("a product has factors");
        let rest: Vec<(MulOp, Expr)> = it.collect();
        if rest.is_empty() {
            first
        } else {
            Expr::Product {
                first: Box::new(first),
                rest,
            }
        }
    };
    for (k, (_, x)) in factors.iter().enumerate() {
        let Expr::Apply {
            head: Head::Function(f),
            args,
            scripts: None,
        } = x
        else {
            continue;
        };
        let end = (k + 1..factors.len())
            .take_while(|j| factors[*j].0 == MulOp::Implicit)
            .last();
        let (true, Some(end), [arg]) = (f.bare, end, args.as_slice()) else {
            continue;
        };
        let mut taken = vec![(MulOp::Implicit, arg.clone())];
        taken.extend(
            factors[k + 1..=end]
                .iter()
                .map(|(op, e)| (*op, (*e).clone())),
        );
        let applied = Expr::Apply {
            head: Head::Function(f.clone()),
            args: vec![rebuild(taken)],
            scripts: None,
        };
        let mut items: Vec<(MulOp, Expr)> = factors[..k]
            .iter()
            .map(|(op, e)| (*op, (*e).clone()))
            .collect();
        items.push((factors[k].0, applied));
        items.extend(factors[end + 1..].iter().map(|(op, e)| (*op, (*e).clone())));
        out.push((
            rebuild(items),
            format!("`{}` applied to every factor after it", f.name),
        ));
    }
    let mixed = |op: MulOp| {
        factors.iter().skip(1).any(|(o, _)| *o == op)
            && factors.iter().skip(1).any(|(o, _)| *o != op)
    };
    if mixed(MulOp::Times) || mixed(MulOp::Slash) {
        // ((a × b) c …): each operator on everything before it.
        let mut acc: Expr = factors[0].1.clone();
        for (op, x) in &factors[1..] {
            acc = Expr::Product {
                first: Box::new(acc),
                rest: vec![(*op, (*x).clone())],
            };
        }
        out.push((acc, "the product read strictly from left to right".into()));
    }
    if let Some(k) = factors.iter().position(|(op, _)| *op == MulOp::Slash)
        && k + 1 < factors.len()
    {
        let denominator: Vec<(MulOp, Expr)> = factors[k..]
            .iter()
            .enumerate()
            .map(|(i, (op, e))| (if i == 0 { MulOp::Implicit } else { *op }, (*e).clone()))
            .collect();
        let mut items: Vec<(MulOp, Expr)> = factors[..k]
            .iter()
            .map(|(op, e)| (*op, (*e).clone()))
            .collect();
        items.push((MulOp::Slash, rebuild(denominator)));
        out.push((rebuild(items), "everything after `/` below it".into()));
    }
    out
}

/// When `claim` is wrong or malformed as read, a reading of its notation
/// (one choice changed, then two) under which it agrees with the truth at
/// every one of the audit's samples: the reading as LaTeX with every
/// grouping explicit, and the choices in words.
pub fn settle(audit: &TextAudit, claim: &TextClaim, samples: usize) -> Option<String> {
    if nodes(&claim.printed_ast).len() > MAX_SEARCHED_NODES {
        return None;
    }
    let ctx = &audit.contexts[claim.context];
    let is_function = |s: &Symbol| {
        ctx.lookup(claim.scope(), &symbol_key(s)).is_some_and(|id| {
            matches!(
                ctx.table.entries[id].meaning,
                Meaning::Function(_) | Meaning::Template(_)
            )
        })
    };
    let singles = readings(&claim.printed_ast, is_function);
    let mut trial = Trial {
        claim,
        ctx,
        samples,
        seen: vec![claim.printed.clone()],
    };
    for r in &singles {
        if let Some(found) = trial.attempt(&[r]) {
            return Some(found);
        }
    }
    for (i, a) in singles.iter().enumerate() {
        for b in &singles[i + 1..] {
            if a.path.starts_with(&b.path) || b.path.starts_with(&a.path) {
                continue;
            }
            if trial.seen.len() > MAX_READINGS {
                return None;
            }
            if let Some(found) = trial.attempt(&[a, b]) {
                return Some(found);
            }
        }
    }
    None
}

/// When `claim` is malformed as read, the one reading of a function name
/// (`exp` as `Exp`, `log` as `Log`) under which it evaluates at every
/// sample: the claim read so, with a note saying how (the types of what
/// the formula multiplies choose the function: `\exp(-v) B` with `B` a
/// matrix is the rotation `Exp(−v)`, not a quaternion).
pub fn well_formed(audit: &TextAudit, claim: &TextClaim, samples: usize) -> Option<TextClaim> {
    if nodes(&claim.printed_ast).len() > MAX_SEARCHED_NODES {
        return None;
    }
    let ctx = &audit.contexts[claim.context];
    let evaluating: Vec<(Expr, Term, String)> = readings(&claim.printed_ast, |_| false)
        .into_iter()
        .filter(|r| r.dispatch)
        .filter_map(|r| {
            let mut e = claim.printed_ast.clone();
            *at_mut(&mut e, &r.path)? = r.replacement.clone();
            let term = lower_variant(claim, ctx, &e)?;
            evaluates(claim, ctx, &term, samples).then_some((e, term, r.words))
        })
        .collect();
    let [(printed_ast, printed, words)] = <[_; 1]>::try_from(evaluating).ok()?;
    let mut read = claim.clone();
    read.understood =
        super::claims::understood_line(ctx, claim.lhs.as_ref(), claim.relation, &printed);
    read.printed_ast = printed_ast;
    read.printed = printed;
    read.notes
        .push(format!("{words}: as printed it does not evaluate"));
    Some(read)
}

/// Whether `term` (a variant of the claim's printed side) evaluates at
/// every one of the audit's samples.
fn evaluates(claim: &TextClaim, ctx: &Context, term: &Term, samples: usize) -> bool {
    let mut sampler = factor_testing::samples::Sampler::new(TextAudit::seed(claim.index));
    (0..samples).all(|_| {
        let d = super::claims::TextDerivation::new(claim, ctx, ctx.sample(&mut sampler));
        matches!(
            d.printed_term(term),
            crate::derivation::Printed::Evaluated(_)
        )
    })
}

/// The readings of one claim tried so far.
struct Trial<'a> {
    claim: &'a TextClaim,
    ctx: &'a Context,
    samples: usize,
    /// The terms already audited (the printed one first): two readings
    /// evaluated alike are audited once.
    seen: Vec<Term>,
}

impl Trial<'_> {
    /// The printed tree with `choices` made the other way, when it agrees
    /// with the truth everywhere: as [`settle`] says it.
    fn attempt(&mut self, choices: &[&Reading]) -> Option<String> {
        let mut e = self.claim.printed_ast.clone();
        let mut ordered = choices.to_vec();
        ordered.sort_by(|a, b| b.path.cmp(&a.path));
        for r in ordered {
            *at_mut(&mut e, &r.path)? = r.replacement.clone();
        }
        let term = lower_variant(self.claim, self.ctx, &e)?;
        if self.seen.contains(&term) {
            return None;
        }
        self.seen.push(term.clone());
        confirmed(self.claim, self.ctx, &term, 0, self.samples).then(|| {
            let words: Vec<&str> = choices.iter().map(|r| r.words.as_str()).collect();
            format!(
                "${}$ ({})",
                Names::of(self.ctx).render(&term),
                words.join(", and ")
            )
        })
    }
}
