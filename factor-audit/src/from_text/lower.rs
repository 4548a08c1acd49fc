//! LaTeX (the `doc-latex` syntax tree) lowered to a [`Term`]: every symbol
//! resolved through the symbols file, every piece of notation given its
//! meaning, or an error naming the fragment that has none.
//!
//! Readings a symbol table does not spell out:
//! - a superscript that is no defined symbol's is a power when it is a
//!   number (`P_z^2`) or a power of a defined index (`l_i^{1^2}`);
//! - `I`, `I_3`, `I_{3×3}` is the identity unless the file defines `I`;
//!   a printed `0` inside a matrix is a zero block;
//! - `f(x)` is an application when `f` is a function symbol, `f` itself
//!   when every argument is a variable or tangent symbol (`T(ξ)`,
//!   `E(ξ, ω)`), and a product otherwise;
//! - `\frac{X}{δξ}` over a tangent symbol is a difference quotient: the
//!   linear map `δξ ↦ X` (X must be affine in the tangent's parts);
//! - a derivative `\frac{∂a}{∂b}` inside a formula is the printed formula
//!   of the claim of the file that states it (a chain rule's link).

use std::collections::HashSet;

use doc_latex::ast::{self, Base, Expr, Head, MulOp, PostfixOp, Sign};

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
    /// A tangent, with the symbols of its parts.
    Tangent(Vec<SymbolId>),
    /// A stored value (a field or a free variable).
    Stored,
    /// A definition, a component, a residual or a bound name.
    Value,
}

/// Where lowering looks symbols and chain-rule links up.
pub trait Resolver {
    /// The symbol whose canonical LaTeX is `key`, in scope (its definition
    /// lowered first); `Ok(None)` when none is.
    fn symbol(&mut self, key: &str) -> Result<Option<(SymbolId, Found)>, LowerError>;
    /// The claim whose derivative is written `key`.
    fn link(&self, key: &str) -> Option<usize>;
}

/// One lowering, with the reading options of the formula.
pub struct Lowering<'r> {
    resolver: &'r mut dyn Resolver,
    /// Read fractions with a non-scalar above the bar as stacks.
    pub stacked_fractions: bool,
}

/// The canonical LaTeX of a symbol: the key of the symbols file.
pub fn symbol_key(s: &ast::Symbol) -> String {
    Expr::Symbol(s.clone()).to_string()
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
        }
    }

    /// `e` lowered.
    pub fn expr(&mut self, e: &Expr) -> Result<Term, LowerError> {
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
            Expr::Neg(x) => Term::Neg(Box::new(self.expr(x)?)),
            Expr::Pos(x) => self.expr(x)?,
            Expr::Sum { .. } => Term::Sum(
                e.terms()
                    .into_iter()
                    .map(|(sign, t)| Ok((sign == Sign::Minus, self.expr(t)?)))
                    .collect::<Result<_, LowerError>>()?,
            ),
            Expr::Product { first, rest } => {
                let mut factors = vec![(Op::Mul, self.expr(first)?)];
                for (op, x) in rest {
                    factors.push((operator(*op, x)?, self.expr(x)?));
                }
                Term::Product(factors)
            }
            Expr::Fraction { num, den } => self.fraction(num, den)?,
            Expr::Derivative { .. } => match self.resolver.link(&e.to_string()) {
                Some(k) => Term::Link(k),
                None => {
                    return Err(LowerError::at(
                        e,
                        "this derivative is no claim of the symbols file (add one, with `lhs` if \
                         it is printed differently there)",
                    ));
                }
            },
            Expr::Differential(_) => {
                return Err(LowerError::at(
                    e,
                    "a differential `∂x` outside a derivative is not evaluated",
                ));
            }
            Expr::Limit { .. } => {
                return Err(LowerError::at(
                    e,
                    "a limit is not evaluated (audit the line that arrives at its value)",
                ));
            }
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
            Expr::Apply { head, args } => self.apply(head, args, e)?,
            Expr::Power { base, exponent } => {
                let p = number(exponent)
                    .ok_or_else(|| LowerError::at(e, "the exponent is not a number"))?;
                Term::Power(Box::new(self.expr(base)?), p)
            }
            Expr::Postfix { base, op } => {
                let base = Box::new(self.expr(base)?);
                match op {
                    PostfixOp::Transpose => Term::Transpose(base),
                    PostfixOp::Hat => Term::Hat(base),
                    PostfixOp::Vee => Term::Vee(base),
                }
            }
            Expr::Indexed { .. } => {
                return Err(LowerError::at(
                    e,
                    "a subscript on an expression is not evaluated (define a symbol for it)",
                ));
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
                            .map(|x| match x {
                                Expr::Number(_) if number(x) == Some(0.0) => Ok(Term::Zero),
                                other => self.expr(other),
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
        })
    }

    /// A symbol: defined, a power of a defined one, or the identity.
    fn symbol(&mut self, s: &ast::Symbol, e: &Expr) -> Result<Term, LowerError> {
        if let Some((id, found)) = self.resolver.symbol(&symbol_key(s))? {
            return match found {
                Found::Function(_) => Err(LowerError::at(
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
                let mut base = s.clone();
                base.sup = index.map(Box::new);
                if let Some((id, Found::Stored | Found::Value)) =
                    self.resolver.symbol(&symbol_key(&base))?
                {
                    return Ok(Term::Power(Box::new(Term::Symbol(id)), p));
                }
            }
        }
        if let Some(size) = identity(s) {
            return size.map(Term::Identity).map_err(|m| LowerError::at(e, m));
        }
        Err(LowerError::at(e, "undefined symbol"))
    }

    /// `f(args)`.
    fn apply(&mut self, head: &Head, args: &[Expr], e: &Expr) -> Result<Term, LowerError> {
        match head {
            Head::Function(f) => {
                let mut args = args.to_vec();
                let count = Builtin::indices(&f.name);
                let builtin = if count > 0 {
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
                            "unknown function `{}` (known: {})",
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
            Head::Symbol(s) => {
                let key = symbol_key(s);
                let found = self.resolver.symbol(&key)?;
                if let Some((_, Found::Function(b))) = found {
                    return self.call(b, args, e);
                }
                let head = self.symbol(s, &Expr::Symbol(s.clone()))?;
                let mut parameters = true;
                for a in args {
                    let is_parameter = match a {
                        Expr::Symbol(x) => matches!(
                            self.resolver.symbol(&symbol_key(x))?,
                            Some((_, Found::Stored | Found::Tangent(_)))
                        ),
                        _ => false,
                    };
                    parameters &= is_parameter;
                }
                if parameters {
                    // `T(ξ)`, `E(ξ, ω)`: the symbol, written with its variables.
                    return Ok(head);
                }
                let arg = match args {
                    [one] => self.expr(one)?,
                    many => Term::Stack(
                        many.iter()
                            .map(|a| self.expr(a))
                            .collect::<Result<_, _>>()?,
                    ),
                };
                Ok(Term::Product(vec![(Op::Mul, head), (Op::Mul, arg)]))
            }
        }
    }

    fn call(&mut self, b: Builtin, args: &[Expr], e: &Expr) -> Result<Term, LowerError> {
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

/// The meaning of a product operator.
fn operator(op: MulOp, x: &Expr) -> Result<Op, LowerError> {
    Ok(match op {
        MulOp::Implicit | MulOp::Cdot | MulOp::Star => Op::Mul,
        MulOp::Times => Op::Cross,
        MulOp::Oplus | MulOp::Otimes => Op::Oplus,
        MulOp::Slash => Op::Div,
        other => {
            return Err(LowerError::at(
                x,
                format!("the operator {other:?} is not evaluated"),
            ));
        }
    })
}

/// `Some(size)` when `s` is the identity `I`, `I_3`, `I_{3×3}`.
fn identity(s: &ast::Symbol) -> Option<Result<Option<usize>, String>> {
    let plain = ast::Symbol {
        sub: None,
        ..s.clone()
    };
    if plain != ast::Symbol::new(Base::Letter('I')) {
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

/// The degree of `t` in the symbols `names` (`None` when it is not a
/// polynomial in them: inside a function, a norm, a denominator, …).
pub fn degree(t: &Term, names: &HashSet<SymbolId>) -> Option<u32> {
    let free = |t: &Term| degree(t, names) == Some(0);
    match t {
        Term::Symbol(id) => Some(u32::from(names.contains(id))),
        Term::Number(_) | Term::Zero | Term::Identity(_) | Term::Link(_) => Some(0),
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
            Op::Oplus if !free(x) || acc > 0 => None,
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
        Term::Call(_, args) => args.iter().all(free).then_some(0),
    }
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
        fn link(&self, _: &str) -> Option<usize> {
            None
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
