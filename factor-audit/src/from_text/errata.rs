//! The erratum search: small symbolic edits of the printed formula, the
//! smallest that makes it agree with the truth at every sample.
//!
//! The edit space (each edit changes the printed syntax tree, which is
//! lowered and evaluated again):
//! - the sign of a term of a sum, of a matrix entry or of the whole;
//! - an exponent `e` (of a power, or a number written as a symbol's
//!   superscript read as a power) to `e + 1`, `e − 1`, `2e`, `e/2` or `−e`
//!   (so `3/2 ↔ 3`);
//! - a factor of a product transposed (or its transpose removed), the whole
//!   transposed;
//! - two entries of a matrix's row or column swapped; an entry replaced by
//!   `0`; a matrix's row or column deleted;
//! - a term of a sum or a factor of a product deleted;
//! - a symbol replaced by a sibling in scope (the same letter with another
//!   subscript, superscript, accent, font or primes: `ω̂ → ω`, `l¹ → l²`);
//! - a term, an entry or the whole multiplied by 2 or ½.
//!
//! Single edits are tried first, then pairs (two edits at places not inside
//! one another), at most [`MAX_CANDIDATES`] edited formulas an equation (and
//! [`MAX_CANDIDATES_PER_RUN`] in a whole audit), each evaluated at up to
//! [`SEARCH_SAMPLES`] of the audit's samples (stopping at the first that
//! disagrees); formulas of more than [`MAX_SEARCHED_NODES`] nodes are not
//! searched. A formula that agrees there is confirmed at
//! every sample of the audit. The targets are the truth, then the truths
//! under the claim's conventions and with the tangent's halves swapped (a
//! fix that makes the formula right only under one of those says so). When
//! no edit within the bound fixes the whole formula, the single edit that
//! makes the most columns agree (more than as printed) is reported as a
//! partial diagnosis, with the columns still wrong.

use doc_latex::ast::{self, Expr, MulOp, PostfixOp, Sign};
use nalgebra::DMatrix;

use super::TextAudit;
use super::claims::{TextClaim, TextDerivation};
use super::context::{Context, FrozenResolver};
use super::lower::{Lowering, number, symbol_key};
use super::symbols::ClaimKind;
use super::term::{Meaning, Term};
use super::tree::{Path, at, at_mut, nodes};
use crate::derivation::{Derivation, Printed, truth};
use crate::verdict::TOLERANCE;
use factor_core::factor::relative_frobenius_error;
use factor_testing::samples::Sampler;

/// Most edited formulas evaluated per equation (singles and pairs).
pub const MAX_CANDIDATES: usize = 20_000;
/// Most edited formulas evaluated in one audit, all equations together.
pub const MAX_CANDIDATES_PER_RUN: usize = 100_000;
/// Largest printed formula searched, in syntax-tree nodes.
pub const MAX_SEARCHED_NODES: usize = 400;
/// Samples an edited formula is evaluated at during the search.
pub const SEARCH_SAMPLES: usize = 6;
/// Most alternative fixes reported.
pub const MAX_FIXES_SHOWN: usize = 3;

/// One edit of a printed formula.
#[derive(Debug, Clone, PartialEq)]
pub enum Edit {
    /// A minus put on (or taken off) the node.
    Negate(Path),
    /// The sign of term `term` (≥ 1) of a sum flipped.
    FlipTerm {
        /// The sum.
        sum: Path,
        /// The term.
        term: usize,
    },
    /// A power's exponent changed.
    Exponent {
        /// The power.
        path: Path,
        /// The exponent printed.
        from: f64,
        /// The new exponent.
        to: f64,
    },
    /// A symbol's superscript read as a power, changed.
    SymbolExponent {
        /// The symbol.
        path: Path,
        /// The exponent printed.
        from: f64,
        /// The new exponent.
        to: f64,
    },
    /// A transpose put on (or taken off) the node.
    Transpose(Path),
    /// Two entries of a matrix swapped (flat indices, row by row).
    Swap {
        /// The matrix.
        matrix: Path,
        /// One entry.
        a: usize,
        /// The other.
        b: usize,
    },
    /// A matrix entry replaced by `0`.
    ZeroEntry {
        /// The matrix.
        matrix: Path,
        /// The entry.
        entry: usize,
    },
    /// A term of a sum deleted.
    DeleteTerm {
        /// The sum.
        sum: Path,
        /// The term.
        term: usize,
    },
    /// A factor of a product deleted.
    DeleteFactor {
        /// The product.
        product: Path,
        /// The factor.
        factor: usize,
    },
    /// A row of a matrix deleted.
    DeleteRow {
        /// The matrix.
        matrix: Path,
        /// The row.
        row: usize,
    },
    /// A column of a matrix deleted.
    DeleteColumn {
        /// The matrix.
        matrix: Path,
        /// The column.
        column: usize,
    },
    /// A symbol replaced by a sibling.
    Replace {
        /// The symbol.
        path: Path,
        /// Its replacement.
        with: Box<ast::Symbol>,
    },
    /// The node multiplied by a constant.
    Scale {
        /// The node.
        path: Path,
        /// The constant (2 or ½).
        by: f64,
    },
}

fn child(path: &Path, i: usize) -> Path {
    let mut p = path.clone();
    p.push(i);
    p
}

impl Edit {
    /// The node it changes (an edit of a list's item names the item).
    fn site(&self) -> Path {
        match self {
            Edit::Negate(p)
            | Edit::Exponent { path: p, .. }
            | Edit::SymbolExponent { path: p, .. }
            | Edit::Transpose(p)
            | Edit::Replace { path: p, .. }
            | Edit::Scale { path: p, .. }
            | Edit::Swap { matrix: p, .. }
            | Edit::DeleteRow { matrix: p, .. }
            | Edit::DeleteColumn { matrix: p, .. } => p.clone(),
            Edit::FlipTerm { sum: p, term: i } | Edit::DeleteTerm { sum: p, term: i } => {
                child(p, *i)
            }
            Edit::DeleteFactor {
                product: p,
                factor: i,
            } => child(p, *i),
            Edit::ZeroEntry {
                matrix: p,
                entry: i,
            } => child(p, *i),
        }
    }

    /// Applies it to `root`; `false` when it no longer fits.
    fn apply(&self, root: &mut Expr) -> bool {
        let Some(node) = at_mut(root, &self.parent_or_site()) else {
            return false;
        };
        match self {
            Edit::Negate(_) => {
                let old = std::mem::replace(node, Expr::Placeholder);
                *node = match old {
                    Expr::Neg(x) => *x,
                    other => Expr::Neg(Box::new(other)),
                };
                true
            }
            Edit::FlipTerm { term, .. } => match node {
                Expr::Sum { rest, .. } if *term >= 1 && *term <= rest.len() => {
                    let s = &mut rest[term - 1].0;
                    *s = if *s == Sign::Plus {
                        Sign::Minus
                    } else {
                        Sign::Plus
                    };
                    true
                }
                _ => false,
            },
            Edit::Exponent { to, .. } => match node {
                Expr::Power { exponent, .. } => {
                    **exponent = number_expr(*to);
                    true
                }
                _ => false,
            },
            Edit::SymbolExponent { to, .. } => match node {
                Expr::Symbol(s) => {
                    s.sup = Some(Box::new(number_expr(*to)));
                    true
                }
                _ => false,
            },
            Edit::Transpose(_) => {
                let old = std::mem::replace(node, Expr::Placeholder);
                *node = match old {
                    Expr::Postfix {
                        base,
                        op: PostfixOp::Transpose,
                    } => *base,
                    other => Expr::Postfix {
                        base: Box::new(other),
                        op: PostfixOp::Transpose,
                    },
                };
                true
            }
            Edit::Swap { a, b, .. } => match node {
                Expr::Matrix(m) => {
                    let mut flat: Vec<&mut Expr> = m.rows.iter_mut().flatten().collect();
                    if *a >= flat.len() || *b >= flat.len() || a == b {
                        return false;
                    }
                    let (lo, hi) = (*a.min(b), *a.max(b));
                    let (left, right) = flat.split_at_mut(hi);
                    std::mem::swap(left[lo], right[0]);
                    true
                }
                _ => false,
            },
            Edit::ZeroEntry { entry, .. } => match node {
                Expr::Matrix(m) => match m.rows.iter_mut().flatten().nth(*entry) {
                    Some(e) => {
                        *e = Expr::Number("0".into());
                        true
                    }
                    None => false,
                },
                _ => false,
            },
            Edit::DeleteTerm { term, .. } => match node {
                Expr::Sum { first, rest } if *term <= rest.len() && !rest.is_empty() => {
                    if *term == 0 {
                        let (sign, next) = rest.remove(0);
                        **first = match sign {
                            Sign::Plus => next,
                            Sign::Minus => Expr::Neg(Box::new(next)),
                        };
                    } else {
                        rest.remove(term - 1);
                    }
                    if rest.is_empty() {
                        let only = std::mem::replace(first.as_mut(), Expr::Placeholder);
                        *node = only;
                    }
                    true
                }
                _ => false,
            },
            Edit::DeleteFactor { factor, .. } => match node {
                Expr::Product { first, rest } if *factor <= rest.len() && !rest.is_empty() => {
                    if *factor == 0 {
                        **first = rest.remove(0).1;
                    } else {
                        rest.remove(factor - 1);
                    }
                    if rest.is_empty() {
                        let only = std::mem::replace(first.as_mut(), Expr::Placeholder);
                        *node = only;
                    }
                    true
                }
                _ => false,
            },
            Edit::DeleteRow { row, .. } => match node {
                Expr::Matrix(m) if m.rows.len() > 1 && *row < m.rows.len() => {
                    m.rows.remove(*row);
                    true
                }
                _ => false,
            },
            Edit::DeleteColumn { column, .. } => match node {
                Expr::Matrix(m) if m.shape().is_some_and(|(_, c)| c > 1 && *column < c) => {
                    for r in &mut m.rows {
                        r.remove(*column);
                    }
                    true
                }
                _ => false,
            },
            Edit::Replace { with, .. } => match node {
                Expr::Symbol(s) => {
                    *s = (**with).clone();
                    true
                }
                _ => false,
            },
            Edit::Scale { by, .. } => {
                let old = std::mem::replace(node, Expr::Placeholder);
                *node = Expr::Product {
                    first: Box::new(number_expr(*by)),
                    rest: vec![(MulOp::Implicit, old)],
                };
                true
            }
        }
    }

    /// The node the edit is applied at (a list's, for edits of its items).
    fn parent_or_site(&self) -> Path {
        match self {
            Edit::FlipTerm { sum: p, .. }
            | Edit::DeleteTerm { sum: p, .. }
            | Edit::DeleteFactor { product: p, .. }
            | Edit::ZeroEntry { matrix: p, .. } => p.clone(),
            other => other.site(),
        }
    }

    /// The edit in words, about the formula as printed.
    pub fn describe(&self, root: &Expr) -> String {
        let show =
            |p: &Path| at(root, p).map_or_else(|| "?".to_string(), |e| plain(&e.to_string()));
        let entry = |m: &Path, k: usize| match at(root, m) {
            Some(Expr::Matrix(mat)) => {
                let mut left = k;
                for (r, row) in mat.rows.iter().enumerate() {
                    if left < row.len() {
                        return format!("({}, {})", r + 1, left + 1);
                    }
                    left -= row.len();
                }
                "?".into()
            }
            _ => "?".into(),
        };
        let matrix = |m: &Path| {
            let shape = match at(root, m) {
                Some(Expr::Matrix(mat)) => mat
                    .shape()
                    .map_or(String::new(), |(r, c)| format!("{r} × {c} ")),
                _ => String::new(),
            };
            match m.split_last() {
                None => format!("the printed {shape}matrix"),
                Some((i, parent)) if matches!(at(root, parent), Some(Expr::Product { .. })) => {
                    format!("the {shape}matrix (factor {} of the product)", i + 1)
                }
                Some(_) => format!("the {shape}matrix `{}`", show(m)),
            }
        };
        match self {
            Edit::Negate(p) if p.is_empty() => {
                "the whole formula should have the opposite sign".into()
            }
            Edit::Negate(p) => format!("the sign of `{}` should be flipped", show(p)),
            Edit::FlipTerm { sum, term } => {
                format!(
                    "the sign of the term `{}` should be flipped",
                    show(&child(sum, *term))
                )
            }
            Edit::Exponent { path, from, to } => {
                let base = match at(root, path) {
                    Some(Expr::Power { base, .. }) => plain(&base.to_string()),
                    _ => "?".into(),
                };
                format!(
                    "exponent {} of {base} should be {}",
                    fraction(*from),
                    fraction(*to)
                )
            }
            Edit::SymbolExponent { path, from, to } => {
                let base = match at(root, path) {
                    Some(Expr::Symbol(s)) => {
                        let mut b = s.clone();
                        b.sup = None;
                        plain(&symbol_key(&b))
                    }
                    _ => "?".into(),
                };
                format!(
                    "exponent {} of {base} should be {}",
                    fraction(*from),
                    fraction(*to)
                )
            }
            Edit::Transpose(p) if p.is_empty() => "the whole formula should be transposed".into(),
            Edit::Transpose(p) => match at(root, p) {
                Some(Expr::Postfix {
                    base,
                    op: PostfixOp::Transpose,
                }) => format!("`{}` should not be transposed", plain(&base.to_string())),
                _ => format!("`{}` should be transposed", show(p)),
            },
            Edit::Swap { matrix: m, a, b } => format!(
                "blocks {} and {} of {} should be swapped",
                entry(m, *a),
                entry(m, *b),
                matrix(m)
            ),
            Edit::ZeroEntry {
                matrix: m,
                entry: k,
            } => format!(
                "block {} (`{}`) of {} should be 0",
                entry(m, *k),
                show(&child(m, *k)),
                matrix(m)
            ),
            Edit::DeleteTerm { sum, term } => {
                format!(
                    "the term `{}` should not be there",
                    show(&child(sum, *term))
                )
            }
            Edit::DeleteFactor { product, factor } => {
                format!(
                    "the factor `{}` should not be there",
                    show(&child(product, *factor))
                )
            }
            Edit::DeleteRow { matrix: m, row } => {
                format!("row {} of {} should not be there", row + 1, matrix(m))
            }
            Edit::DeleteColumn { matrix: m, column } => {
                format!("column {} of {} should not be there", column + 1, matrix(m))
            }
            Edit::Replace { path, with } => {
                format!("`{}` should be `{}`", show(path), plain(&symbol_key(with)))
            }
            Edit::Scale { path, by } if path.is_empty() => {
                format!(
                    "the whole formula should be multiplied by {}",
                    fraction(*by)
                )
            }
            Edit::Scale { path, by } => {
                format!("`{}` should be multiplied by {}", show(path), fraction(*by))
            }
        }
    }
}

/// LaTeX made lighter for prose: no `\left`/`\right`, bars hugging their
/// content, at most 50 characters.
fn plain(latex: &str) -> String {
    let s = latex.replace("\\left", "").replace("\\right", "");
    let s = s.replace("| ", "|").replace(" |", "|");
    let mut out: String = s.trim().chars().take(50).collect();
    if s.trim().chars().count() > 50 {
        out.push('…');
    }
    out
}

/// A number in prose: `3`, `3/2`, `-1/2`.
fn fraction(x: f64) -> String {
    let (p, q) = rational(x);
    if q == 1 {
        format!("{p}")
    } else {
        format!("{p}/{q}")
    }
}

/// `x` as `p/q` with `q ≤ 12` when it is one (else `q = 1` and `p` rounded,
/// which no edit produces).
fn rational(x: f64) -> (i64, i64) {
    for q in 1..=12_i64 {
        let p = x * q as f64;
        if (p - p.round()).abs() < 1e-9 {
            return (p.round() as i64, q);
        }
    }
    (x.round() as i64, 1)
}

/// A number as a printed expression: `3`, `\frac{3}{2}`, `-\frac{1}{2}`.
fn number_expr(x: f64) -> Expr {
    let (p, q) = rational(x.abs());
    let e = if q == 1 {
        Expr::Number(p.to_string())
    } else {
        Expr::Fraction {
            num: Box::new(Expr::Number(p.to_string())),
            den: Box::new(Expr::Number(q.to_string())),
        }
    };
    if x < 0.0 { Expr::Neg(Box::new(e)) } else { e }
}

/// The exponents tried for a printed exponent `e`.
fn exponents(e: f64) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for to in [e + 1.0, e - 1.0, 2.0 * e, e / 2.0, -e] {
        if to != e && to != 0.0 && !out.contains(&to) {
            out.push(to);
        }
    }
    out
}

/// Every single edit of `root`, in a fixed order.
pub fn candidates(root: &Expr, ctx: &Context, claim: &TextClaim) -> Vec<Edit> {
    let mut out = vec![
        Edit::Negate(Vec::new()),
        Edit::Scale {
            path: Vec::new(),
            by: 2.0,
        },
        Edit::Scale {
            path: Vec::new(),
            by: 0.5,
        },
        Edit::Transpose(Vec::new()),
    ];
    let siblings = siblings(ctx, claim);
    for (path, node) in nodes(root) {
        match node {
            Expr::Sum { rest, .. } => {
                for i in 0..=rest.len() {
                    out.push(if i == 0 {
                        Edit::Negate(child(&path, 0))
                    } else {
                        Edit::FlipTerm {
                            sum: path.clone(),
                            term: i,
                        }
                    });
                    out.push(Edit::DeleteTerm {
                        sum: path.clone(),
                        term: i,
                    });
                    for by in [2.0, 0.5] {
                        out.push(Edit::Scale {
                            path: child(&path, i),
                            by,
                        });
                    }
                }
            }
            Expr::Product { first, rest } => {
                let factors = std::iter::once(first.as_ref()).chain(rest.iter().map(|(_, f)| f));
                for (i, f) in factors.enumerate() {
                    if !matches!(f, Expr::Number(_)) {
                        out.push(Edit::Transpose(child(&path, i)));
                    }
                    out.push(Edit::DeleteFactor {
                        product: path.clone(),
                        factor: i,
                    });
                }
            }
            Expr::Matrix(m) => {
                let cells: Vec<(usize, usize)> = m
                    .rows
                    .iter()
                    .enumerate()
                    .flat_map(|(r, row)| (0..row.len()).map(move |c| (r, c)))
                    .collect();
                for (k, (r, c)) in cells.iter().enumerate() {
                    // A printed 0 has no sign to flip and is 0 already.
                    if number(&m.rows[*r][*c]) != Some(0.0) {
                        out.push(Edit::Negate(child(&path, k)));
                        out.push(Edit::ZeroEntry {
                            matrix: path.clone(),
                            entry: k,
                        });
                    }
                    for (j, (r2, c2)) in cells.iter().enumerate().skip(k + 1) {
                        if r == r2 || c == c2 {
                            out.push(Edit::Swap {
                                matrix: path.clone(),
                                a: k,
                                b: j,
                            });
                        }
                    }
                }
                if m.rows.len() > 1 {
                    for row in 0..m.rows.len() {
                        out.push(Edit::DeleteRow {
                            matrix: path.clone(),
                            row,
                        });
                    }
                }
                if let Some((_, cols)) = m.shape().filter(|(_, c)| *c > 1) {
                    for column in 0..cols {
                        out.push(Edit::DeleteColumn {
                            matrix: path.clone(),
                            column,
                        });
                    }
                }
            }
            Expr::Power { exponent, .. } => {
                if let Some(e) = number(exponent) {
                    for to in exponents(e) {
                        out.push(Edit::Exponent {
                            path: path.clone(),
                            from: e,
                            to,
                        });
                    }
                }
            }
            Expr::Symbol(s) => {
                if let Some(e) = s.sup.as_deref().and_then(number) {
                    for to in exponents(e) {
                        out.push(Edit::SymbolExponent {
                            path: path.clone(),
                            from: e,
                            to,
                        });
                    }
                }
                // Another symbol of the same letter that is not the same
                // quantity under another name.
                let same = ctx
                    .lookup(claim.scope(), &symbol_key(s))
                    .map(|id| ctx.alias_of(id));
                for (sibling, _) in siblings
                    .iter()
                    .filter(|(x, target)| x.base == s.base && *x != *s && Some(*target) != same)
                {
                    out.push(Edit::Replace {
                        path: path.clone(),
                        with: Box::new(sibling.clone()),
                    });
                }
            }
            _ => {}
        }
    }
    out
}

/// The symbols in the claim's scope that hold values, as parsed symbols,
/// with the symbol each is an alias of (itself if none).
fn siblings(ctx: &Context, claim: &TextClaim) -> Vec<(ast::Symbol, usize)> {
    ctx.visible(claim.scope())
        .into_iter()
        .filter(|(_, id)| {
            matches!(
                ctx.table.entries[*id].meaning,
                Meaning::Stored { .. }
                    | Meaning::Definition(_)
                    | Meaning::Component { .. }
                    | Meaning::Residual(_)
            )
        })
        .filter_map(|(key, id)| match doc_latex::parse_expr(&key) {
            Ok(Expr::Symbol(s)) => Some((s, ctx.alias_of(id))),
            _ => None,
        })
        .collect()
}

/// A target an edited formula may agree with: the truth, or an alternative.
struct Target {
    /// `None` for the truth, else what the alternative is.
    name: Option<String>,
    /// Its matrix at each search sample.
    at: Vec<DMatrix<f64>>,
}

fn agree(a: &DMatrix<f64>, b: &DMatrix<f64>) -> bool {
    a.shape() == b.shape() && relative_frobenius_error(a, b, 1e-9) <= TOLERANCE
}

/// The truth and the alternatives at the samples of `derivations`.
fn targets(claim: &TextClaim, derivations: &[TextDerivation<'_>]) -> Vec<Target> {
    let truths: Vec<DMatrix<f64>> = derivations.iter().map(truth).collect();
    let mut out = vec![Target {
        name: None,
        at: truths.clone(),
    }];
    for (k, c) in claim.conventions.iter().enumerate() {
        out.push(Target {
            name: Some(c.description.clone()),
            at: derivations
                .iter()
                .map(|d| d.conventions().swap_remove(k).1)
                .collect(),
        });
    }
    let n = truths[0].ncols();
    if claim.kind != ClaimKind::Value && n >= 2 && n.is_multiple_of(2) {
        out.push(Target {
            name: Some(
                "with the two halves of the tangent swapped (e.g. [δρ, δω] instead of [δω, δρ])"
                    .into(),
            ),
            at: truths
                .iter()
                .map(|t| DMatrix::from_fn(t.nrows(), n, |r, c| t[(r, (c + n / 2) % n)]))
                .collect(),
        });
    }
    out
}

/// The suspected erratum of a claim.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnosis {
    /// In words: the edits, what they make right, and what stays wrong.
    pub words: String,
    /// The printed formula with the edits, as LaTeX (`lhs = rhs'`).
    pub corrected: String,
    /// Whether the edited formula agrees everywhere (else it is partial).
    pub complete: bool,
    /// How many edits it makes.
    pub edits: usize,
}

/// What a search found, and how many edited formulas it evaluated.
#[derive(Debug, Clone, PartialEq)]
pub struct Searched {
    /// The diagnosis, if an edit within the bound fixes (part of) it.
    pub diagnosis: Option<Diagnosis>,
    /// Edited formulas evaluated (at most the budget given).
    pub evaluated: usize,
}

/// One search: the formula, its samples and its targets.
struct Search<'a> {
    claim: &'a TextClaim,
    ctx: &'a Context,
    root: Expr,
    derivations: Vec<TextDerivation<'a>>,
    targets: Vec<Target>,
    evaluated: usize,
    budget: usize,
}

/// What an edited formula does.
enum Outcome {
    /// It cannot be evaluated (or the edit does not apply).
    Invalid,
    /// It agrees with these targets (indices) at every search sample.
    Agrees(Vec<usize>),
    /// It agrees with no target; these columns of the truth (when counted)
    /// agree at every search sample.
    Columns(Vec<usize>),
}

/// Whether column `c` of `p` is right: within the tolerance of the whole
/// truth's norm, as the verdict engine measures columns.
fn column_agrees(p: &DMatrix<f64>, t: &DMatrix<f64>, c: usize) -> bool {
    p.shape() == t.shape() && (p.column(c) - t.column(c)).norm() <= TOLERANCE * t.norm().max(1e-9)
}

impl Search<'_> {
    fn lower(&self, e: &Expr) -> Option<Term> {
        let mut resolver = FrozenResolver {
            ctx: self.ctx,
            scope: self.claim.scope(),
        };
        Lowering::new(&mut resolver, self.claim.stacked_fractions)
            .expr(e)
            .ok()
    }

    /// Applies `edits` (the later places first, so earlier ones keep their
    /// paths) and scores the result.
    fn try_edits(&mut self, edits: &[&Edit], columns: bool) -> (Outcome, Option<Expr>) {
        let mut e = self.root.clone();
        let mut ordered: Vec<&&Edit> = edits.iter().collect();
        ordered.sort_by_key(|edit| std::cmp::Reverse(edit.site()));
        if !ordered.iter().all(|edit| edit.apply(&mut e)) {
            return (Outcome::Invalid, None);
        }
        self.evaluated += 1;
        let Some(term) = self.lower(&e) else {
            return (Outcome::Invalid, None);
        };
        (self.score(&term, columns), Some(e))
    }

    /// How `term` fares against the targets at the search samples.
    fn score(&self, term: &Term, columns: bool) -> Outcome {
        let mut alive: Vec<usize> = (0..self.targets.len()).collect();
        let mut good: Vec<usize> = if columns {
            (0..self.targets[0].at[0].ncols()).collect()
        } else {
            Vec::new()
        };
        for (k, d) in self.derivations.iter().enumerate() {
            let Printed::Evaluated(p) = d.printed_term(term) else {
                return Outcome::Invalid;
            };
            alive.retain(|t| agree(&p, &self.targets[*t].at[k]));
            good.retain(|c| column_agrees(&p, &self.targets[0].at[k], *c));
            if alive.is_empty() && good.is_empty() {
                return Outcome::Columns(Vec::new());
            }
        }
        if alive.is_empty() {
            Outcome::Columns(good)
        } else {
            Outcome::Agrees(alive)
        }
    }

    /// Whether `edited` agrees with target `target` at every one of the
    /// audit's `samples` samples.
    fn confirm(&self, edited: &Expr, target: usize, samples: usize) -> bool {
        let Some(term) = self.lower(edited) else {
            return false;
        };
        let mut sampler = Sampler::new(TextAudit::seed(self.claim.index));
        (0..samples).all(|_| {
            let d = TextDerivation::new(self.claim, self.ctx, self.ctx.sample(&mut sampler));
            let Printed::Evaluated(p) = d.printed_term(&term) else {
                return false;
            };
            let t = truth(&d);
            let conventions = self.claim.conventions.len();
            let t = match target {
                0 => t,
                k if k <= conventions => d.conventions().swap_remove(k - 1).1,
                _ => {
                    let n = t.ncols();
                    DMatrix::from_fn(t.nrows(), n, |r, c| t[(r, (c + n / 2) % n)])
                }
            };
            agree(&p, &t)
        })
    }
}

/// `1, 2 and 3` for column indices (0-based in, 1-based out).
fn list(columns: &[usize]) -> String {
    let names: Vec<String> = columns.iter().map(|c| (c + 1).to_string()).collect();
    match names.as_slice() {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// Searches the edits of `claim`'s printed formula (see the module
/// documentation), evaluating at most `budget` edited formulas; `samples`
/// is the audit's sample count, at which a fix is confirmed.
pub fn search(audit: &TextAudit, claim: &TextClaim, samples: usize, budget: usize) -> Searched {
    if nodes(&claim.printed_ast).len() > MAX_SEARCHED_NODES {
        return Searched {
            diagnosis: None,
            evaluated: 0,
        };
    }
    let ctx = &audit.contexts[claim.context];
    let mut sampler = Sampler::new(TextAudit::seed(claim.index));
    let derivations: Vec<TextDerivation<'_>> = (0..samples.clamp(1, SEARCH_SAMPLES))
        .map(|_| TextDerivation::new(claim, ctx, ctx.sample(&mut sampler)))
        .collect();
    let targets = targets(claim, &derivations);
    let mut s = Search {
        claim,
        ctx,
        root: claim.printed_ast.clone(),
        derivations,
        targets,
        evaluated: 0,
        budget: budget.min(MAX_CANDIDATES),
    };
    let printed_good = match s.score(&claim.printed, true) {
        Outcome::Columns(good) => good.len(),
        _ => 0,
    };
    let singles = candidates(&s.root, ctx, claim);
    let diagnosis = diagnose(&mut s, &singles, printed_good, samples);
    Searched {
        diagnosis,
        evaluated: s.evaluated,
    }
}

/// Singles, then pairs, then the best partial fix.
fn diagnose(
    s: &mut Search<'_>,
    singles: &[Edit],
    printed_good: usize,
    samples: usize,
) -> Option<Diagnosis> {
    let claim = s.claim;
    let mut fixes: Vec<(Vec<&Edit>, usize, Expr)> = Vec::new();
    let mut best: Option<(Vec<usize>, &Edit, Expr)> = None;
    for edit in singles {
        if s.evaluated >= s.budget {
            break;
        }
        match s.try_edits(&[edit], true) {
            (Outcome::Agrees(t), Some(e)) => fixes.push((vec![edit], t[0], e)),
            (Outcome::Columns(good), Some(e))
                if good.len() > printed_good
                    && best.as_ref().is_none_or(|(b, ..)| good.len() > b.len()) =>
            {
                best = Some((good, edit, e));
            }
            _ => {}
        }
    }
    if fixes.is_empty() {
        'pairs: for (i, a) in singles.iter().enumerate() {
            for b in &singles[i + 1..] {
                if s.evaluated >= s.budget {
                    break 'pairs;
                }
                let (sa, sb) = (a.site(), b.site());
                if sa.starts_with(&sb) || sb.starts_with(&sa) {
                    continue;
                }
                if let (Outcome::Agrees(t), Some(e)) = s.try_edits(&[a, b], false) {
                    fixes.push((vec![a, b], t[0], e));
                    if fixes.len() >= MAX_FIXES_SHOWN {
                        break 'pairs;
                    }
                }
            }
        }
    }
    // The fewest edits, the truth before the alternatives; confirmed at
    // every sample of the audit.
    fixes.sort_by_key(|(edits, target, _)| (edits.len(), *target));
    // Edits that print the same formula (deleting one of two equal rows)
    // are one fix.
    let mut seen: Vec<&Expr> = Vec::new();
    let confirmed: Vec<&(Vec<&Edit>, usize, Expr)> = fixes
        .iter()
        .filter(|(_, _, e)| {
            let new = !seen.contains(&e);
            seen.push(e);
            new
        })
        .filter(|(_, target, e)| s.confirm(e, *target, samples))
        .take(MAX_FIXES_SHOWN)
        .collect();
    let root = &s.root;
    if let Some((edits, _, edited)) = confirmed.first() {
        let said: Vec<String> = confirmed
            .iter()
            .map(|(edits, target, _)| {
                let mut words: Vec<String> = edits.iter().map(|e| e.describe(root)).collect();
                if let Some(name) = &s.targets[*target].name {
                    words.push(format!("then it is right {name}"));
                }
                words.join(", and ")
            })
            .collect();
        return Some(Diagnosis {
            words: said.join("; or "),
            corrected: claim.with_rhs(edited),
            complete: true,
            edits: edits.len(),
        });
    }
    let (good, edit, edited) = best?;
    let columns = s.targets[0].at[0].ncols();
    let wrong: Vec<usize> = (0..columns).filter(|c| !good.contains(c)).collect();
    let plural = |v: &[usize]| if v.len() > 1 { "s" } else { "" };
    Some(Diagnosis {
        words: format!(
            "{} (then column{} {} agree{}; column{} {} {} still wrong)",
            edit.describe(root),
            plural(&good),
            list(&good),
            if good.len() > 1 { "" } else { "s" },
            plural(&wrong),
            list(&wrong),
            if wrong.len() > 1 { "are" } else { "is" }
        ),
        corrected: claim.with_rhs(&edited),
        complete: false,
        edits: 1,
    })
}
