//! The edits the erratum search tries on a printed formula's syntax tree
//! (the edit space is listed in [`super::errata`]): generating them, applying
//! them by path, and saying each in words about the formula as printed.

use doc_latex::ast::{self, Expr, MulOp, PostfixOp, Sign};

use super::claims::TextClaim;
use super::context::Context;
use super::lower::{number, symbol_key};
use super::term::Meaning;
use super::tree::{Path, at, at_mut, nodes};
// Where they were before they moved to `tree` (the public API stays).
pub use super::tree::{MAX_NEARBY_TERMS, nearby_terms};

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
    /// The node inverted (`x` to `x^{-1}`), or its inverse undone.
    Invert(Path),
    /// A parenthesis misplaced in a sum whose last term is a product:
    /// `(a − b c)` read as `(a − b) c`.
    Regroup(Path),
    /// A term printed elsewhere on the formula's display added to the node
    /// (`−p × ω` to `−p × ω + v` when the chain's other sides have `+ v`;
    /// before a lone subtracted term, `−x` to `a − x`).
    AddTerm {
        /// The node (a sum gets the term as its last).
        path: Path,
        /// The term, `Neg` for a subtracted one.
        term: Box<Expr>,
        /// Put it first (before a lone subtracted term: `−x` to `a − x`).
        first: bool,
    },
    /// The node multiplied by a constant.
    Scale {
        /// The node.
        path: Path,
        /// The constant (2 or ½).
        by: f64,
    },
}

/// `path` extended by child `i`.
fn child(path: &Path, i: usize) -> Path {
    let mut p = path.clone();
    p.push(i);
    p
}

impl Edit {
    /// The node it changes (an edit of a list's item names the item).
    pub fn site(&self) -> Path {
        match self {
            Edit::Negate(p)
            | Edit::Invert(p)
            | Edit::Regroup(p)
            | Edit::Exponent { path: p, .. }
            | Edit::SymbolExponent { path: p, .. }
            | Edit::Transpose(p)
            | Edit::Replace { path: p, .. }
            | Edit::Scale { path: p, .. }
            | Edit::AddTerm { path: p, .. }
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
    pub fn apply(&self, root: &mut Expr) -> bool {
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
            // An exponent 1 is not printed: `x^2` corrected to `x`.
            Edit::Exponent { to, .. } => match node {
                Expr::Power { base, .. } if *to == 1.0 => {
                    let base = std::mem::replace(base.as_mut(), Expr::Placeholder);
                    *node = base;
                    true
                }
                Expr::Power { exponent, .. } => {
                    **exponent = number_expr(*to);
                    true
                }
                _ => false,
            },
            Edit::SymbolExponent { to, .. } => match node {
                Expr::Symbol(s) => {
                    s.sup = (*to != 1.0).then(|| Box::new(number_expr(*to)));
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
            Edit::AddTerm { term, first, .. } => {
                let (sign, t) = match term.as_ref() {
                    Expr::Neg(x) => (Sign::Minus, x.as_ref().clone()),
                    other => (Sign::Plus, other.clone()),
                };
                match node {
                    Expr::Sum { rest, .. } => rest.push((sign, t)),
                    // `−x` missing the term before it: `a − x`.
                    Expr::Neg(_) if *first => {
                        let Expr::Neg(x) = std::mem::replace(node, Expr::Placeholder) else {
                            unreachable!("matched")
                        };
                        let first = match sign {
                            Sign::Plus => t,
                            Sign::Minus => Expr::Neg(Box::new(t)),
                        };
                        *node = Expr::Sum {
                            first: Box::new(first),
                            rest: vec![(Sign::Minus, *x)],
                        };
                    }
                    _ => {
                        let old = std::mem::replace(node, Expr::Placeholder);
                        *node = Expr::Sum {
                            first: Box::new(old),
                            rest: vec![(sign, t)],
                        };
                    }
                }
                true
            }
            Edit::Scale { by, .. } => {
                let old = std::mem::replace(node, Expr::Placeholder);
                *node = Expr::Product {
                    first: Box::new(number_expr(*by)),
                    rest: vec![(MulOp::Implicit, old)],
                };
                true
            }
            Edit::Invert(_) => {
                let old = std::mem::replace(node, Expr::Placeholder);
                *node = match old {
                    Expr::Power { base, exponent } if number(&exponent) == Some(-1.0) => *base,
                    other => Expr::Power {
                        base: Box::new(other),
                        exponent: Box::new(number_expr(-1.0)),
                    },
                };
                true
            }
            Edit::Regroup(_) => match regrouped(node) {
                Some(e) => {
                    *node = e;
                    true
                }
                None => false,
            },
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
            Edit::Invert(p) => match at(root, p) {
                Some(Expr::Power { base, exponent }) if number(exponent) == Some(-1.0) => {
                    format!("`{}` should not be inverted", plain(&base.to_string()))
                }
                _ => format!("`{}` should be inverted", show(p)),
            },
            Edit::Regroup(p) => match at(root, p).and_then(regrouped) {
                Some(e) => format!(
                    "a parenthesis is misplaced: `{}` should read `{}`",
                    show(p),
                    plain(&e.to_string())
                ),
                None => "a parenthesis is misplaced".into(),
            },
            Edit::AddTerm { path, term, .. } => {
                let written = match term.as_ref() {
                    Expr::Neg(x) => format!("− {}", plain(&x.to_string())),
                    other => format!("+ {}", plain(&other.to_string())),
                };
                if path.is_empty() {
                    format!("the term `{written}` is missing")
                } else {
                    format!("the term `{written}` is missing after `{}`", show(path))
                }
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

/// `(a − b c)` as `(a − b) c`: a sum whose last term is a product of at
/// least two factors, with that product's last factor taken out.
fn regrouped(e: &Expr) -> Option<Expr> {
    let Expr::Sum { first, rest } = e else {
        return None;
    };
    let (sign, last) = rest.last()?;
    let Expr::Product {
        first: f0,
        rest: factors,
    } = last
    else {
        return None;
    };
    let ((op, outside), inside) = factors.split_last()?;
    if *op != MulOp::Implicit {
        return None;
    }
    let kept = if inside.is_empty() {
        f0.as_ref().clone()
    } else {
        Expr::Product {
            first: f0.clone(),
            rest: inside.to_vec(),
        }
    };
    let mut terms = rest[..rest.len() - 1].to_vec();
    terms.push((*sign, kept));
    Some(Expr::Product {
        first: Box::new(Expr::Sum {
            first: first.clone(),
            rest: terms,
        }),
        rest: vec![(MulOp::Implicit, outside.clone())],
    })
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
        if matches!(node, Expr::Symbol(_) | Expr::Apply { .. })
            || matches!(node, Expr::Power { exponent, .. } if number(exponent) == Some(-1.0))
        {
            out.push(Edit::Invert(path.clone()));
        }
        if regrouped(node).is_some() {
            out.push(Edit::Regroup(path.clone()));
        }
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

/// Missing terms: each of `terms` added to the right side, to each of its
/// sums, before each of its subtracted terms and to each entry of its
/// matrices.
pub fn additions(root: &Expr, terms: &[Expr]) -> Vec<Edit> {
    // The whole right side gets the term last (`−p × ω` to `−p × ω + v`);
    // a subtracted term inside it, first (`(−x)` to `(a − x)`).
    let mut sites: Vec<(Path, bool)> = vec![(Vec::new(), false)];
    for (path, node) in nodes(root) {
        match node {
            Expr::Sum { .. } if !path.is_empty() => sites.push((path, false)),
            Expr::Neg(_) if !path.is_empty() => sites.push((path, true)),
            Expr::Matrix(m) => {
                let cells = m.rows.iter().map(Vec::len).sum::<usize>();
                sites.extend((0..cells).map(|k| (child(&path, k), false)));
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    for (site, first) in &sites {
        for t in terms {
            out.push(Edit::AddTerm {
                path: site.clone(),
                term: Box::new(t.clone()),
                first: *first,
            });
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

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(latex: &str) -> Expr {
        doc_latex::parse_expr(latex).expect("LaTeX")
    }

    fn path_of(root: &Expr, latex: &str) -> Path {
        nodes(root)
            .into_iter()
            .find(|(_, n)| n.to_string() == latex)
            .map(|(p, _)| p)
            .unwrap_or_else(|| panic!("no {latex} in {root}"))
    }

    #[test]
    fn an_exponent_edit_is_applied_and_said() {
        let root = parse("\\frac{1}{|y|} I - \\frac{1}{|y|^{\\frac{3}{2}}} y y^T");
        let path = path_of(&root, "\\left| y \\right|^{\\frac{3}{2}}");
        let edit = Edit::Exponent {
            path,
            from: 1.5,
            to: 3.0,
        };
        assert_eq!(edit.describe(&root), "exponent 3/2 of |y| should be 3");
        let mut edited = root.clone();
        assert!(edit.apply(&mut edited));
        assert_eq!(
            edited.to_string(),
            "\\frac{1}{\\left| y \\right|} I - \\frac{1}{\\left| y \\right|^{3}} y y^{T}"
        );
    }

    #[test]
    fn deleting_the_first_term_keeps_the_sign_of_the_next() {
        let root = parse("a - b + c");
        let mut edited = root.clone();
        let edit = Edit::DeleteTerm {
            sum: Vec::new(),
            term: 0,
        };
        assert!(edit.apply(&mut edited));
        assert_eq!(edited.to_string(), "-b + c");
        assert_eq!(edit.describe(&root), "the term `a` should not be there");
        // An edit whose place is gone does not apply.
        assert!(
            !Edit::FlipTerm {
                sum: vec![9],
                term: 1
            }
            .apply(&mut edited)
        );
    }

    #[test]
    fn numbers_are_printed_as_fractions() {
        assert_eq!(fraction(1.5), "3/2");
        assert_eq!(number_expr(-0.5).to_string(), "-\\frac{1}{2}");
        assert_eq!(exponents(1.5), [2.5, 0.5, 3.0, 0.75, -1.5]);
    }
}
