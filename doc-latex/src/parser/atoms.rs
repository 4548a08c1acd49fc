//! Factors: symbols (fonts, accents, increments `\delta x`, pre-scripts),
//! numbers, functions and their application, `\partial`, `\lim`, `\frac`,
//! `\sqrt`.

use super::{Ctx, Parser, Seps};
use crate::ast::{
    Base, DerivativeKind, Expr, Font, Function, Head, Matrix, MulOp, PostfixOp, Symbol,
};
use crate::error::{ErrorKind, ParseError};
use crate::lexer::{Delim, Tok};
use crate::names::{
    ACCENT_COMMANDS, FONT_COMMANDS, combined_font, function_command, lookup, operator_word,
    symbol_command,
};

/// The largest `k` whose `k!` is read (`20!` is the largest in a `u64`).
const MAX_FACTORIAL: u64 = 20;

/// What a factor starts with, before its scripts.
pub(super) enum Atom {
    /// A symbol: scripts become part of it.
    Symbol(Symbol),
    /// A function name: a power, then its argument(s).
    Function(String),
    /// Anything else: scripts wrap it.
    Expr(Expr),
    /// `\partial …`, `\lim …`: already took the rest of the product.
    Swallowed(Expr),
}

impl Parser<'_> {
    /// One factor with its scripts (and its application to a parenthesised
    /// group, after a symbol or function).
    pub(super) fn factor(&mut self, ctx: Ctx) -> Result<Expr, ParseError> {
        self.nested(|p| {
            p.skip_spaces();
            let atom = p.atom(ctx)?;
            p.finish(atom, true)
        })
    }

    /// A factor without application to a following group: the argument of
    /// a function written without parentheses (`\sin\theta`).
    fn simple_factor(&mut self) -> Result<Expr, ParseError> {
        self.nested(|p| {
            let atom = p.atom(Ctx::default())?;
            p.finish(atom, false)
        })
    }

    fn finish(&mut self, atom: Atom, apply: bool) -> Result<Expr, ParseError> {
        match atom {
            Atom::Swallowed(e) => Ok(e),
            Atom::Function(name) => self.function(name),
            Atom::Expr(e) => self.scripts_on_expr(e),
            Atom::Symbol(s) => {
                let e = self.scripts_on_symbol(s)?;
                match e {
                    Expr::Symbol(s)
                        if apply && matches!(self.peek(), Some(Tok::Open(Delim::Paren))) =>
                    {
                        let args = self.call_arguments()?;
                        // Scripts on the closing parenthesis: the symbol
                        // table decides what they apply to.
                        let scripts = match self.scripts_on_expr(Expr::Placeholder)? {
                            Expr::Placeholder => None,
                            chain => Some(Box::new(chain)),
                        };
                        Ok(Expr::Apply {
                            head: Head::Symbol(s),
                            args,
                            scripts,
                        })
                    }
                    e => Ok(e),
                }
            }
        }
    }

    pub(super) fn atom(&mut self, ctx: Ctx) -> Result<Atom, ParseError> {
        let Some(tok) = self.peek().cloned() else {
            return Err(self.unexpected());
        };
        match tok {
            Tok::Number(n) => {
                self.pos += 1;
                // `k!` of a whole number (series coefficients, `\frac{1}{3!}`)
                // is read as its value.
                if self.peek() == Some(&Tok::Other('!')) {
                    let value = n
                        .parse::<u64>()
                        .ok()
                        .filter(|k| *k <= MAX_FACTORIAL)
                        .map(|k| (1..=k).product::<u64>());
                    return match value {
                        Some(value) => {
                            self.pos += 1;
                            Ok(Atom::Expr(Expr::Number(value.to_string())))
                        }
                        None => Err(self.unexpected()),
                    };
                }
                Ok(Atom::Expr(Expr::Number(n)))
            }
            Tok::Letter(c) => {
                self.pos += 1;
                let s = Symbol::new(Base::Letter(c));
                Ok(Atom::Symbol(self.increment(s)?))
            }
            Tok::Word(w) => {
                self.pos += 1;
                Ok(Atom::Function(w))
            }
            // `\text{}^{I_k}_{G} R`, `^G v`: pre-scripts on the symbol that
            // follows (an empty text or nothing carrying them).
            Tok::Text(t) if t.trim().is_empty() && self.script_at(self.pos + 1) => {
                self.pos += 1;
                self.prescripted_symbol()
            }
            Tok::Sup | Tok::Sub if self.frame_prescripts_follow(self.pos) => {
                self.prescripted_symbol()
            }
            Tok::Text(t) => {
                self.pos += 1;
                Ok(match operator_word(t.trim()) {
                    Some(f) => Atom::Function(f.to_string()),
                    None if self.names_a_function() && is_word(t.trim()) => {
                        Atom::Function(t.trim().to_string())
                    }
                    None => Atom::Expr(Expr::Text(t)),
                })
            }
            Tok::OperatorName(n) => {
                self.pos += 1;
                Ok(Atom::Function(n.trim().to_string()))
            }
            Tok::LBrace => self.brace_group(),
            Tok::Open(_) | Tok::Left(_) | Tok::Bar | Tok::DoubleBar => self.delimited(),
            Tok::Begin(name) => Ok(Atom::Expr(self.environment(&name)?)),
            Tok::Period if self.closes(self.pos + 1) => {
                self.pos += 1;
                Ok(Atom::Expr(Expr::Placeholder))
            }
            Tok::Command(name) => self.command(&name, ctx),
            _ => Err(self.unexpected()),
        }
    }

    /// A command: commands nest (`\sqrt\sqrt…`, `\hat\hat…`) with the
    /// largest stack frames, so each counts one more nesting step.
    fn command(&mut self, name: &str, ctx: Ctx) -> Result<Atom, ParseError> {
        self.nested(|p| p.command_atom(name, ctx))
    }

    fn command_atom(&mut self, name: &str, ctx: Ctx) -> Result<Atom, ParseError> {
        if let Some(font) = lookup(FONT_COMMANDS, name) {
            return self.font(name, font);
        }
        if let Some(accent) = lookup(ACCENT_COMMANDS, name) {
            let mut s = match self.argument_expr(name)? {
                Expr::Symbol(s) => s,
                // `\widehat{\xi_b + \delta\xi_b}`: the hat operator on an
                // expression.
                other if name == "widehat" => {
                    return Ok(Atom::Expr(Expr::Postfix {
                        base: Box::new(other),
                        op: PostfixOp::Hat,
                    }));
                }
                _ => return Err(self.error_before(ErrorKind::NotASymbol(name.into()))),
            };
            if s.accent.is_some() {
                return Err(self.error_before(ErrorKind::NotASymbol(name.into())));
            }
            s.accent = Some(accent);
            return Ok(Atom::Symbol(self.increment(s)?));
        }
        if let Some(f) = function_command(name) {
            self.pos += 1;
            return Ok(Atom::Function(f.to_string()));
        }
        if let Some(s) = symbol_command(name) {
            self.pos += 1;
            let s = Symbol::new(Base::Command(s.to_string()));
            return Ok(Atom::Symbol(self.increment(s)?));
        }
        match name {
            "partial" => {
                self.pos += 1;
                // `\partial` alone (the numerator of `\frac{\partial}{\partial x}`).
                let of = if self.closes(self.pos) {
                    Expr::Placeholder
                } else {
                    self.product(ctx)?
                };
                Ok(Atom::Swallowed(Expr::Differential(Box::new(of))))
            }
            "lim" => {
                self.pos += 1;
                if self.peek() != Some(&Tok::Sub) {
                    return Err(self.error_here(ErrorKind::MissingOperand("\\lim".into())));
                }
                self.pos += 1;
                let under = self.script_expression(false)?;
                let body = self.product(ctx)?;
                Ok(Atom::Swallowed(Expr::Limit {
                    under: Box::new(under),
                    body: Box::new(body),
                }))
            }
            "frac" | "dfrac" | "tfrac" | "cfrac" => {
                self.pos += 1;
                match self.fraction()? {
                    // `\frac{\partial}{\partial x} f`: the operator takes
                    // the rest of the product.
                    Expr::Derivative { kind, of, wrt } if *of == Expr::Placeholder => {
                        self.skip_spaces();
                        if !self.starts_operand(self.pos) || self.closes(self.pos) {
                            return Err(self.error_here(ErrorKind::MissingOperand(
                                "a derivative operator".into(),
                            )));
                        }
                        let of = self.product(ctx)?;
                        Ok(Atom::Swallowed(Expr::Derivative {
                            kind,
                            of: Box::new(of),
                            wrt,
                        }))
                    }
                    e => Ok(Atom::Expr(e)),
                }
            }
            "sqrt" => {
                self.pos += 1;
                Ok(Atom::Expr(self.sqrt()?))
            }
            "cdot" if self.closes(self.pos + 1) => {
                self.pos += 1;
                Ok(Atom::Expr(Expr::Placeholder))
            }
            "cdots" | "ldots" | "dots" | "dotsc" | "dotsb" | "dotsm" | "vdots" | "ddots" => {
                self.pos += 1;
                Ok(Atom::Expr(Expr::Ellipsis))
            }
            _ if lookup(crate::names::RELATION_COMMANDS, name).is_some()
                || lookup(crate::names::MULOP_COMMANDS, name).is_some()
                || name == "mid" =>
            {
                Err(self.unexpected())
            }
            _ => Err(self.error_here(ErrorKind::UnknownCommand(name.into()))),
        }
    }

    /// `\delta x`, `\Delta x`: a bare `δ` or `Δ` directly before a symbol
    /// makes an increment.
    fn increment(&mut self, s: Symbol) -> Result<Symbol, ParseError> {
        let bare = |name: &str| {
            s.base == Base::Command(name.into())
                && matches!(s.font, Font::Plain | Font::Bold)
                && Symbol {
                    font: Font::Plain,
                    ..s.clone()
                } == Symbol::new(Base::Command(name.into()))
        };
        let capital = bare("Delta");
        if !(bare("delta") || capital) || !self.starts_symbol(self.pos) {
            return Ok(s);
        }
        let name = if capital { "Delta" } else { "delta" };
        let mut inner = self.symbol_atom(name)?;
        if inner.delta.is_some() {
            return Err(self.error_before(ErrorKind::NotASymbol(name.into())));
        }
        inner.delta = Some(s.font);
        inner.capital_delta = capital;
        Ok(inner)
    }

    /// Whether token `i` is a sub- or superscript.
    fn script_at(&self, i: usize) -> bool {
        matches!(self.peek_at(i), Some(Tok::Sub | Tok::Sup))
    }

    /// Whether token `i` begins a symbol (for `\delta x`, `{}_W x` and
    /// pre-scripts after a group).
    pub(super) fn starts_symbol(&self, i: usize) -> bool {
        match self.peek_at(i) {
            Some(Tok::Letter(_)) => true,
            Some(Tok::Command(c)) => {
                symbol_command(c).is_some()
                    || lookup(FONT_COMMANDS, c).is_some()
                    || lookup(ACCENT_COMMANDS, c).is_some()
            }
            _ => false,
        }
    }

    /// `{}_W x`: pre-scripts on the symbol that follows (the cursor is after
    /// the empty group).
    pub(super) fn prescripted_symbol(&mut self) -> Result<Atom, ParseError> {
        let (mut pre_sub, mut pre_sup) = (None, None);
        loop {
            let is_sub = match self.peek() {
                Some(Tok::Sub) => true,
                Some(Tok::Sup) => false,
                _ => break,
            };
            if (if is_sub { &pre_sub } else { &pre_sup }).is_some() {
                return Err(self.error_here(ErrorKind::DoubleScript("pre-")));
            }
            self.pos += 1;
            let e = Some(Box::new(self.script_expression(false)?));
            if is_sub {
                pre_sub = e;
            } else {
                pre_sup = e;
            }
        }
        self.skip_spaces();
        if !self.starts_symbol(self.pos) {
            return Err(self.error_here(ErrorKind::NotASymbol("{}_".into())));
        }
        let mut s = self.symbol_atom("{}_")?;
        if s.pre_sub.is_some() || s.pre_sup.is_some() {
            return Err(self.error_before(ErrorKind::DoubleScript("pre-")));
        }
        s.pre_sub = pre_sub;
        s.pre_sup = pre_sup;
        Ok(Atom::Symbol(s))
    }

    /// The symbol atom at the cursor (without scripts), for `what`.
    fn symbol_atom(&mut self, what: &str) -> Result<Symbol, ParseError> {
        self.nested(|p| match p.atom(Ctx::default())? {
            Atom::Symbol(s) => Ok(s),
            _ => Err(p.error_before(ErrorKind::NotASymbol(what.into()))),
        })
    }

    /// A function name's power, subscript and argument(s), then scripts on
    /// the result. A function with a subscript may stand without an
    /// argument (`Ad_T` is the adjoint matrix of `T`).
    fn function(&mut self, name: String) -> Result<Expr, ParseError> {
        let (mut power, mut sub) = (None, None);
        loop {
            let (slot, which) = match self.peek() {
                Some(Tok::Sup) => (&mut power, "super"),
                Some(Tok::Sub) => (&mut sub, "sub"),
                _ => break,
            };
            if slot.is_some() {
                return Err(self.error_here(ErrorKind::DoubleScript(which)));
            }
            let is_sup = which == "super";
            self.pos += 1;
            let e = Some(Box::new(self.script_expression(false)?));
            if is_sup {
                power = e;
            } else {
                sub = e;
            }
        }
        let (args, bare) = match self.peek() {
            Some(Tok::Open(Delim::Paren) | Tok::Left(Delim::Paren)) => {
                (self.call_arguments()?, false)
            }
            _ => {
                self.skip_spaces();
                if !self.starts_operand(self.pos) {
                    if sub.is_none() {
                        return Err(self.error_here(ErrorKind::MissingOperand(name)));
                    }
                    (Vec::new(), false)
                } else {
                    (vec![self.simple_factor()?], true)
                }
            }
        };
        self.scripts_on_expr(Expr::Apply {
            head: Head::Function(Function {
                name,
                power,
                sub,
                bare,
            }),
            args,
            scripts: None,
        })
    }

    /// Whether the token at the cursor applies a function name before it:
    /// `(`, `\left(`, or a script.
    fn names_a_function(&self) -> bool {
        matches!(
            self.peek(),
            Some(Tok::Open(Delim::Paren) | Tok::Left(Delim::Paren) | Tok::Sub)
        )
    }

    /// `\mathbf{x}`, `\mathcal{K}`, `\mathrm{d}`; `\mathrm` of a word is a
    /// function name or text; a font over several letters is their product
    /// (`\mathbf{Rp}` is `\mathbf{R}\mathbf{p}`), over a digit a symbol
    /// (`\mathbf{0}`, `\mathds{1}`), over a symbol in another font the two
    /// fonts combined (`\bm{\mathcal{J}}`).
    fn font(&mut self, name: &str, font: Font) -> Result<Atom, ParseError> {
        if self.peek_at(self.pos + 1) == Some(&Tok::LBrace)
            && let Some(word) = self.braced_word(self.pos + 1)
            && word.chars().count() > 1
        {
            let close = self.matching[self.pos + 1];
            if font == Font::Roman {
                self.pos = close + 1;
                return Ok(match operator_word(&word) {
                    Some(f) => Atom::Function(f.to_string()),
                    None if self.names_a_function() => Atom::Function(word),
                    None => Atom::Expr(Expr::Text(word)),
                });
            }
            if self.only_letters(self.pos + 2, close) {
                // `\mathbf{Rp}`: each letter in the font.
                self.pos = close + 1;
                let factors: Vec<Expr> = word
                    .chars()
                    .map(|c| {
                        Expr::Symbol(Symbol {
                            font,
                            ..Symbol::new(Base::Letter(c))
                        })
                    })
                    .collect();
                return self.font_product(factors);
            }
        }
        if let Some((digit, next)) = self.font_digit() {
            self.pos = next;
            return Ok(Atom::Symbol(Symbol {
                font,
                ..Symbol::new(Base::Letter(digit))
            }));
        }
        let mut s = match self.argument_expr(name)? {
            Expr::Symbol(s) => s,
            // A font over an expression (`\mathfrak{\mathbb{R}^{2}}`,
            // `\mathfrak{g^{*} \rightarrow g^{*}}`): the expression.
            other => return Ok(Atom::Expr(other)),
        };
        s.font = combined_font(font, s.font)
            .ok_or_else(|| self.error_before(ErrorKind::NotASymbol(name.into())))?;
        Ok(Atom::Symbol(self.increment(s)?))
    }

    /// The digit a font is written over (`\mathbf{0}`, `\mathbf 1`), and
    /// the token after it.
    fn font_digit(&self) -> Option<(char, usize)> {
        let digit = |t: Option<&Tok>| match t {
            Some(Tok::Number(n)) if n.len() == 1 => n.chars().next(),
            _ => None,
        };
        if self.peek_at(self.pos + 1) == Some(&Tok::LBrace) {
            let close = self.matching[self.pos + 1];
            return (close == self.pos + 3)
                .then(|| digit(self.peek_at(self.pos + 2)))
                .flatten()
                .map(|d| (d, close + 1));
        }
        digit(self.peek_at(self.pos + 1)).map(|d| (d, self.pos + 2))
    }

    /// Whether the tokens `from..to` are letters written one after another.
    fn only_letters(&self, from: usize, to: usize) -> bool {
        self.toks[from..to]
            .iter()
            .all(|t| matches!(t.tok, Tok::Letter(_)))
    }

    /// The letters of a font over a word, as one atom: their product, with
    /// the scripts after the group on the last letter.
    fn font_product(&mut self, mut factors: Vec<Expr>) -> Result<Atom, ParseError> {
        let last = match factors.pop() {
            Some(Expr::Symbol(s)) => self.scripts_on_symbol(s)?,
            _ => unreachable!("a word has letters"),
        };
        let first = factors.remove(0);
        let mut rest: Vec<(MulOp, Expr)> =
            factors.into_iter().map(|f| (MulOp::Implicit, f)).collect();
        rest.push((MulOp::Implicit, last));
        Ok(Atom::Swallowed(Expr::Product {
            first: Box::new(first),
            rest,
        }))
    }

    /// The letters of the group opened at `open`, if it holds only letters.
    fn braced_word(&self, open: usize) -> Option<String> {
        let close = self.matching[open];
        let mut word = String::new();
        for t in &self.toks[open + 1..close] {
            match &t.tok {
                Tok::Letter(c) => word.push(*c),
                Tok::Word(w) => word.push_str(w),
                _ => return None,
            }
        }
        Some(word)
    }

    /// The argument of a font or accent command at the cursor: a braced
    /// group's expression, or one symbol.
    fn argument_expr(&mut self, name: &str) -> Result<Expr, ParseError> {
        self.pos += 1;
        let not_a_symbol = |p: &Self| p.error_before(ErrorKind::NotASymbol(name.into()));
        let e = if self.peek() == Some(&Tok::LBrace) {
            let close = self.matching[self.pos];
            self.pos += 1;
            let e = self.bounded(close, |p| p.relation(Ctx::default()))?;
            if self.pos != close {
                return Err(not_a_symbol(self));
            }
            self.pos += 1;
            e
        } else if self.starts_symbol(self.pos) {
            Expr::Symbol(self.symbol_atom(name)?)
        } else {
            return Err(not_a_symbol(self));
        };
        Ok(e)
    }

    /// Runs `f` with the input cut at token `end`.
    pub(super) fn bounded<T>(
        &mut self,
        end: usize,
        f: impl FnOnce(&mut Self) -> Result<T, ParseError>,
    ) -> Result<T, ParseError> {
        let saved = self.end;
        self.end = end;
        let r = f(self);
        self.end = saved;
        r
    }

    /// `\frac{num}{den}`: a derivative, a stacked block matrix when a half
    /// holds `\mid` separators, or a fraction.
    fn fraction(&mut self) -> Result<Expr, ParseError> {
        let num = self.argument(Seps::Mid)?;
        let den = self.argument(Seps::Mid)?;
        let stacked = num.iter().chain(&den).any(|item| item.len() > 1);
        if stacked {
            if num.len() > 1 || den.len() > 1 {
                return Err(self.error_before(ErrorKind::MixedSeparators));
            }
            let rows = num.into_iter().chain(den).collect();
            return Ok(Expr::Matrix(Matrix { rows }));
        }
        let num = self.build_group(num)?;
        let den = self.build_group(den)?;
        Ok(derivative(num, den))
    }

    /// `\sqrt[index]{body}`.
    fn sqrt(&mut self) -> Result<Expr, ParseError> {
        let index = if self.peek() == Some(&Tok::Open(Delim::Bracket)) {
            self.pos += 1;
            let items = self.list(Seps::None)?;
            if self.peek() != Some(&Tok::Close(Delim::Bracket)) {
                return Err(self.error_here(ErrorKind::Unclosed {
                    open: "[".into(),
                    expected: "]".into(),
                }));
            }
            self.pos += 1;
            Some(Box::new(self.build_group(items)?))
        } else {
            None
        };
        let body = self.argument(Seps::None)?;
        Ok(Expr::Sqrt {
            index,
            body: Box::new(self.build_group(body)?),
        })
    }

    /// A command's argument: a braced group's list, or one token. An
    /// operator (`\times`, `\oplus`) is no operand, braced or not: a
    /// script may name one (`x^\times`), `\frac4\times` may not, as
    /// `\frac{4}{\times}` may not.
    pub(super) fn argument(&mut self, seps: Seps) -> Result<Vec<Vec<Expr>>, ParseError> {
        if let Some(tok) = self.peek()
            && matches!(tok, Tok::Command(_))
            && super::scripts::operator_named(tok)
        {
            return Err(self.unexpected());
        }
        if self.peek() == Some(&Tok::LBrace) {
            let close = self.matching[self.pos];
            self.pos += 1;
            let items = self.bounded(close, |p| p.list(seps))?;
            if self.pos != close {
                return Err(self.unexpected());
            }
            self.pos = close + 1;
            Ok(items)
        } else {
            Ok(vec![vec![self.single_token_argument()?]])
        }
    }

    /// An argument written without braces: one digit, one letter, or one
    /// command with its own arguments (`\frac12`, `x^2`, `_\phi`).
    pub(super) fn single_token_argument(&mut self) -> Result<Expr, ParseError> {
        match self.peek().cloned() {
            Some(Tok::Number(n)) => {
                // LaTeX takes one digit: `x^12` is `x^1 2`. A decimal `0.5`
                // is taken whole (its digits split would leave `.5`).
                if n.len() > 1 && n.as_bytes()[1] != b'.' {
                    let t = &mut self.toks[self.pos];
                    t.start = (t.start + 1).min(t.end);
                    t.tok = Tok::Number(n[1..].to_string());
                    Ok(Expr::Number(n[..1].to_string()))
                } else {
                    self.pos += 1;
                    Ok(Expr::Number(n))
                }
            }
            Some(Tok::Letter(c)) => {
                self.pos += 1;
                Ok(Expr::Symbol(Symbol::new(Base::Letter(c))))
            }
            // `f_\oplus`, `x^\ominus`: an operator named in a script.
            Some(Tok::Command(c)) if super::scripts::operator_named(&Tok::Command(c.clone())) => {
                self.pos += 1;
                Ok(Expr::Symbol(Symbol::new(Base::Command(c))))
            }
            Some(Tok::Command(_)) => self.nested(|p| match p.atom(Ctx::default())? {
                Atom::Symbol(s) => Ok(Expr::Symbol(s)),
                Atom::Expr(e) => Ok(e),
                Atom::Function(_) | Atom::Swallowed(_) => {
                    Err(p.error_before(ErrorKind::MissingOperand("a one-token argument".into())))
                }
            }),
            _ => Err(self.unexpected()),
        }
    }
}

/// `num / den` as a derivative when both are differentials: `∂a/∂b`, or
/// `d a / d b` (a `d` juxtaposed before the rest of each half). A lone `∂`
/// or `d` over a differential is a derivative operator: its `of` is a
/// placeholder the caller fills with what follows.
fn derivative(num: Expr, den: Expr) -> Expr {
    match (num, den) {
        (Expr::Differential(of), Expr::Differential(wrt)) if *wrt != Expr::Placeholder => {
            Expr::Derivative {
                kind: DerivativeKind::Partial,
                of,
                wrt,
            }
        }
        (num, den) if is_d(&num) && after_d(&den).is_some() => Expr::Derivative {
            kind: DerivativeKind::Total,
            of: Box::new(Expr::Placeholder),
            wrt: Box::new(after_d(&den).expect("checked")),
        },
        (num, den) => match (after_d(&num), after_d(&den)) {
            (Some(of), Some(wrt)) => Expr::Derivative {
                kind: DerivativeKind::Total,
                of: Box::new(of),
                wrt: Box::new(wrt),
            },
            _ => Expr::Fraction {
                num: Box::new(num),
                den: Box::new(den),
            },
        },
    }
}

/// Whether `e` is a bare `d` (or an upright `\mathrm{d}`).
fn is_d(e: &Expr) -> bool {
    match e {
        Expr::Symbol(s) => {
            s.is_letter('d')
                || *s
                    == Symbol {
                        font: Font::Roman,
                        ..Symbol::new(Base::Letter('d'))
                    }
        }
        _ => false,
    }
}

/// The rest of a product `d x …` whose first factor is a bare `d`.
fn after_d(e: &Expr) -> Option<Expr> {
    let Expr::Product { first, rest } = e else {
        return None;
    };
    if !is_d(first) || rest[0].0 != MulOp::Implicit {
        return None;
    }
    let mut rest = rest.clone();
    let (_, second) = rest.remove(0);
    Some(if rest.is_empty() {
        second
    } else {
        Expr::Product {
            first: Box::new(second),
            rest,
        }
    })
}

/// Whether `w` is a word of letters, maybe hyphenated (a function name
/// printed as text: `\text{pseudo-log}(T)`).
fn is_word(w: &str) -> bool {
    !w.is_empty()
        && w.split('-')
            .all(|part| !part.is_empty() && part.chars().all(|c| c.is_ascii_alphabetic()))
}
