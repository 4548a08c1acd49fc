//! Sub- and superscripts, primes, and what they mean on their base.
//!
//! A superscript is first stripped of trailing postfix markers (`T`,
//! `\top`, `\wedge`, `\vee`, primes), so `T_w^{cT}` is `(T_w^c)ᵀ` and
//! `\delta\phi^{\wedge T}` is `((δφ)^∧)ᵀ`. What remains is part of a symbol's
//! name unless it reads as an exponent ([`Expr::reads_as_exponent`]); on any
//! other base it is a power. A subscript `\times` makes a skew matrix, `r
//! \times c` on a non-symbol a shape annotation.

use super::{Parser, Seps};
use crate::ast::{Base, Expr, PostfixOp, Symbol};
use crate::error::{ErrorKind, ParseError};
use crate::lexer::Tok;
use crate::names::postfix_operator;

/// One script's argument, taken apart.
#[derive(Debug, Default)]
pub(super) struct ScriptArg {
    /// What remains after the markers, if anything.
    pub expr: Option<Expr>,
    /// Postfix markers, in the order they apply.
    pub markers: Vec<PostfixOp>,
    /// Primes among the markers.
    pub primes: u32,
    /// The subscript is `\times`.
    pub times: bool,
}

/// The scripts after one base.
#[derive(Default)]
struct Scripts {
    sub: Option<ScriptArg>,
    sup: Option<ScriptArg>,
    primes: u32,
}

/// The postfix marker a token stands for in a superscript.
enum Marker {
    Op(PostfixOp),
    Prime,
}

fn marker(tok: &Tok) -> Option<Marker> {
    match tok {
        Tok::Letter('T') => Some(Marker::Op(PostfixOp::Transpose)),
        Tok::Prime => Some(Marker::Prime),
        Tok::Star => Some(Marker::Op(PostfixOp::Operator("*"))),
        Tok::Plus => Some(Marker::Op(PostfixOp::Operator("+"))),
        Tok::Command(c) => match c.as_str() {
            "top" | "intercal" => Some(Marker::Op(PostfixOp::Transpose)),
            "wedge" => Some(Marker::Op(PostfixOp::Hat)),
            "vee" => Some(Marker::Op(PostfixOp::Vee)),
            "prime" => Some(Marker::Prime),
            other => postfix_operator(other).map(|op| Marker::Op(PostfixOp::Operator(op))),
        },
        _ => None,
    }
}

/// Whether a token is an operator or relation command (named as a symbol
/// in a script: `f_\oplus`).
pub(super) fn operator_named(tok: &Tok) -> bool {
    matches!(tok, Tok::Command(c) if crate::names::lookup(crate::names::MULOP_COMMANDS, c).is_some()
        || crate::names::lookup(crate::names::RELATION_COMMANDS, c).is_some())
}

/// The transpose written in a font (`^{\mathsf{T}}`, `^{\mathrm{T}}`): the
/// four tokens `\font { T }` ending at `end` (exclusive).
fn fonted_transpose(toks: &[crate::lexer::Token], end: usize) -> bool {
    end >= 4
        && end <= toks.len()
        && matches!(&toks[end - 4].tok, Tok::Command(c) if ["mathsf", "mathrm", "mathit", "text", "mathbf"].contains(&c.as_str()))
        && toks[end - 3].tok == Tok::LBrace
        && toks[end - 2].tok == Tok::Letter('T')
        && toks[end - 1].tok == Tok::RBrace
}

impl Parser<'_> {
    /// The argument of the `^` (`sup`) or `_` just consumed.
    pub(super) fn script_argument(&mut self, sup: bool) -> Result<ScriptArg, ParseError> {
        let mut arg = ScriptArg::default();
        let Some(tok) = self.peek().cloned() else {
            return Err(self.unexpected());
        };
        if tok != Tok::LBrace {
            if sup && fonted_transpose(&self.toks[..self.end], self.pos + 4) {
                // `^\mathsf{T}`: the transpose in a font, unbraced.
                arg.markers.push(PostfixOp::Transpose);
                self.pos += 4;
                return Ok(arg);
            }
            match (sup, marker(&tok)) {
                (true, Some(Marker::Op(op))) => arg.markers.push(op),
                (true, Some(Marker::Prime)) => arg.primes += 1,
                _ if !sup && tok == Tok::Command("times".into()) => arg.times = true,
                // `[x]_+`: a subscript sign names a notation (`[ω]_+`, the
                // plane's restricted cross product), as an index.
                _ if !sup && tok == Tok::Plus => {
                    arg.expr = Some(Expr::Symbol(Symbol::new(Base::Letter('+'))));
                }
                _ => {
                    arg.expr = Some(self.single_token_argument()?);
                    return Ok(arg);
                }
            }
            self.pos += 1;
            return Ok(arg);
        }
        let open = self.pos;
        let close = self.matching[open];
        // `T_1^{^{-1}}`: a superscript printed inside a superscript.
        if close > open + 2
            && self.toks[open + 1].tok == (if sup { Tok::Sup } else { Tok::Sub })
            && self.toks[open + 2].tok == Tok::LBrace
            && self.matching[open + 2] + 1 == close
        {
            self.pos = open + 2;
            let inner = self.nested(|p| p.script_argument(sup))?;
            self.pos = close + 1;
            return Ok(inner);
        }
        let mut stop = close;
        if sup {
            while stop > open + 1 {
                if fonted_transpose(&self.toks[..stop], stop) && stop >= open + 5 {
                    arg.markers.push(PostfixOp::Transpose);
                    stop -= 4;
                    continue;
                }
                match marker(&self.toks[stop - 1].tok) {
                    Some(Marker::Op(op)) => arg.markers.push(op),
                    Some(Marker::Prime) => arg.primes += 1,
                    None => break,
                }
                stop -= 1;
            }
            arg.markers.reverse();
        } else if close == open + 2 && self.toks[open + 1].tok == Tok::Command("times".into()) {
            arg.times = true;
            stop = open + 1;
        } else if close == open + 2 && self.toks[open + 1].tok == Tok::Plus {
            arg.expr = Some(Expr::Symbol(Symbol::new(Base::Letter('+'))));
            stop = open + 1;
        }
        if stop == open + 2 && operator_named(&self.toks[open + 1].tok) {
            // `f_{\oplus}`: an operator named in a script.
            self.pos = open + 1;
            arg.expr = Some(self.single_token_argument()?);
        } else if stop > open + 1 {
            self.pos = open + 1;
            let items = self.bounded(stop, |p| p.list(Seps::None))?;
            if self.pos != stop {
                return Err(self.unexpected());
            }
            arg.expr = Some(self.build_group(items)?);
        } else if arg.markers.is_empty() && arg.primes == 0 && !arg.times && arg.expr.is_none() {
            return Err(self.error_here(ErrorKind::Empty("script")));
        }
        self.pos = close + 1;
        Ok(arg)
    }

    /// A script that must be a plain expression (under `\lim`, a
    /// pre-script, a function's power).
    pub(super) fn script_expression(&mut self, sup: bool) -> Result<Expr, ParseError> {
        let at = self.pos;
        let arg = self.script_argument(sup)?;
        match arg.expr {
            Some(e) if arg.markers.is_empty() && arg.primes == 0 => Ok(e),
            _ => Err(super::error_at(
                self.place,
                self.toks[at].start,
                ErrorKind::Unexpected(self.text_of(at).to_string()),
            )),
        }
    }

    fn collect_scripts(&mut self) -> Result<Scripts, ParseError> {
        let mut s = Scripts::default();
        loop {
            let sup = match self.peek() {
                Some(Tok::Sub) => false,
                Some(Tok::Sup) => true,
                Some(Tok::Prime) => {
                    self.pos += 1;
                    s.primes += 1;
                    continue;
                }
                _ => return Ok(s),
            };
            if (if sup { &s.sup } else { &s.sub }).is_some() {
                let which = if sup { "super" } else { "sub" };
                return Err(self.error_here(ErrorKind::DoubleScript(which)));
            }
            self.pos += 1;
            let arg = Some(self.script_argument(sup)?);
            if sup {
                s.sup = arg;
            } else {
                s.sub = arg;
            }
        }
    }

    /// The scripts after a symbol: indices join the symbol.
    pub(super) fn scripts_on_symbol(&mut self, mut s: Symbol) -> Result<Expr, ParseError> {
        let at = self.pos;
        let scripts = self.collect_scripts()?;
        let double = |p: &Self, which| {
            super::error_at(p.place, p.toks[at].start, ErrorKind::DoubleScript(which))
        };
        s.primes += scripts.primes;
        let mut skew = false;
        if let Some(sub) = scripts.sub {
            skew = sub.times;
            if let Some(x) = sub.expr {
                if s.sub.is_some() {
                    return Err(double(self, "sub"));
                }
                s.sub = Some(Box::new(x));
            }
        }
        let mut power = None;
        let mut markers = Vec::new();
        if let Some(sup) = scripts.sup {
            markers = sup.markers;
            match sup.expr {
                Some(x) if x.reads_as_exponent() => {
                    s.primes += sup.primes;
                    power = Some(x);
                }
                Some(x) => {
                    if s.sup.is_some() {
                        return Err(double(self, "super"));
                    }
                    // `p_i^{1'}`: the prime belongs to the superscript.
                    s.sup_primes += sup.primes;
                    s.sup = Some(Box::new(x));
                }
                None => s.primes += sup.primes,
            }
        }
        let mut e = Expr::Symbol(s);
        if skew {
            e = Expr::Skew(Box::new(e));
        }
        if let Some(p) = power {
            e = Expr::Power {
                base: Box::new(e),
                exponent: Box::new(p),
            };
        }
        Ok(postfix(e, markers))
    }

    /// Whether the scripts at the cursor are a frame's pre-scripts on the
    /// symbol right after them, not scripts on what is before them:
    /// `(\mathbf{I} - \lfloor θ \rfloor)^{I}_{G}\hat{\mathbf{R}}`, `\exp(…)^{I_k}_{G}
    /// \hat{R}`. They are when a symbol follows directly and they name
    /// frames: both a super- and a subscript, or one starting with a
    /// capital letter, and neither a number, a sign or a postfix marker.
    pub(super) fn frame_prescripts_follow(&self, at: usize) -> bool {
        let mut i = at;
        let (mut sup, mut sub, mut capital) = (false, false, false);
        while let Some(t @ (Tok::Sup | Tok::Sub)) = self.peek_at(i) {
            let is_sup = *t == Tok::Sup;
            if (is_sup && sup) || (!is_sup && sub) {
                return false;
            }
            let start = i + 1;
            let end = match self.peek_at(start) {
                Some(Tok::LBrace) => self.matching[start] + 1,
                Some(_) => start + 1,
                None => return false,
            };
            let inner = if self.peek_at(start) == Some(&Tok::LBrace) {
                start + 1..end - 1
            } else {
                start..end
            };
            match self.toks.get(inner.start).map(|t| &t.tok) {
                Some(Tok::Letter(c)) if is_sup && *c == 'T' && inner.len() == 1 => return false,
                Some(Tok::Letter(c)) => capital |= c.is_uppercase(),
                Some(Tok::Command(c)) if marker(&Tok::Command(c.clone())).is_none() => {}
                _ => return false,
            }
            sup |= is_sup;
            sub |= !is_sup;
            i = end;
        }
        (sup && sub || capital) && self.starts_symbol(i)
    }

    /// The scripts after anything but a symbol.
    pub(super) fn scripts_on_expr(&mut self, mut e: Expr) -> Result<Expr, ParseError> {
        if self.frame_prescripts_follow(self.pos) {
            return Ok(e);
        }
        let scripts = self.collect_scripts()?;
        if let Some(sub) = scripts.sub {
            e = match (sub.times, sub.expr) {
                (true, _) => Expr::Skew(Box::new(e)),
                (false, Some(index)) => match index.shape_annotation() {
                    Some((rows, cols)) => Expr::Shaped {
                        base: Box::new(e),
                        rows,
                        cols,
                    },
                    None => Expr::Indexed {
                        base: Box::new(e),
                        index: Box::new(index),
                    },
                },
                (false, None) => e,
            };
        }
        let (sup_primes, exponent, markers) = match scripts.sup {
            Some(s) => (s.primes, s.expr, s.markers),
            None => (0, None, Vec::new()),
        };
        let primes = scripts.primes + sup_primes;
        if primes > 0 {
            e = Expr::Primed {
                base: Box::new(e),
                primes,
            };
        }
        if let Some(x) = exponent {
            e = Expr::Power {
                base: Box::new(e),
                exponent: Box::new(x),
            };
        }
        Ok(postfix(e, markers))
    }
}

fn postfix(e: Expr, markers: Vec<PostfixOp>) -> Expr {
    markers.into_iter().fold(e, |base, op| Expr::Postfix {
        base: Box::new(base),
        op,
    })
}
