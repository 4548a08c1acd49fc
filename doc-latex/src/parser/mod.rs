//! Recursive descent from tokens to the [`crate::ast`] tree.
//!
//! Grammar, lowest precedence first:
//!
//! ```text
//! statement := ['\Rightarrow'] [sum] (rel sum)*          (one line)
//! relation  := sum (rel sum)*                            (inside groups)
//! sum       := term (('+' | '-') term)* [bar '_' script] (a bar: evaluated at)
//! term      := ('-' | '+') term | product
//! product   := factor (mulop? factor)*                   (juxtaposition = implicit)
//! factor    := atom scripts [ '(' args ')' scripts ]     (application after a symbol)
//!            | '\partial' product | '\lim' '_' script product
//! ```
//!
//! Every recursive step passes through [`Parser::nested`], which bounds the
//! nesting at [`crate::MAX_DEPTH`]; each token is read once (no
//! backtracking), so parsing is linear in the input.

mod atoms;
mod groups;
mod scripts;
mod spans;

use crate::ast::{Expr, MulOp, Rel, Sign, Statement};
use crate::error::{ErrorKind, Lines, ParseError};
use crate::lexer::{Tok, Token};
use crate::names::{MULOP_COMMANDS, RELATION_COMMANDS, lookup};

/// Deepest nesting of groups, signs, factors and commands accepted; deeper
/// input is an [`ErrorKind::TooDeep`] error, so hostile input cannot
/// overflow the stack.
pub const MAX_DEPTH: usize = 64;

/// Where the tokens come from, for error positions.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Place<'a> {
    /// The whole text error offsets and lines refer to.
    pub text: &'a str,
    /// Its line starts.
    pub lines: &'a Lines,
    /// Offset in `text` of the string the tokens index.
    pub base: usize,
    /// The formula's label.
    pub label: Option<&'a str>,
}

/// Which separators end an entry of the group being parsed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) enum Seps {
    /// None: wide spaces are ignored and `|` opens a norm.
    #[default]
    None,
    /// `\mid` (the two halves of a stacked fraction `\frac{R \mid t}{0 \mid 1}`).
    Mid,
    /// `\mid`, `|` and wide spaces (bracket groups and matrix entries).
    All,
}

/// Parsing context passed down within one group.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Ctx {
    /// A plain `|…|` (false) or `\|…\|` (true) norm is open at this level:
    /// the bar in operator position closes it.
    pub norm: Option<bool>,
    /// Separators ending an entry at this level.
    pub seps: Seps,
}

/// The parser over one statement's tokens.
pub(crate) struct Parser<'a> {
    src: &'a str,
    toks: Vec<Token>,
    /// For each `{`, the index of its `}` (and the reverse).
    matching: Vec<usize>,
    pos: usize,
    end: usize,
    depth: usize,
    place: Place<'a>,
}

/// What stands at an operator position.
enum Operator {
    Explicit(MulOp),
    Implicit,
    Stop,
}

impl<'a> Parser<'a> {
    /// A parser of `toks` (indexing `src`), or the error of an unbalanced brace.
    pub fn new(src: &'a str, toks: Vec<Token>, place: Place<'a>) -> Result<Self, ParseError> {
        let mut matching = vec![usize::MAX; toks.len()];
        let mut open = Vec::new();
        for (i, t) in toks.iter().enumerate() {
            match t.tok {
                Tok::LBrace => open.push(i),
                Tok::RBrace => {
                    let Some(o) = open.pop() else {
                        return Err(error_at(place, t.start, ErrorKind::UnbalancedBraces));
                    };
                    matching[o] = i;
                    matching[i] = o;
                }
                _ => {}
            }
        }
        if let Some(&o) = open.first() {
            return Err(error_at(place, toks[o].start, ErrorKind::UnbalancedBraces));
        }
        let end = toks.len();
        Ok(Parser {
            src,
            toks,
            matching,
            pos: 0,
            end,
            depth: 0,
            place,
        })
    }

    /// The whole input as one statement.
    pub fn statement(mut self) -> Result<Statement, ParseError> {
        self.skip_spaces();
        let implied = self.relation_here() == Some(Rel::Implies);
        if implied {
            self.pos += 1;
            self.skip_spaces();
            if self.peek().is_none() {
                return Err(self.error_before(ErrorKind::MissingOperand("\\Rightarrow".into())));
            }
        }
        let head = match self.relation_here() {
            Some(_) => None,
            None => Some(self.sum(Ctx::default())?),
        };
        let steps = self.steps(Ctx::default())?;
        self.skip_spaces();
        if self.peek().is_some() {
            return Err(self.unexpected());
        }
        Ok(Statement {
            implied,
            head,
            steps,
        })
    }

    /// The whole input as one expression.
    pub fn whole_expression(mut self) -> Result<Expr, ParseError> {
        let e = self.relation(Ctx::default())?;
        self.skip_spaces();
        if self.peek().is_some() {
            return Err(self.unexpected());
        }
        Ok(e)
    }

    // -- nesting, tokens and errors ------------------------------------------

    /// Runs `f` one nesting level deeper, failing beyond [`MAX_DEPTH`].
    fn nested<T>(
        &mut self,
        f: impl FnOnce(&mut Self) -> Result<T, ParseError>,
    ) -> Result<T, ParseError> {
        if self.depth >= MAX_DEPTH {
            return Err(self.error_here(ErrorKind::TooDeep(MAX_DEPTH)));
        }
        self.depth += 1;
        let r = f(self);
        self.depth -= 1;
        r
    }

    fn peek(&self) -> Option<&Tok> {
        (self.pos < self.end).then(|| &self.toks[self.pos].tok)
    }

    fn peek_at(&self, i: usize) -> Option<&Tok> {
        (i < self.end).then(|| &self.toks[i].tok)
    }

    /// The source text of token `i` (a macro's body token shows the
    /// invocation).
    fn text_of(&self, i: usize) -> &'a str {
        let t = &self.toks[i];
        self.src.get(t.start..t.end).unwrap_or("")
    }

    /// Skips wide spaces (in operand position, or where they only space).
    fn skip_spaces(&mut self) {
        while matches!(self.peek(), Some(Tok::Quad | Tok::Space)) {
            self.pos += 1;
        }
    }

    fn error_here(&self, kind: ErrorKind) -> ParseError {
        if self.pos < self.end {
            error_at(self.place, self.toks[self.pos].start, kind)
        } else {
            self.error_before(kind)
        }
    }

    /// An error at the end of the input: points at the last token read.
    fn error_before(&self, kind: ErrorKind) -> ParseError {
        let at = match self.pos.min(self.end).checked_sub(1) {
            Some(i) => self.toks[i].start,
            None => self.toks.first().map_or(0, |t| t.start),
        };
        error_at(self.place, at, kind)
    }

    /// The error for the token at the cursor, which nothing expects.
    fn unexpected(&self) -> ParseError {
        let kind = match self.peek() {
            None => ErrorKind::MissingOperand(
                self.pos
                    .checked_sub(1)
                    .map_or(String::new(), |i| self.text_of(i).to_string()),
            ),
            Some(Tok::Amp) => ErrorKind::StrayAmpersand,
            Some(Tok::RowBreak) => ErrorKind::StrayRowBreak,
            Some(_) => ErrorKind::Unexpected(self.text_of(self.pos).to_string()),
        };
        self.error_here(kind)
    }

    /// The relation at the cursor, if any.
    fn relation_here(&self) -> Option<Rel> {
        match self.peek()? {
            Tok::Eq => Some(Rel::Eq),
            Tok::Lt => Some(Rel::Lt),
            Tok::Gt => Some(Rel::Gt),
            Tok::Colon => Some(Rel::Colon),
            Tok::Command(c) => lookup(RELATION_COMMANDS, c),
            _ => None,
        }
    }

    // -- relations, sums, products -------------------------------------------

    /// A relation chain, or a single sum (inside a group).
    fn relation(&mut self, ctx: Ctx) -> Result<Expr, ParseError> {
        self.nested(|p| {
            p.skip_spaces();
            if p.relation_here().is_some() {
                let rel = p.text_of(p.pos).to_string();
                return Err(p.error_here(ErrorKind::RelationWithoutLeftSide(rel)));
            }
            let first = p.sum(ctx)?;
            let rest = p.steps(ctx)?;
            Ok(if rest.is_empty() {
                first
            } else {
                Expr::Relation {
                    first: Box::new(first),
                    rest,
                }
            })
        })
    }

    /// `(rel sum)*`.
    fn steps(&mut self, ctx: Ctx) -> Result<Vec<(Rel, Expr)>, ParseError> {
        let mut steps = Vec::new();
        loop {
            if ctx.seps != Seps::All {
                self.skip_spaces();
            }
            let Some(rel) = self.relation_here() else {
                return Ok(steps);
            };
            self.pos += 1;
            steps.push((rel, self.sum(ctx)?));
        }
    }

    /// Whether a bar followed by a subscript is at the cursor where no norm
    /// is open: an evaluation bar (`\left. … \right|` is read with its
    /// group).
    fn evaluation_bar_here(&self, ctx: Ctx) -> bool {
        ctx.norm.is_none()
            && self.peek() == Some(&Tok::Bar)
            && self.peek_at(self.pos + 1) == Some(&Tok::Sub)
    }

    fn sum(&mut self, ctx: Ctx) -> Result<Expr, ParseError> {
        let first = self.term(ctx)?;
        let mut rest = Vec::new();
        loop {
            if ctx.seps != Seps::All {
                self.skip_spaces();
            }
            let sign = match self.peek() {
                Some(Tok::Plus) => Sign::Plus,
                Some(Tok::Minus) => Sign::Minus,
                _ => break,
            };
            self.pos += 1;
            rest.push((sign, self.term(ctx)?));
        }
        let sum = if rest.is_empty() {
            first
        } else {
            Expr::Sum {
                first: Box::new(first),
                rest,
            }
        };
        // A side evaluated at a point: `\frac{d f}{d t} \Big\vert_{t=0}`.
        if self.evaluation_bar_here(ctx) {
            self.pos += 1;
            return self.evaluated_at(sum);
        }
        Ok(sum)
    }

    fn term(&mut self, ctx: Ctx) -> Result<Expr, ParseError> {
        self.nested(|p| {
            p.skip_spaces();
            match p.peek() {
                Some(Tok::Minus) => {
                    p.pos += 1;
                    Ok(Expr::Neg(Box::new(p.term(ctx)?)))
                }
                Some(Tok::Plus) => {
                    p.pos += 1;
                    Ok(Expr::Pos(Box::new(p.term(ctx)?)))
                }
                _ => p.product(ctx),
            }
        })
    }

    fn product(&mut self, ctx: Ctx) -> Result<Expr, ParseError> {
        let first = self.factor(ctx)?;
        let mut rest = Vec::new();
        loop {
            let op = match self.operator(ctx) {
                Operator::Stop => break,
                Operator::Implicit => MulOp::Implicit,
                Operator::Explicit(op) => {
                    self.pos += 1;
                    op
                }
            };
            rest.push((op, self.factor(ctx)?));
        }
        Ok(if rest.is_empty() {
            first
        } else {
            Expr::Product {
                first: Box::new(first),
                rest,
            }
        })
    }

    /// What the token at an operator position means.
    fn operator(&mut self, ctx: Ctx) -> Operator {
        loop {
            let Some(tok) = self.peek() else {
                return Operator::Stop;
            };
            return match tok {
                Tok::Quad | Tok::Space if ctx.seps == Seps::All => Operator::Stop,
                Tok::Quad | Tok::Space => {
                    self.pos += 1;
                    continue;
                }
                Tok::Star => Operator::Explicit(MulOp::Star),
                Tok::Slash => Operator::Explicit(MulOp::Slash),
                Tok::Command(c) => match lookup(MULOP_COMMANDS, c) {
                    Some(op) => Operator::Explicit(op),
                    None if self.starts_operand(self.pos) => Operator::Implicit,
                    None => Operator::Stop,
                },
                // A bar closes a norm open here, separates entries where
                // bars do, ends the side before an evaluation bar's
                // subscript, and otherwise opens a norm factor.
                Tok::Bar if self.evaluation_bar_here(ctx) => Operator::Stop,
                Tok::Bar if ctx.norm == Some(false) || ctx.seps == Seps::All => Operator::Stop,
                Tok::DoubleBar if ctx.norm == Some(true) => Operator::Stop,
                Tok::Bar | Tok::DoubleBar => Operator::Implicit,
                _ if self.starts_operand(self.pos) => Operator::Implicit,
                _ => Operator::Stop,
            };
        }
    }

    /// Whether token `i` can begin a factor.
    fn starts_operand(&self, i: usize) -> bool {
        match self.peek_at(i) {
            Some(
                Tok::Number(_)
                | Tok::Letter(_)
                | Tok::Word(_)
                | Tok::Text(_)
                | Tok::OperatorName(_)
                | Tok::LBrace
                | Tok::Open(_)
                | Tok::Left(_)
                | Tok::Begin(_)
                | Tok::Bar
                | Tok::DoubleBar,
            ) => true,
            // A frame's pre-scripts on the next symbol (`(…)^{I}_{G} \hat{R}`).
            Some(Tok::Sup | Tok::Sub) => self.frame_prescripts_follow(i),
            Some(Tok::Command(c)) => {
                c != "mid"
                    && lookup(RELATION_COMMANDS, c).is_none()
                    && lookup(MULOP_COMMANDS, c).is_none()
            }
            _ => false,
        }
    }

    /// Whether token `i` ends an entry or group whatever the context.
    fn closes(&self, i: usize) -> bool {
        matches!(
            self.peek_at(i),
            None | Some(
                Tok::RBrace
                    | Tok::Close(_)
                    | Tok::Right(_)
                    | Tok::Amp
                    | Tok::RowBreak
                    | Tok::End(_)
                    | Tok::Comma
                    | Tok::Bar
                    | Tok::DoubleBar
            )
        ) || matches!(self.peek_at(i), Some(Tok::Command(c)) if c == "mid")
    }
}

fn error_at(place: Place, offset: usize, kind: ErrorKind) -> ParseError {
    ParseError::at(
        place.text,
        place.lines,
        place.base + offset,
        place.label,
        kind,
    )
}
