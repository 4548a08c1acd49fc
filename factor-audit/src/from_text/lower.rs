//! LaTeX (the `doc-latex` syntax tree) lowered to a [`Term`]: every symbol
//! resolved through the symbols file, every piece of notation given its
//! meaning, or an error naming the fragment that has none.
//!
//! Readings a symbol table does not spell out:
//! - a superscript that is no defined symbol's is a power when it is a
//!   number (`P_z^2`) or a power of a defined index (`l_i^{1^2}`);
//! - any printed expression the file defines as a name (`\pi'(q)`, `u v`)
//!   is that name;
//! - `I`, `\mathbf{I}`, `\mathbb{I}`, `\mathds{1}`, with or without a size
//!   (`I_3`, `I_{3×3}`), is the identity unless the file defines it; `0`,
//!   `\mathbf{0}`, `0^T`, `0_{3×1}` inside a matrix are zero blocks (and
//!   `\mathbf{0}`, `0_{3×1}` anywhere);
//! - a function symbol before a factor applies to it (`J_l^{-1}\left(\phi\right)`,
//!   `f^{-1}` its inverse), and `f(\cdot)` is `f`;
//! - a function name with a subscript and no argument (`Ad_T`, `ad_\xi`) is
//!   the function of its subscript; with an argument, it acts on it;
//! - operators and words the file defines (`\boxminus`, `p^\odot`,
//!   `between(a, b)`) are its templates;
//! - `f(x)` is an application when `f` is a function symbol, `f` itself
//!   when every argument is a variable or tangent symbol (`T(ξ)`,
//!   `E(ξ, ω)`), and a product otherwise;
//! - `\frac{X}{δξ}` over a tangent symbol is a difference quotient: the
//!   linear map `δξ ↦ X` (X must be affine in the tangent's parts);
//! - a derivative `\frac{∂a}{∂b}` inside a formula is the printed formula
//!   of the claim of the file that states it (a chain rule's link).

use std::collections::HashSet;

use doc_latex::ast::{self, Base, Expr, Head, MulOp, PostfixOp, Rel, Sign};
use doc_latex::render::mulop_latex;

use super::functions::Builtin;
use super::term::{Op, SymbolId, Term};

/// A fragment that cannot be lowered, and why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message} at `{fragment}`")]
pub struct LowerError {
    /// What is wrong.
    pub message: String,
    /// The fragment, as canonical LaTeX (at most 60 characters).
    pub fragment: String,
}

impl LowerError {
    /// An error about `e`.
    pub fn at(e: &Expr, message: impl Into<String>) -> Self {
        LowerError {
            message: message.into(),
            fragment: short(&e.to_string()),
        }
    }
}

/// `s` cut to 60 characters.
pub fn short(s: &str) -> String {
    let mut out: String = s.chars().take(60).collect();
    if s.chars().count() > 60 {
        out.push('…');
    }
    out
}

/// What a symbol found in scope is, as far as lowering needs to know.
#[derive(Debug, Clone, PartialEq)]
pub enum Found {
    /// A function symbol.
    Function(Builtin),
    /// A function symbol defined by LaTeX (a template).
    Template(usize),
    /// A tangent, with the symbols of its parts.
    Tangent(Vec<SymbolId>),
    /// A stored value (a field or a free variable); `group` when it is a
    /// rotation, pose or another group element.
    Stored {
        /// Whether it is a group element.
        group: bool,
    },
    /// A definition, a component, a residual or a bound name.
    Value,
}

/// What a symbol before a parenthesised group was read as.
enum Application {
    /// A function applied to the group.
    Call(Term),
    /// The symbol written with its variables (`T(ξ)`).
    Written(Term),
    /// A value multiplying the group: the value.
    Product(Term),
}

/// What a derivative in a chain rule stands for.
#[derive(Debug, Clone, PartialEq)]
pub enum Link {
    /// The printed formula of this claim of the file.
    Claim(usize),
    /// The true derivative of this link the file states in words.
    Truth(usize),
    /// A link stated in words that cannot be read, and why.
    Broken(String),
}

/// A derivative printed in a formula that no claim or stated link names.
pub struct PrintedDerivative<'a> {
    /// Its canonical LaTeX.
    pub key: &'a str,
    /// The map.
    pub of: &'a Expr,
    /// The variable.
    pub wrt: &'a Expr,
    /// The other variables it holds (a partial).
    pub holding: &'a [Expr],
    /// The symbols evaluation bars around it bind to values.
    pub bound: &'a [(SymbolId, Term)],
    /// Taken at `wrt = 0` (an evaluation bar says so).
    pub at_zero: bool,
}

/// Where lowering looks symbols, chain-rule links and templates up.
pub trait Resolver {
    /// The symbol whose canonical LaTeX is `key`, in scope (its definition
    /// lowered first); `Ok(None)` when none is.
    fn symbol(&mut self, key: &str) -> Result<Option<(SymbolId, Found)>, LowerError>;
    /// What the derivative written `key` stands for.
    fn link(&self, key: &str) -> Option<Link>;
    /// A derivative printed in a formula that no claim or stated link
    /// names: its true value, when its map and variable can be read.
    fn inline_link(&mut self, d: PrintedDerivative<'_>) -> Result<Link, LowerError> {
        Err(LowerError {
            message: "no new derivative is read here".into(),
            fragment: d.key.to_string(),
        })
    }
    /// The template (and its number of arguments) an operator, word or
    /// symbol written `key` names (its body lowered first).
    fn template(&mut self, key: &str) -> Result<Option<(usize, usize)>, LowerError>;
    /// Whether the symbols file states JPL quaternions (`⊗` and
    /// `rotation(q)` in JPL's convention).
    fn jpl_quaternions(&self) -> bool {
        false
    }
    /// The symbols of the file whose keys cannot be read, with why (an
    /// undefined symbol may be one of them).
    fn unreadable_symbols(&self) -> &[String] {
        &[]
    }
    /// Whether template `t`'s printed subscript is its first argument.
    fn subscripted(&self, t: usize) -> bool {
        let _ = t;
        false
    }
}

/// One lowering, with the reading options of the formula.
pub struct Lowering<'r> {
    resolver: &'r mut dyn Resolver,
    /// Read fractions with a non-scalar above the bar as stacks.
    pub stacked_fractions: bool,
    /// Read a name no symbol has as the claim that states it (`D_2 g(ξ)`);
    /// off for a claim's own left side.
    pub names_claims: bool,
    /// What a reader should know of how the formula was read (a zero
    /// block's printed size overridden by its row and column).
    pub notes: Vec<String>,
    /// For each map the formula differentiates (its canonical LaTeX), the
    /// variables it differentiates it by: a partial by one holds the others.
    partials: Vec<(String, Vec<Expr>)>,
    /// The symbols the evaluation bars around the term being lowered bind,
    /// with their values: a derivative inside a bar is taken with them.
    bars: Vec<(SymbolId, Term)>,
}

/// The canonical LaTeX of a symbol: the key of the symbols file.
pub fn symbol_key(s: &ast::Symbol) -> String {
    Expr::Symbol(s.clone()).to_string()
}

/// The bindings of an evaluation bar's subscript: `x = a = b` (the name
/// and its printed values), several separated by commas or in the rows of
/// a `subarray`.
pub fn evaluation_bindings(at: &Expr) -> Result<Vec<(Expr, Vec<Expr>)>, LowerError> {
    let items: Vec<&Expr> = match at {
        Expr::Tuple(items) => items.iter().collect(),
        Expr::Matrix(m) => m.rows.iter().flatten().collect(),
        one => vec![one],
    };
    items
        .into_iter()
        .map(|item| match item {
            Expr::Relation { first, rest } if rest.iter().all(|(r, _)| *r == Rel::Eq) => Ok((
                first.as_ref().clone(),
                rest.iter().map(|(_, v)| v.clone()).collect(),
            )),
            other => Err(LowerError::at(
                other,
                "an evaluation bar's subscript is `name = value`, or several of them",
            )),
        })
        .collect()
}

/// Whether `e` is a printed zero (`0`, `\mathbf{0}`, `0_3`).
fn is_zero(e: &Expr) -> bool {
    zero_block(e).is_some()
}

/// Whether `s` is a plain `e` (a superscript aside): Euler's number where
/// the file gives it no meaning.
fn is_bare_e(s: &ast::Symbol) -> bool {
    s.base == ast::Base::Letter('e')
        && s.font == ast::Font::Plain
        && s.accent.is_none()
        && s.delta.is_none()
        && s.primes == 0
        && s.sup_primes == 0
        && s.sub.is_none()
        && s.pre_sub.is_none()
        && s.pre_sup.is_none()
}

/// The number `e` is, if it is one (`2`, `-1`, `\frac{3}{2}`, `1 + 1`).
pub fn number(e: &Expr) -> Option<f64> {
    match e {
        Expr::Number(n) => n.parse().ok().filter(|x: &f64| x.is_finite()),
        Expr::Neg(x) => number(x).map(|x| -x),
        Expr::Pos(x) => number(x),
        Expr::Fraction { num, den } => Some(number(num)? / number(den)?).filter(|x| x.is_finite()),
        Expr::Sum { .. } => e.terms().iter().try_fold(0.0, |acc, (sign, t)| {
            let x = number(t)?;
            Some(if *sign == Sign::Minus {
                acc - x
            } else {
                acc + x
            })
        }),
        _ => None,
    }
}

impl<'r> Lowering<'r> {
    /// A lowering resolving through `resolver`.
    pub fn new(resolver: &'r mut dyn Resolver, stacked_fractions: bool) -> Self {
        Lowering {
            resolver,
            stacked_fractions,
            names_claims: true,
            notes: Vec::new(),
            partials: Vec::new(),
            bars: Vec::new(),
        }
    }

    /// The same lowering, reading no name as another claim (for a claim's
    /// own left side, which names itself).
    pub fn without_claim_names(mut self) -> Self {
        self.names_claims = false;
        self
    }

    /// A formula lowered: the partials it prints of one map each hold the
    /// map's other printed variables (`∂g/∂x + ∂g/∂r ∂r/∂x`).
    pub fn formula(&mut self, e: &Expr) -> Result<Term, LowerError> {
        self.partials.clear();
        for d in super::tree::derivatives(e) {
            if let Expr::Derivative { of, wrt, .. } = d {
                let key = of.to_string();
                match self.partials.iter_mut().find(|(k, _)| *k == key) {
                    Some((_, wrts)) if !wrts.contains(wrt) => wrts.push(wrt.as_ref().clone()),
                    Some(_) => {}
                    None => self.partials.push((key, vec![wrt.as_ref().clone()])),
                }
            }
        }
        self.expr(e)
    }

    /// `e` lowered.
    pub fn expr(&mut self, e: &Expr) -> Result<Term, LowerError> {
        // A key of the file is what it means, whatever it prints
        // (`\mathbf{M}^{-1}`, `e^{-v}`, `\mathbf{p} \cdot \mathbf{d}`).
        if !matches!(e, Expr::Number(_) | Expr::Symbol(_) | Expr::Placeholder)
            && let Some((id, found)) = self.resolver.symbol(&e.to_string())?
        {
            return match found {
                Found::Function(_) | Found::Template(_) => Err(LowerError::at(
                    e,
                    "this is a function symbol: apply it to an argument",
                )),
                _ => Ok(Term::Symbol(id)),
            };
        }
        // A name that cannot be read otherwise but another claim states
        // (`D_2 g(ξ)` in a chain of differentials): that claim's printed
        // formula.
        let linked = match (self.names_claims && (is_name_like(e) || is_applied_product(e)))
            .then(|| self.resolver.link(&e.to_string()))
            .flatten()
        {
            Some(Link::Claim(k)) => Some(k),
            _ => None,
        };
        match (self.parts(e), linked) {
            (Err(_), Some(k)) => Ok(Term::Link(k)),
            (lowered, _) => lowered,
        }
    }

    /// `e` lowered by its parts.
    fn parts(&mut self, e: &Expr) -> Result<Term, LowerError> {
        Ok(match e {
            Expr::Number(_) => {
                Term::Number(number(e).ok_or_else(|| LowerError::at(e, "not a number"))?)
            }
            Expr::Symbol(s) => self.symbol(s, e)?,
            Expr::Text(t) => {
                return Err(LowerError::at(
                    e,
                    format!("the text `{t}` is not a quantity"),
                ));
            }
            Expr::Placeholder => return Err(LowerError::at(e, "a placeholder is not a quantity")),
            Expr::Ellipsis => {
                return Err(LowerError::at(
                    e,
                    "an ellipsis stands for what the formula does not print (more blocks, more \
                     terms): it cannot be evaluated",
                ));
            }
            Expr::Neg(x) => Term::Neg(Box::new(self.expr(x)?)),
            Expr::Pos(x) => self.expr(x)?,
            Expr::Sum { .. } => Term::Sum(
                e.terms()
                    .into_iter()
                    .map(|(sign, t)| Ok((sign == Sign::Minus, self.expr(t)?)))
                    .collect::<Result<_, LowerError>>()?,
            ),
            Expr::Product { first, rest } => self.product(first, rest)?,
            Expr::Fraction { num, den } => self.fraction(num, den)?,
            Expr::Derivative { of, wrt, .. } => {
                let key = e.to_string();
                let mut holding: Vec<Expr> = self
                    .partials
                    .iter()
                    .find(|(k, _)| *k == of.to_string())
                    .map(|(_, wrts)| {
                        wrts.iter()
                            .filter(|w| *w != wrt.as_ref())
                            .cloned()
                            .collect()
                    })
                    .unwrap_or_default();
                holding.extend(written_arguments_held(of, wrt));
                let link = match self.resolver.link(&key) {
                    Some(link) => link,
                    None => self
                        .resolver
                        .inline_link(PrintedDerivative {
                            key: &key,
                            of,
                            wrt,
                            holding: &holding,
                            bound: &self.bars,
                            at_zero: false,
                        })
                        .map_err(|err| {
                            LowerError::at(
                                e,
                                format!(
                                    "this derivative is no claim of the symbols file, and what it \
                                 prints cannot be differentiated: {} (add a claim, with `lhs` \
                                 if it is printed differently there, or a \
                                 `[[context.NAME.link]]`)",
                                    err.message
                                ),
                            )
                        })?,
                };
                match link {
                    Link::Claim(k) => Term::Link(k),
                    Link::Truth(k) => Term::TruthLink(k),
                    Link::Broken(why) => {
                        return Err(LowerError::at(
                            e,
                            format!(
                                "the link the symbols file states for it cannot be read: {why}"
                            ),
                        ));
                    }
                }
            }
            Expr::Differential(_) => {
                return Err(LowerError::at(
                    e,
                    "a differential `∂x` outside a derivative is not evaluated",
                ));
            }
            Expr::Limit { under, body } => self.limit(under, body, e)?,
            Expr::Sqrt { index, body } => {
                let body = self.expr(body)?;
                match index {
                    None => Term::Call(Builtin::Sqrt, vec![body]),
                    Some(n) => {
                        let n = number(n)
                            .filter(|n| *n != 0.0)
                            .ok_or_else(|| LowerError::at(e, "the root's index is not a number"))?;
                        Term::Power(Box::new(body), 1.0 / n)
                    }
                }
            }
            Expr::Norm { body, .. } => Term::Norm(Box::new(self.expr(body)?)),
            Expr::Skew(x) => Term::Hat(Box::new(self.expr(x)?)),
            Expr::Apply {
                head,
                args,
                scripts: None,
            } => self.apply(head, args, e)?,
            Expr::Apply {
                head,
                args,
                scripts: Some(chain),
            } => self.scripted_application(head, args, chain, e)?,
            Expr::Power { base, exponent } => {
                let p = number(exponent)
                    .ok_or_else(|| LowerError::at(e, "the exponent is not a number"))?;
                match base.as_ref() {
                    // `e^{-1}`: the exponential, when the file gives `e` no
                    // meaning.
                    Expr::Symbol(s)
                        if is_bare_e(s)
                            && s.sup.is_none()
                            && self.resolver.symbol(&symbol_key(s))?.is_none() =>
                    {
                        Term::Call(Builtin::Exp, vec![Term::Number(p)])
                    }
                    _ => Term::Power(Box::new(self.expr(base)?), p),
                }
            }
            Expr::Postfix { base, op } => {
                if *op == PostfixOp::Transpose && zero_block(base).is_some() {
                    // `0^T`: a zero row, sized where it is used.
                    return Ok(Term::Zero);
                }
                let lowered = Box::new(self.expr(base)?);
                match op {
                    PostfixOp::Transpose => Term::Transpose(lowered),
                    PostfixOp::Hat => Term::Hat(lowered),
                    PostfixOp::Vee => Term::Vee(lowered),
                    PostfixOp::Operator(name) => {
                        let key = match *name {
                            c @ ("*" | "+") => format!("^{c}"),
                            other => format!("^\\{other}"),
                        };
                        match self.resolver.template(&key)? {
                            Some((t, 1)) => Term::Template(t, vec![*lowered]),
                            Some(_) => {
                                return Err(LowerError::at(
                                    e,
                                    format!(
                                        "the operator `{key}` takes one argument in the symbols file"
                                    ),
                                ));
                            }
                            None => {
                                return Err(LowerError::at(
                                    e,
                                    format!(
                                        "the operator `{key}` has no meaning: define it in the \
                                         context's `operators`"
                                    ),
                                ));
                            }
                        }
                    }
                }
            }
            Expr::Indexed { base, index } if zero_block(base).is_some() => match number(index) {
                Some(n) if n.fract() == 0.0 && n >= 1.0 => {
                    Term::Shaped(Box::new(Term::Zero), (n as usize, 1))
                }
                _ => {
                    return Err(LowerError::at(
                        e,
                        "a zero's subscript is its size (`0_3`, `0_{3 \\times 1}`)",
                    ));
                }
            },
            Expr::Indexed { .. } => {
                return Err(LowerError::at(
                    e,
                    "a subscript on an expression is not evaluated (define a symbol for it)",
                ));
            }
            Expr::Shaped { base, rows, cols } if zero_block(base).is_some() => {
                Term::Shaped(Box::new(Term::Zero), (*rows as usize, *cols as usize))
            }
            Expr::Shaped { base, rows, cols } => {
                Term::Shaped(Box::new(self.expr(base)?), (*rows as usize, *cols as usize))
            }
            Expr::Primed { .. } => {
                return Err(LowerError::at(
                    e,
                    "primes on an expression are not evaluated",
                ));
            }
            Expr::Tuple(items) => Term::Stack(
                items
                    .iter()
                    .map(|x| self.expr(x))
                    .collect::<Result<_, _>>()?,
            ),
            Expr::Matrix(m) => Term::Blocks(
                m.rows
                    .iter()
                    .map(|row| {
                        row.iter()
                            .map(|x| match printed_zero(x) {
                                Some((None, None)) => Ok(Term::Zero),
                                Some((rows, cols)) => {
                                    let note = format!(
                                        "`{x}` is a zero block sized by its block row and \
                                         column (its printed size only where they do not tell)"
                                    );
                                    if !self.notes.contains(&note) {
                                        self.notes.push(note);
                                    }
                                    Ok(Term::BlockZero(rows, cols))
                                }
                                None => self.expr(x),
                            })
                            .collect()
                    })
                    .collect::<Result<_, _>>()?,
            ),
            Expr::Cases(_) => {
                return Err(LowerError::at(
                    e,
                    "a `cases` is evaluated only as a whole right side, one case chosen with `case`",
                ));
            }
            Expr::Relation { .. } => {
                return Err(LowerError::at(
                    e,
                    "a relation inside a formula is not a value",
                ));
            }
            Expr::At { body, at } => self.evaluated_at(body, at, e)?,
        })
    }

    /// `\left. X \right|_{x = a, …}`: a derivative `X` by `x` at `x = 0`
    /// is taken at zero; otherwise `X` with the bound symbols given the
    /// printed values (a name the file does not define is defined by the
    /// bar, as the claim's own reading).
    fn evaluated_at(&mut self, body: &Expr, at: &Expr, e: &Expr) -> Result<Term, LowerError> {
        // `\left. -\frac{∂X}{∂x} \right|_{x = 0}`: the negated derivative
        // at the point.
        if let Expr::Neg(inner) = body
            && matches!(inner.as_ref(), Expr::Derivative { .. })
        {
            let bar = Expr::At {
                body: inner.clone(),
                at: Box::new(at.clone()),
            };
            return Ok(Term::Neg(Box::new(self.evaluated_at(inner, at, &bar)?)));
        }
        let bindings = evaluation_bindings(at)?;
        let wrt = match body {
            Expr::Derivative { wrt, .. } => Some(wrt.as_ref()),
            _ => None,
        };
        let bound = self.bar_bindings(&bindings, wrt)?;
        let depth = self.bars.len();
        self.bars.extend(bound.iter().cloned());
        let body = self.bar_body(body, &bindings, e);
        self.bars.truncate(depth);
        let body = body?;
        Ok(if bound.is_empty() {
            body
        } else {
            Term::At {
                body: Box::new(body),
                bindings: bound,
            }
        })
    }

    /// The symbols an evaluation bar's `bindings` give values (the last
    /// printed: `A = e^0 D = D`), but the variable `wrt` a derivative is
    /// taken by (that binding is its point, not a value to hold), and
    /// names no symbol has.
    fn bar_bindings(
        &mut self,
        bindings: &[(Expr, Vec<Expr>)],
        wrt: Option<&Expr>,
    ) -> Result<Vec<(SymbolId, Term)>, LowerError> {
        let mut bound = Vec::new();
        for (name, values) in bindings {
            if Some(name) == wrt {
                continue;
            }
            let key = match name {
                Expr::Symbol(s) => symbol_key(s),
                other => other.to_string(),
            };
            let Some((id, _)) = self.resolver.symbol(&key)? else {
                continue;
            };
            let value = values.last().expect("a binding has a value");
            bound.push((id, self.expr(value)?));
        }
        Ok(bound)
    }

    /// `of`, the map a derivative by `wrt` under the evaluation bar `at`
    /// differentiates, with the bar's other bindings
    /// (`\left. \frac{∂ A B}{∂ B} \right|_{A = D}`: `D B`).
    pub fn map_under_bar(&mut self, of: &Expr, wrt: &Expr, at: &Expr) -> Result<Term, LowerError> {
        let bound = self.bar_bindings(&evaluation_bindings(at)?, Some(wrt))?;
        let of = self.expr(of)?;
        Ok(if bound.is_empty() {
            of
        } else {
            Term::At {
                body: Box::new(of),
                bindings: bound,
            }
        })
    }

    /// The body of an evaluation bar whose `bindings` (and those around it)
    /// are in `self.bars`: a derivative by `x` at `x = 0` is taken at zero.
    fn bar_body(
        &mut self,
        body: &Expr,
        bindings: &[(Expr, Vec<Expr>)],
        e: &Expr,
    ) -> Result<Term, LowerError> {
        if let Expr::Derivative { of, wrt, .. } = body {
            let at_zero = bindings
                .iter()
                .any(|(name, values)| name == wrt.as_ref() && values.iter().any(is_zero));
            if at_zero {
                let key = e.to_string();
                return Ok(match self.resolver.link(&key) {
                    Some(Link::Claim(k)) => Term::Link(k),
                    Some(Link::Truth(k)) => Term::TruthLink(k),
                    _ => match self.resolver.inline_link(PrintedDerivative {
                        key: &key,
                        of,
                        wrt,
                        holding: &[],
                        bound: &self.bars,
                        at_zero: true,
                    })? {
                        Link::Claim(k) => Term::Link(k),
                        Link::Truth(k) => Term::TruthLink(k),
                        Link::Broken(why) => return Err(LowerError::at(e, why)),
                    },
                });
            }
        }
        self.expr(body)
    }

    /// A symbol: defined, a power of a defined one, a zero, or the identity.
    fn symbol(&mut self, s: &ast::Symbol, e: &Expr) -> Result<Term, LowerError> {
        if let Some((id, found)) = self.resolver.symbol(&symbol_key(s))? {
            return match found {
                Found::Function(_) | Found::Template(_) => Err(LowerError::at(
                    e,
                    "this is a function symbol: apply it to an argument",
                )),
                _ => Ok(Term::Symbol(id)),
            };
        }
        if let Some(sup) = &s.sup {
            let (index, power) = match sup.as_ref() {
                Expr::Power { base, exponent } => (Some(base.as_ref().clone()), number(exponent)),
                other => (None, number(other)),
            };
            if let Some(p) = power {
                // `P_z^2`, `\hat{v}^2`: a power of what the symbol without
                // it is, when that is a value.
                let mut base = s.clone();
                base.sup = index.map(Box::new);
                let defined = self.resolver.symbol(&symbol_key(&base))?;
                match defined {
                    Some((id, Found::Stored { .. } | Found::Value)) => {
                        return Ok(Term::Power(Box::new(Term::Symbol(id)), p));
                    }
                    Some(_) => {}
                    None => {
                        if let Ok(t) = self.symbol(&base, &Expr::Symbol(base.clone())) {
                            return Ok(Term::Power(Box::new(t), p));
                        }
                    }
                }
            }
        }
        match zero_block(e) {
            Some(None) => return Ok(Term::Zero),
            Some(Some(shape)) => return Ok(Term::Shaped(Box::new(Term::Zero), shape)),
            None => {}
        }
        if let Some(size) = identity(s) {
            return size.map(Term::Identity).map_err(|m| LowerError::at(e, m));
        }
        // `\hat{v}` undefined: the accent as the file defines it (an
        // operator `\hat`), on the symbol without it.
        if let Some(accent) = s.accent {
            let key = format!("\\{}", accent_name(accent));
            if let Some((t, 1)) = self.resolver.template(&key)? {
                let bare = ast::Symbol {
                    accent: None,
                    ..s.clone()
                };
                let inner = self.symbol(&bare, &Expr::Symbol(bare.clone()))?;
                return Ok(Term::Template(t, vec![inner]));
            }
        }
        // `e^{x}`: the exponential, when the file gives `e` no meaning.
        if let Some(sup) = &s.sup
            && is_bare_e(s)
        {
            let bare = ast::Symbol {
                sup: None,
                ..s.clone()
            };
            if self.resolver.symbol(&symbol_key(&bare))?.is_none() {
                return Ok(Term::Call(Builtin::Exp, vec![self.expr(sup)?]));
            }
        }
        let unreadable = self.resolver.unreadable_symbols();
        Err(LowerError::at(
            e,
            if unreadable.is_empty() {
                "undefined symbol".to_string()
            } else {
                format!(
                    "undefined symbol (the symbols file's {} cannot be read)",
                    unreadable.join(", ")
                )
            },
        ))
    }

    /// A product: factors with their operators; a function symbol before a
    /// factor applies to it (`J_l^{-1}\left(\phi\right)`); operators the
    /// file defines are its templates.
    fn product(&mut self, first: &Expr, rest: &[(MulOp, Expr)]) -> Result<Term, LowerError> {
        let mut items: Vec<(MulOp, &Expr)> = vec![(MulOp::Implicit, first)];
        items.extend(rest.iter().map(|(op, x)| (*op, x)));
        let mut factors: Vec<(Op, Term)> = Vec::with_capacity(items.len());
        let mut i = 0;
        while i < items.len() {
            let (op, x) = items[i];
            // `g^{-1}(T, 0)` inside a longer product: a name the file gives
            // as a whole.
            if let Some(next) = items.get(i + 1).filter(|(o, _)| *o == MulOp::Implicit)
                && matches!(next.1, Expr::Tuple(_))
                && let Some(pair) = Some(Expr::Product {
                    first: Box::new(x.clone()),
                    rest: vec![(MulOp::Implicit, next.1.clone())],
                })
                && is_applied_product(&pair)
                && let Some((id, Found::Stored { .. } | Found::Value)) =
                    self.resolver.symbol(&pair.to_string())?
            {
                factors.push((self.operator(op, x)?, Term::Symbol(id)));
                i += 2;
                continue;
            }
            if let Some(next) = items.get(i + 1).filter(|(o, _)| *o == MulOp::Implicit)
                && let Some(applied) = self.applied(x, next.1)?
            {
                factors.push((self.operator(op, x)?, applied));
                i += 2;
                continue;
            }
            let custom = match op {
                MulOp::Implicit | MulOp::Cdot | MulOp::Star | MulOp::Slash => None,
                other => self.resolver.template(&mulop_latex(other))?,
            };
            match (custom, factors.pop()) {
                (Some((t, 2)), Some((before, left))) => {
                    // `a \boxminus b`: the template of the operator, between
                    // the factor before it and this one.
                    let right = self.expr(x)?;
                    factors.push((before, Term::Template(t, vec![left, right])));
                }
                (Some(_), previous) => {
                    factors.extend(previous);
                    return Err(LowerError::at(
                        x,
                        format!(
                            "the operator `{}` takes two arguments in the symbols file",
                            mulop_latex(op)
                        ),
                    ));
                }
                (None, previous) => {
                    factors.extend(previous);
                    factors.push((self.operator(op, x)?, self.expr(x)?));
                }
            }
            i += 1;
        }
        Ok(if factors.len() == 1 {
            factors.pop().expect("one factor").1
        } else {
            cross_of_products(factors)
        })
    }

    /// `f_{a}(args)` with `f` a function of the file whose subscript is an
    /// argument (`\Phi_{R_0}(θ)`): the application, else `None`.
    fn subscripted_template(
        &mut self,
        s: &ast::Symbol,
        args: &[Expr],
    ) -> Result<Option<Term>, LowerError> {
        let Some(sub) = &s.sub else {
            return Ok(None);
        };
        // A symbol of the file as printed (`x_n` beside a function `x`, or
        // in `x`'s own definition) is that symbol.
        if self.resolver.symbol(&symbol_key(s))?.is_some() {
            return Ok(None);
        }
        let bare = ast::Symbol {
            sub: None,
            ..s.clone()
        };
        let Some((_, Found::Template(t))) = self.resolver.symbol(&symbol_key(&bare))? else {
            return Ok(None);
        };
        if !self.resolver.subscripted(t) {
            return Ok(None);
        }
        let mut terms = vec![self.expr(sub)?];
        for a in args {
            terms.push(self.expr(a)?);
        }
        Ok(Some(Term::Template(t, terms)))
    }

    /// `f x` with `f` a function symbol (or its inverse `f^{-1}`): the
    /// application, else `None`.
    fn applied(&mut self, f: &Expr, x: &Expr) -> Result<Option<Term>, LowerError> {
        let (s, inverse) = match f {
            Expr::Symbol(s) => (s, false),
            Expr::Power { base, exponent } if number(exponent) == Some(-1.0) => match base.as_ref()
            {
                Expr::Symbol(s) => (s, true),
                _ => return Ok(None),
            },
            _ => return Ok(None),
        };
        if !inverse && let Some(call) = self.subscripted_template(s, std::slice::from_ref(x))? {
            return Ok(Some(call));
        }
        let arg = self.expr(x);
        Ok(match self.resolver.symbol(&symbol_key(s))? {
            Some((_, Found::Function(b))) => {
                let b = if inverse {
                    b.inverse().ok_or_else(|| {
                        LowerError::at(f, format!("`{}` has no inverse here", b.name()))
                    })?
                } else {
                    b
                };
                Some(Term::Call(b, vec![arg?]))
            }
            Some((_, Found::Template(t))) if !inverse => Some(Term::Template(t, vec![arg?])),
            _ => None,
        })
    }

    /// `f(args)` with scripts on its closing parenthesis: on the call when
    /// `f` is a function, on `f` when it is written with its variables
    /// (`T(ξ)^{-1}`), else on the parenthesised group of the product
    /// (`R (R Q)^\top` is `R ((R Q)^\top)`).
    fn scripted_application(
        &mut self,
        head: &Head,
        args: &[Expr],
        chain: &Expr,
        e: &Expr,
    ) -> Result<Term, LowerError> {
        let call = Expr::Apply {
            head: head.clone(),
            args: args.to_vec(),
            scripts: None,
        };
        // A key of the file written as the application (`R(t)^{T}`).
        if self.resolver.symbol(&call.to_string())?.is_some() {
            return self.expr(&Expr::with_scripts_of(chain, call));
        }
        let Head::Symbol(s) = head else {
            return self.expr(&Expr::with_scripts_of(chain, call));
        };
        match self.symbol_application(s, args, e)? {
            Application::Call(_) => self.expr(&Expr::with_scripts_of(chain, call)),
            Application::Written(_) => {
                self.expr(&Expr::with_scripts_of(chain, Expr::Symbol(s.clone())))
            }
            Application::Product(head) => {
                let group = match args {
                    [one] => one.clone(),
                    many => Expr::Tuple(many.to_vec()),
                };
                let scripted = self.expr(&Expr::with_scripts_of(chain, group))?;
                Ok(Term::Product(vec![(Op::Mul, head), (Op::Mul, scripted)]))
            }
        }
    }

    /// What a symbol before a parenthesised group is: a function applied,
    /// the symbol written with its variables (`T(ξ)`, `E(ξ, ω)`: every
    /// argument a variable or tangent), or a value multiplying the group.
    fn symbol_application(
        &mut self,
        s: &ast::Symbol,
        args: &[Expr],
        e: &Expr,
    ) -> Result<Application, LowerError> {
        let key = symbol_key(s);
        let found = self.resolver.symbol(&key)?;
        match found {
            Some((_, Found::Function(b))) => return Ok(Application::Call(self.call(b, args, e)?)),
            Some((_, Found::Template(t))) => {
                return Ok(Application::Call(Term::Template(
                    t,
                    args.iter()
                        .map(|a| self.expr(a))
                        .collect::<Result<_, _>>()?,
                )));
            }
            _ => {}
        }
        if let Some(call) = self.subscripted_template(s, args)? {
            return Ok(Application::Call(call));
        }
        let head = self.symbol(s, &Expr::Symbol(s.clone()))?;
        // `f(\cdot)`: the function written with its argument's place.
        if args.iter().all(|a| *a == Expr::Placeholder) {
            return Ok(Application::Written(head));
        }
        // `h(x, \cdots)`: the symbol written with some of its variables.
        let ellipsis = args.contains(&Expr::Ellipsis);
        let group_head = matches!(found, Some((_, Found::Stored { group: true })));
        // Each argument: a variable, a named value (`θ` in `e(ω, θ)`), or
        // neither.
        let mut variables = 0;
        let mut named = 0;
        for a in args {
            match a {
                Expr::Ellipsis => variables += 1,
                Expr::Symbol(x) => match self.resolver.symbol(&symbol_key(x))? {
                    Some((_, Found::Tangent(_))) => variables += 1,
                    Some((_, Found::Stored { .. })) if !group_head => variables += 1,
                    Some((_, Found::Value)) => named += 1,
                    _ => {}
                },
                _ => {}
            }
        }
        // Written with its variables, some of them named values derived
        // from others (`e_q^ω(ω, θ)` with `θ = ‖ω‖`).
        let parameters = variables > 0 && variables + named == args.len();
        Ok(if parameters || ellipsis {
            Application::Written(head)
        } else {
            Application::Product(head)
        })
    }

    /// `f(args)`.
    fn apply(&mut self, head: &Head, args: &[Expr], e: &Expr) -> Result<Term, LowerError> {
        match head {
            Head::Function(f) => {
                let mut args = args.to_vec();
                if let Some(sub) = &f.sub {
                    // `Ad_T`, `ad_\xi`: the function of the subscript, acting
                    // on an argument when one follows.
                    let (alone, acting) = match f.name.as_str() {
                        "Ad" => (Builtin::Adjoint, Builtin::AdjointAct),
                        "ad" => (Builtin::SmallAdjoint, Builtin::SmallAdjointAct),
                        name => {
                            return Err(LowerError::at(
                                e,
                                format!("a subscript on `{name}` is not evaluated"),
                            ));
                        }
                    };
                    let of = self.expr(sub)?;
                    return Ok(match args.as_slice() {
                        [] => Term::Call(alone, vec![of]),
                        [x] => Term::Call(acting, vec![of, self.expr(x)?]),
                        _ => return Err(LowerError::at(e, "one argument is expected")),
                    });
                }
                // A function the file defines (its `log`, `between`, its
                // `\exp` as `expm`) comes before the built-in one of the
                // same name, written with or without its backslash.
                let keys = [format!("\\{}", f.name), f.name.clone()];
                let mut redefined = None;
                for key in &keys {
                    if let Some((_, Found::Function(b))) = self.resolver.symbol(key)? {
                        redefined = Some(b);
                        break;
                    }
                }
                let mut template = None;
                for key in &keys {
                    if template.is_none() {
                        template = self.resolver.template(key)?;
                    }
                }
                if f.power.is_none()
                    && let Some((t, arity)) = template
                {
                    if args.len() != arity {
                        return Err(LowerError::at(
                            e,
                            format!("`{}` takes {arity} argument(s) in the symbols file", f.name),
                        ));
                    }
                    return Ok(Term::Template(
                        t,
                        args.iter()
                            .map(|a| self.expr(a))
                            .collect::<Result<_, _>>()?,
                    ));
                }
                let count = Builtin::indices(&f.name);
                let builtin = if let Some(b) = redefined {
                    Some(b)
                } else if count > 0 {
                    let mut k = Vec::with_capacity(count);
                    for _ in 0..count {
                        let index = args
                            .pop()
                            .as_ref()
                            .and_then(number)
                            .filter(|k| k.fract() == 0.0 && *k >= 1.0 && *k <= 1e6)
                            .ok_or_else(|| {
                                LowerError::at(
                                    e,
                                    format!("`{}` needs printed indices last", f.name),
                                )
                            })?;
                        k.insert(0, index as usize);
                    }
                    Builtin::indexed(&f.name, &k)
                } else {
                    Builtin::named(&f.name)
                };
                let Some(mut builtin) = builtin else {
                    return Err(LowerError::at(
                        e,
                        format!(
                            "unknown function `{}` (known: {}; or define it in the context's \
                             `operators`)",
                            f.name,
                            Builtin::all_names()
                        ),
                    ));
                };
                let power = match &f.power {
                    None => None,
                    Some(p) => match number(p) {
                        Some(-1.0) => {
                            builtin = builtin.inverse().ok_or_else(|| {
                                LowerError::at(e, format!("`{}` has no inverse here", f.name))
                            })?;
                            None
                        }
                        Some(p) => Some(p),
                        None => return Err(LowerError::at(e, "the power is not a number")),
                    },
                };
                let call = self.call(builtin, &args, e)?;
                Ok(match power {
                    Some(p) => Term::Power(Box::new(call), p),
                    None => call,
                })
            }
            Head::Symbol(s) => Ok(match self.symbol_application(s, args, e)? {
                Application::Call(t) | Application::Written(t) => t,
                Application::Product(head) => {
                    let arg = match args {
                        [one] => self.expr(one)?,
                        many => Term::Stack(
                            many.iter()
                                .map(|a| self.expr(a))
                                .collect::<Result<_, _>>()?,
                        ),
                    };
                    Term::Product(vec![(Op::Mul, head), (Op::Mul, arg)])
                }
            }),
        }
    }

    /// The meaning of a product operator (the quaternion product JPL's in a
    /// file that states JPL quaternions).
    fn operator(&self, op: MulOp, x: &Expr) -> Result<Op, LowerError> {
        Ok(match op {
            MulOp::Implicit | MulOp::Star => Op::Mul,
            MulOp::Cdot => Op::Dot,
            MulOp::Times => Op::Cross,
            MulOp::Oplus => Op::Oplus {
                jpl: self.resolver.jpl_quaternions(),
            },
            MulOp::Otimes => Op::Otimes {
                jpl: self.resolver.jpl_quaternions(),
            },
            MulOp::Slash => Op::Div,
            other => {
                return Err(LowerError::at(
                    x,
                    format!("the operator {other:?} is not evaluated"),
                ));
            }
        })
    }

    fn call(&mut self, b: Builtin, args: &[Expr], e: &Expr) -> Result<Term, LowerError> {
        let b = if self.resolver.jpl_quaternions() {
            b.in_jpl()
        } else {
            b
        };
        if args.len() != b.arity() {
            return Err(LowerError::at(
                e,
                format!("`{}` takes {} argument(s)", b.name(), b.arity()),
            ));
        }
        Ok(Term::Call(
            b,
            args.iter()
                .map(|a| self.expr(a))
                .collect::<Result<_, _>>()?,
        ))
    }

    /// `\lim_{δ → 0} \frac{N(δ) − N(0)}{δ}` with `δ` a tangent: the
    /// derivative of the numerator by it at zero (the numerator need not be
    /// linearised).
    fn limit(&mut self, under: &Expr, body: &Expr, e: &Expr) -> Result<Term, LowerError> {
        let variable = match under {
            Expr::Relation { first, rest }
                if rest.len() == 1 && rest[0].0 == Rel::To && number(&rest[0].1) == Some(0.0) =>
            {
                Some(first.as_ref())
            }
            _ => None,
        };
        let tangent = match variable {
            Some(Expr::Symbol(s)) => match self.resolver.symbol(&symbol_key(s))? {
                Some((id, Found::Tangent(_))) => Some((id, s.clone())),
                _ => None,
            },
            _ => None,
        };
        match (tangent, body) {
            (Some((id, s)), Expr::Fraction { num, den }) if matches!(den.as_ref(), Expr::Symbol(d) if *d == s) => {
                Ok(Term::Quotient {
                    numerator: Box::new(self.expr(num)?),
                    tangent: id,
                    limit: true,
                })
            }
            _ => Err(LowerError::at(
                e,
                "a limit is evaluated only as `\\lim_{δ \\to 0}` of a difference quotient over \
                 a perturbation δ the symbols file declares",
            )),
        }
    }

    /// A fraction, a difference quotient over a tangent, or a stack.
    fn fraction(&mut self, num: &Expr, den: &Expr) -> Result<Term, LowerError> {
        let tangent_symbol = match den {
            Expr::Relation { first, .. } => first.as_ref(),
            other => other,
        };
        if let Expr::Symbol(s) = tangent_symbol
            && let Some((id, Found::Tangent(parts))) = self.resolver.symbol(&symbol_key(s))?
        {
            let numerator = self.expr(num)?;
            let mut names: HashSet<SymbolId> = parts.into_iter().collect();
            names.insert(id);
            if degree(&numerator, &names).is_none_or(|d| d > 1) {
                return Err(LowerError::at(
                    num,
                    format!(
                        "the difference quotient over `{}` is not linear in it: only a linearised \
                         numerator is read",
                        tangent_symbol
                    ),
                ));
            }
            return Ok(Term::Quotient {
                numerator: Box::new(numerator),
                tangent: id,
                limit: false,
            });
        }
        if let Expr::Relation { .. } = den {
            return Err(LowerError::at(den, "a relation below a fraction bar"));
        }
        Ok(Term::Fraction {
            num: Box::new(self.expr(num)?),
            den: Box::new(self.expr(den)?),
            stack: self.stacked_fractions,
        })
    }
}

/// A product whose `\times` separates juxtaposed factors: juxtaposition
/// binds tighter (`ω × R p` is `ω × (R p)`), the crosses then taken left to
/// right; other products as printed.
fn cross_of_products(factors: Vec<(Op, Term)>) -> Term {
    let crosses = factors
        .iter()
        .skip(1)
        .filter(|(op, _)| *op == Op::Cross)
        .count();
    if crosses == 0 || crosses + 1 == factors.len() {
        return Term::Product(factors);
    }
    let mut segments: Vec<(Op, Vec<(Op, Term)>)> = Vec::new();
    for (i, (op, t)) in factors.into_iter().enumerate() {
        match segments.last_mut() {
            Some((_, segment)) if i > 0 && op != Op::Cross => segment.push((op, t)),
            _ => segments.push((op, vec![(Op::Mul, t)])),
        }
    }
    Term::Product(
        segments
            .into_iter()
            .map(|(op, mut segment)| {
                let t = if segment.len() == 1 {
                    segment.pop().expect("one factor").1
                } else {
                    Term::Product(segment)
                };
                (op, t)
            })
            .collect(),
    )
}

/// `Some(size)` when `s` is the identity: `I`, `\mathbf{I}`, `\mathbb{I}`,
/// `\mathds{1}`, with a size or not (`I_3`, `I_{3×3}`).
fn identity(s: &ast::Symbol) -> Option<Result<Option<usize>, String>> {
    let plain = ast::Symbol {
        sub: None,
        font: ast::Font::Plain,
        ..s.clone()
    };
    let letter = plain == ast::Symbol::new(Base::Letter('I'))
        && matches!(
            s.font,
            ast::Font::Plain | ast::Font::Bold | ast::Font::Blackboard | ast::Font::Roman
        );
    let one = plain == ast::Symbol::new(Base::Letter('1')) && s.font == ast::Font::Blackboard;
    if !(letter || one) {
        return None;
    }
    Some(match s.sub.as_deref() {
        None => Ok(None),
        Some(sub) => match (number(sub), sub.shape_annotation()) {
            (Some(n), _) if n.fract() == 0.0 && n >= 1.0 => Ok(Some(n as usize)),
            (_, Some((r, c))) if r == c && r >= 1 => Ok(Some(r as usize)),
            _ => Err("an identity's subscript is its size (`I_3`, `I_{3 \\times 3}`)".into()),
        },
    })
}

/// The command of an accent (`hat` for `\hat`).
fn accent_name(a: ast::Accent) -> &'static str {
    match a {
        ast::Accent::Hat => "hat",
        ast::Accent::Tilde => "tilde",
        ast::Accent::Bar => "bar",
        ast::Accent::Dot => "dot",
        ast::Accent::DDot => "ddot",
        ast::Accent::Vec => "vec",
        ast::Accent::Check => "check",
        ast::Accent::Breve => "breve",
    }
}

/// Whether `e` is printed as a name the symbols file may define as a whole
/// (an application, a name with operators or primes, a product of
/// symbols): checked before its parts are read.
fn is_name_like(e: &Expr) -> bool {
    match e {
        Expr::Apply { .. } | Expr::Postfix { .. } | Expr::Primed { .. } | Expr::Indexed { .. } => {
            true
        }
        Expr::Product { first, rest } => {
            matches!(first.as_ref(), Expr::Symbol(_))
                && rest
                    .iter()
                    .all(|(op, x)| *op == MulOp::Implicit && matches!(x, Expr::Symbol(_)))
        }
        _ => false,
    }
}

/// Whether `e` is a product of symbols, their powers, applications and
/// argument lists, printed side by side (`D_2 g(ξ)`, `g^{-1}(T, 0)`): a
/// name the file or another claim may give as a whole.
fn is_applied_product(e: &Expr) -> bool {
    match e {
        Expr::Product { first, rest } => {
            std::iter::once(first.as_ref())
                .chain(rest.iter().map(|(_, x)| x))
                .all(|x| match x {
                    Expr::Symbol(_) | Expr::Apply { .. } | Expr::Tuple(_) => true,
                    Expr::Power { base, exponent } => {
                        matches!(base.as_ref(), Expr::Symbol(_)) && number(exponent).is_some()
                    }
                    _ => false,
                })
                && rest.iter().all(|(op, _)| *op == MulOp::Implicit)
        }
        _ => false,
    }
}

/// `Some(shape)` when `e` is a printed zero block: `0`, `\mathbf{0}` (with
/// a size subscript or not: `Some(Some((3, 1)))` for `0_{3×1}`), `0^T`.
fn zero_block(e: &Expr) -> Option<Option<(usize, usize)>> {
    match e {
        Expr::Number(_) if number(e) == Some(0.0) => Some(None),
        Expr::Symbol(s) if s.base == Base::Letter('0') => {
            let bare = ast::Symbol {
                sub: None,
                font: ast::Font::Plain,
                ..s.clone()
            };
            if bare != ast::Symbol::new(Base::Letter('0')) {
                return None;
            }
            match s.sub.as_deref() {
                None => Some(None),
                Some(sub) => match (number(sub), sub.shape_annotation()) {
                    (Some(n), _) if n.fract() == 0.0 && n >= 1.0 => Some(Some((n as usize, 1))),
                    (_, Some((r, c))) if r >= 1 && c >= 1 => Some(Some((r as usize, c as usize))),
                    _ => None,
                },
            }
        }
        Expr::Postfix {
            base,
            op: PostfixOp::Transpose,
        } => zero_block(base).map(|s| s.map(|(r, c)| (c, r))),
        _ => None,
    }
}

/// The rows and columns a zero block inside a matrix is printed with
/// (`0`: neither; `0_3`: 3 rows; `0_3^\top`: 3 columns; `0_{3 \times 1}`:
/// both), when it is one.
fn printed_zero(e: &Expr) -> Option<(Option<usize>, Option<usize>)> {
    let single = |s: &ast::Symbol| s.sub.as_deref().is_some_and(|sub| number(sub).is_some());
    match e {
        Expr::Symbol(s) if single(s) => zero_block(e).map(|shape| (shape.map(|s| s.0), None)),
        Expr::Postfix {
            base,
            op: PostfixOp::Transpose,
        } if matches!(base.as_ref(), Expr::Symbol(s) if single(s)) => {
            zero_block(base).map(|shape| (None, shape.map(|s| s.0)))
        }
        _ => zero_block(e).map(|shape| (shape.map(|s| s.0), shape.map(|s| s.1))),
    }
}

/// The degree of `t` in the symbols `names` (`None` when it is not a
/// polynomial in them: inside a function, a norm, a denominator, …).
pub fn degree(t: &Term, names: &HashSet<SymbolId>) -> Option<u32> {
    let free = |t: &Term| degree(t, names) == Some(0);
    match t {
        Term::Symbol(id) => Some(u32::from(names.contains(id))),
        Term::Number(_)
        | Term::Zero
        | Term::BlockZero(..)
        | Term::Identity(_)
        | Term::Link(_)
        | Term::TruthLink(_) => Some(0),
        Term::Neg(x) | Term::Hat(x) | Term::Vee(x) | Term::Transpose(x) | Term::Shaped(x, _) => {
            degree(x, names)
        }
        Term::Sum(terms) => terms
            .iter()
            .map(|(_, x)| degree(x, names))
            .try_fold(0, |a, d| Some(a.max(d?))),
        Term::Stack(items) => items
            .iter()
            .map(|x| degree(x, names))
            .try_fold(0, |a, d| Some(a.max(d?))),
        Term::Blocks(rows) => rows
            .iter()
            .flatten()
            .map(|x| degree(x, names))
            .try_fold(0, |a, d| Some(a.max(d?))),
        Term::Product(factors) => factors.iter().try_fold(0, |acc, (op, x)| match op {
            Op::Div if !free(x) => None,
            Op::Oplus { .. } | Op::Otimes { .. } if !free(x) || acc > 0 => None,
            _ => Some(acc + degree(x, names)?),
        }),
        Term::Fraction {
            num,
            den,
            stack: true,
        } => Some(degree(num, names)?.max(degree(den, names)?)),
        Term::Fraction { num, den, .. } => free(den).then(|| degree(num, names)).flatten(),
        Term::Power(x, p) => {
            if free(x) {
                Some(0)
            } else if *p == 1.0 {
                degree(x, names)
            } else {
                None
            }
        }
        Term::Norm(x) | Term::Quotient { numerator: x, .. } => free(x).then_some(0),
        Term::Call(_, args) | Term::Template(_, args) => args.iter().all(free).then_some(0),
        Term::At { body, bindings } => {
            (bindings.iter().all(|(_, t)| free(t)) && free(body)).then_some(0)
        }
    }
}

/// The arguments a partial derivative of a map written with them holds
/// (`∂e(ω, θ)/∂ω` holds `θ`): every symbol argument the derivative is not
/// taken by.
fn written_arguments_held(of: &Expr, wrt: &Expr) -> Vec<Expr> {
    let Expr::Apply {
        head: Head::Symbol(_),
        args,
        ..
    } = of
    else {
        return Vec::new();
    };
    let by: Vec<&Expr> = match wrt {
        Expr::Tuple(items) => items.iter().collect(),
        one => vec![one],
    };
    args.iter()
        .filter(|a| matches!(a, Expr::Symbol(_)) && !by.contains(a))
        .cloned()
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Symbols by key, all values but `δφ` (a tangent) and `f` (a function).
    struct Symbols(HashMap<String, SymbolId>);

    impl Resolver for Symbols {
        fn symbol(&mut self, key: &str) -> Result<Option<(SymbolId, Found)>, LowerError> {
            Ok(self.0.get(key).map(|id| {
                let found = match key {
                    "\\delta \\phi" => Found::Tangent(Vec::new()),
                    "f" => Found::Function(Builtin::Normalize),
                    _ => Found::Value,
                };
                (*id, found)
            }))
        }
        fn link(&self, _: &str) -> Option<Link> {
            None
        }
        fn template(&mut self, _: &str) -> Result<Option<(usize, usize)>, LowerError> {
            Ok(None)
        }
    }

    fn lower(latex: &str) -> Result<Term, LowerError> {
        let keys = ["P_{z}", "y", "\\delta \\phi", "f"];
        let mut symbols = Symbols(
            keys.iter()
                .enumerate()
                .map(|(i, k)| (k.to_string(), i))
                .collect(),
        );
        Lowering::new(&mut symbols, false).expr(&doc_latex::parse_expr(latex).unwrap())
    }

    #[test]
    fn readings_the_symbols_file_does_not_spell_out() {
        // A numeric superscript on a defined symbol is a power.
        assert_eq!(
            lower("P_z^2").unwrap(),
            Term::Power(Box::new(Term::Symbol(0)), 2.0)
        );
        assert_eq!(lower("I_{3 \\times 3}").unwrap(), Term::Identity(Some(3)));
        // A function symbol applies; a value symbol before parentheses of a
        // non-variable multiplies.
        assert_eq!(
            lower("f(y)").unwrap(),
            Term::Call(Builtin::Normalize, vec![Term::Symbol(1)])
        );
        assert!(matches!(lower("y(y + y)").unwrap(), Term::Product(_)));
        // A difference quotient must be linear in its tangent.
        assert!(matches!(
            lower("\\frac{y \\delta\\phi}{\\delta\\phi}").unwrap(),
            Term::Quotient { tangent: 2, .. }
        ));
        let e = lower("\\frac{\\sin(\\delta\\phi)}{\\delta\\phi}").unwrap_err();
        assert!(e.message.contains("not linear"), "{e}");
        let e = lower("\\operatorname{frobnicate}(y)").unwrap_err();
        assert!(
            e.message.starts_with("unknown function `frobnicate`"),
            "{e}"
        );
        assert_eq!(
            lower("z").unwrap_err().to_string(),
            "undefined symbol at `z`"
        );
    }
}
