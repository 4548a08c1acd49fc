//! Groups: braces, delimited groups (grouping, tuples, block rows), norms,
//! `\lfloor…\rfloor_\times`, argument lists and environments (matrices,
//! `cases`).

use super::atoms::Atom;
use super::spans;
use super::{Ctx, Parser, Seps};
use crate::ast::{Case, Expr, Matrix};
use crate::error::{ErrorKind, ParseError};
use crate::lexer::{Delim, Tok};
use crate::names::{ALIGNMENT_ENVIRONMENTS, CASES_ENVIRONMENTS, MATRIX_ENVIRONMENTS};

impl Parser<'_> {
    /// `{…}`: a transparent group, or `{}` before pre-scripts.
    pub(super) fn brace_group(&mut self) -> Result<Atom, ParseError> {
        let close = self.matching[self.pos];
        if close == self.pos + 1 {
            self.pos = close + 1;
            if matches!(self.peek(), Some(Tok::Sub | Tok::Sup)) {
                return self.prescripted_symbol();
            }
            return Err(self.error_before(ErrorKind::Empty("group")));
        }
        self.pos += 1;
        let items = self.bounded(close, |p| p.list(Seps::None))?;
        if self.pos != close {
            return Err(self.unexpected());
        }
        self.pos = close + 1;
        Ok(Atom::Expr(self.build_group(items)?))
    }

    /// A group opened by a delimiter at the cursor: `(…)`, `[…]`, `\{…\}`,
    /// `\left…\right…`, a norm `|…|`/`\|…\|`, or `\lfloor…\rfloor_\times`.
    pub(super) fn delimited(&mut self) -> Result<Atom, ParseError> {
        let open = self.pos;
        let tok = self.toks[open].tok.clone();
        self.pos += 1;
        let (sized, delim) = match tok {
            Tok::Open(d) => (false, d),
            Tok::Left(d) => (true, d),
            Tok::Bar => (false, Delim::Bar),
            Tok::DoubleBar => (false, Delim::DoubleBar),
            _ => return Err(self.unexpected()),
        };
        let e = match delim {
            Delim::Bar | Delim::DoubleBar => {
                let double = delim == Delim::DoubleBar;
                // A plain bar closes at the same level; `\right|` is its own token.
                let ctx = Ctx {
                    norm: (!sized).then_some(double),
                    seps: Seps::None,
                };
                let body = self.relation(ctx)?;
                self.close(open, sized, delim)?;
                Expr::Norm {
                    double,
                    body: Box::new(body),
                }
            }
            Delim::Floor => {
                // `\left\lfloor v \times \right\rfloor` (the cross-product
                // matrix written with its `×` inside) is a skew matrix too.
                if let Some(times) = self.times_before_floor_close() {
                    let body = self.bounded(times, |p| p.relation(Ctx::default()))?;
                    if self.pos != times {
                        return Err(self.unexpected());
                    }
                    self.pos = times + 1;
                    self.close(open, sized, delim)?;
                    return Ok(Atom::Expr(Expr::Skew(Box::new(body))));
                }
                // `\lfloor v \rfloor_\times`, or `\lfloor v \rfloor` alone
                // (JPL and Trawny's notation for the same skew matrix).
                let body = self.relation(Ctx::default())?;
                self.close(open, sized, delim)?;
                if self.peek() == Some(&Tok::Sub) {
                    self.pos += 1;
                    if !self.script_argument(false)?.times {
                        return Err(self.error_before(ErrorKind::FloorSubscript));
                    }
                }
                Expr::Skew(Box::new(body))
            }
            _ => {
                let items = self.list(Seps::All)?;
                let closing_invisible =
                    sized && matches!(self.peek(), Some(Tok::Right(Delim::Invisible)));
                // `\left. X \right|_{x=0}`: `X` evaluated at a point.
                let evaluation = delim == Delim::Invisible
                    && matches!(self.peek(), Some(Tok::Right(Delim::Bar)))
                    && self.peek_at(self.pos + 1) == Some(&Tok::Sub);
                self.close(open, sized, delim)?;
                if evaluation {
                    let body = self.build_group(items)?;
                    return Ok(Atom::Expr(self.evaluated_at(body)?));
                }
                let group = self.build_group(items)?;
                match group {
                    // `\left\{ \begin{array}{ll} v & c \\ … \end{array} \right.`
                    // is a `cases`.
                    Expr::Matrix(m) if delim == Delim::Brace && closing_invisible => Expr::Cases(
                        m.rows
                            .into_iter()
                            .map(|mut row| {
                                let condition = (row.len() > 1).then(|| row.remove(1));
                                Case {
                                    value: row.remove(0),
                                    condition,
                                }
                            })
                            .collect(),
                    ),
                    other => other,
                }
            }
        };
        Ok(Atom::Expr(e))
    }

    /// `body` evaluated where the subscript at the cursor (after its bar)
    /// says; a subscript `r \times c` is a shape annotation instead
    /// (`\left. … \right|_{3 \times 9}`).
    pub(super) fn evaluated_at(&mut self, body: Expr) -> Result<Expr, ParseError> {
        self.pos += 1; // the `_`
        let at = self.script_expression(false)?;
        Ok(match at.shape_annotation() {
            Some((rows, cols)) => Expr::Shaped {
                base: Box::new(body),
                rows,
                cols,
            },
            None => Expr::At {
                body: Box::new(body),
                at: Box::new(at),
            },
        })
    }

    /// The index of a `\times` right before the `\rfloor` closing the
    /// floor opened at the cursor (the cursor is after the opener).
    fn times_before_floor_close(&self) -> Option<usize> {
        let mut depth = 0usize;
        for i in self.pos..self.end {
            match &self.toks[i].tok {
                Tok::Open(Delim::Floor) | Tok::Left(Delim::Floor) => depth += 1,
                Tok::Close(Delim::Floor) | Tok::Right(Delim::Floor) => {
                    if depth == 0 {
                        let before = i.checked_sub(1)?;
                        return (before >= self.pos
                            && self.toks[before].tok == Tok::Command("times".into()))
                        .then_some(before);
                    }
                    depth -= 1;
                }
                _ => {}
            }
        }
        None
    }

    /// Consumes the closing delimiter matching the one at `open`.
    fn close(&mut self, open: usize, sized: bool, delim: Delim) -> Result<(), ParseError> {
        let ok = match (self.peek(), sized) {
            (Some(Tok::Close(d)), false) => *d == delim,
            (Some(Tok::Bar), false) => delim == Delim::Bar,
            (Some(Tok::DoubleBar), false) => delim == Delim::DoubleBar,
            (Some(Tok::Right(d)), true) => {
                *d == delim || *d == Delim::Invisible || delim == Delim::Invisible
            }
            _ => false,
        };
        if ok {
            self.pos += 1;
            return Ok(());
        }
        let (left, right) = if sized {
            ("\\left", "\\right")
        } else {
            ("", "")
        };
        let err = ErrorKind::Unclosed {
            open: format!("{left}{}", delim.open()),
            expected: format!("{right}{}", delim.close()),
        };
        Err(match self.peek() {
            Some(_) => self.error_here(err),
            None => super::error_at(self.place, self.toks[open].start, err),
        })
    }

    /// `(a, b)` after a function or symbol: the arguments.
    pub(super) fn call_arguments(&mut self) -> Result<Vec<Expr>, ParseError> {
        let open = self.pos;
        let sized = matches!(self.toks[open].tok, Tok::Left(_));
        self.pos += 1;
        let items = self.list(Seps::All)?;
        self.close(open, sized, Delim::Paren)?;
        Ok(items.into_iter().map(row_or_entry).collect())
    }

    /// Comma-separated items, each a row of entries separated by the `seps`
    /// separators, up to the next closing token (not consumed).
    pub(super) fn list(&mut self, seps: Seps) -> Result<Vec<Vec<Expr>>, ParseError> {
        let mut items = Vec::new();
        let mut row = Vec::new();
        loop {
            self.skip_spaces();
            if self.no_entry_here() {
                let what = if items.is_empty() {
                    "group"
                } else {
                    "list item"
                };
                return Err(self.error_here(ErrorKind::Empty(what)));
            }
            row.push(self.relation(Ctx { norm: None, seps })?);
            let mut spaced = false;
            while matches!(self.peek(), Some(Tok::Quad | Tok::Space)) {
                self.pos += 1;
                spaced = true;
            }
            match self.peek() {
                Some(Tok::Comma) => {
                    self.pos += 1;
                    items.push(std::mem::take(&mut row));
                }
                Some(Tok::Bar) if seps == Seps::All => self.pos += 1,
                Some(Tok::Command(c)) if c == "mid" && seps != Seps::None => self.pos += 1,
                _ if self.closes(self.pos) => {
                    items.push(row);
                    return Ok(items);
                }
                _ if spaced && seps == Seps::All => {}
                _ => return Err(self.unexpected()),
            }
        }
    }

    /// Whether the cursor is where an entry should start but none does (a
    /// bar there opens a norm entry, as in `[|n| \mid v]`).
    fn no_entry_here(&self) -> bool {
        self.closes(self.pos) && !matches!(self.peek(), Some(Tok::Bar | Tok::DoubleBar))
    }

    /// One item of one entry is that entry (grouping); one item of several
    /// entries is a block row; several single-entry items are a tuple.
    pub(super) fn build_group(&self, mut items: Vec<Vec<Expr>>) -> Result<Expr, ParseError> {
        if items.len() == 1 {
            return Ok(row_or_entry(items.pop().expect("one item")));
        }
        if items.iter().any(|row| row.len() != 1) {
            return Err(self.error_before(ErrorKind::MixedSeparators));
        }
        Ok(Expr::Tuple(items.into_iter().flatten().collect()))
    }

    /// `\begin{name} … \end{name}` inside an expression.
    pub(super) fn environment(&mut self, name: &str) -> Result<Expr, ParseError> {
        if ALIGNMENT_ENVIRONMENTS.contains(&name) {
            return Err(self.error_here(ErrorKind::NestedAlignment(name.into())));
        }
        let is_matrix = MATRIX_ENVIRONMENTS.contains(&name);
        if !is_matrix && !CASES_ENVIRONMENTS.contains(&name) {
            return Err(self.error_here(ErrorKind::UnknownEnvironment(name.into())));
        }
        let begin = self.pos;
        self.pos += 1;
        let mut column_rules = Vec::new();
        if name == "array" || name == "subarray" {
            // The column specification (`{c|c}`) draws rules, which tell
            // which block an empty cell belongs to.
            if self.peek() != Some(&Tok::LBrace) {
                return Err(self.error_here(ErrorKind::MissingOperand("\\begin{array}".into())));
            }
            let close = self.matching[self.pos];
            column_rules = rules_of(&self.src[self.toks[self.pos].end..self.toks[close].start]);
            self.pos = close + 1;
        }
        self.nested(|p| {
            if is_matrix {
                p.matrix_rows(name, begin, column_rules)
            } else {
                p.case_rows(name, begin)
            }
        })
    }

    fn end_of(&mut self, name: &str, begin: usize) -> Result<bool, ParseError> {
        match self.peek() {
            Some(Tok::End(n)) if n == name => {
                self.pos += 1;
                Ok(true)
            }
            Some(Tok::End(_)) | None => Err(super::error_at(
                self.place,
                self.toks[begin].start,
                ErrorKind::UnclosedEnvironment(name.into()),
            )),
            _ => Ok(false),
        }
    }

    fn matrix_rows(
        &mut self,
        name: &str,
        begin: usize,
        column_rules: Vec<usize>,
    ) -> Result<Expr, ParseError> {
        let mut rows = Vec::new();
        let mut row_rules = Vec::new();
        while !self.end_of(name, begin)? {
            // An `\hline` (dropped by the lexer) in the gap before the row.
            let gap = self.toks[self.pos - 1].end;
            let mut row = Vec::new();
            loop {
                self.skip_spaces();
                if row.is_empty()
                    && self.pos < self.end
                    && self.src[gap..self.toks[self.pos].start].contains("\\hline")
                {
                    row_rules.push(rows.len());
                }
                if self.no_entry_here() {
                    // An empty cell: a block beside it may span it.
                    row.push(Err(self.pos.min(self.end.saturating_sub(1))));
                } else {
                    row.push(Ok(self.relation(Ctx {
                        norm: None,
                        seps: Seps::All,
                    })?));
                }
                let mut spaced = false;
                while matches!(self.peek(), Some(Tok::Quad | Tok::Space)) {
                    self.pos += 1;
                    spaced = true;
                }
                self.skip_row_punctuation();
                match self.peek() {
                    Some(Tok::Amp | Tok::Bar) => self.pos += 1,
                    Some(Tok::Command(c)) if c == "mid" => self.pos += 1,
                    Some(Tok::RowBreak) => {
                        self.pos += 1;
                        break;
                    }
                    Some(Tok::End(_)) | None => break,
                    _ if spaced => {}
                    _ => return Err(self.unexpected()),
                }
            }
            rows.push(row);
        }
        if rows.is_empty() {
            return Err(self.error_before(ErrorKind::Empty("matrix")));
        }
        spans::resolve(spans::Grid {
            cells: rows,
            column_rules,
            row_rules,
        })
        .map_err(|at| {
            super::error_at(
                self.place,
                self.toks[at].start,
                ErrorKind::Empty("matrix entry"),
            )
        })
    }

    fn case_rows(&mut self, name: &str, begin: usize) -> Result<Expr, ParseError> {
        let mut cases = Vec::new();
        while !self.end_of(name, begin)? {
            // A row of nothing (`~ \\`) between the cases is spacing.
            self.skip_spaces();
            if self.peek() == Some(&Tok::RowBreak) {
                self.pos += 1;
                continue;
            }
            let value = self.relation(Ctx::default())?;
            self.skip_row_punctuation();
            let condition = if self.peek() == Some(&Tok::Amp) {
                self.pos += 1;
                let c = self.relation(Ctx::default())?;
                self.skip_row_punctuation();
                Some(c)
            } else {
                None
            };
            match self.peek() {
                Some(Tok::RowBreak) => self.pos += 1,
                Some(Tok::End(_)) | None => {}
                _ => return Err(self.unexpected()),
            }
            cases.push(Case { value, condition });
        }
        if cases.is_empty() {
            return Err(self.error_before(ErrorKind::Empty("cases")));
        }
        Ok(Expr::Cases(cases))
    }
}

impl Parser<'_> {
    /// Skips a `,` or `.` ending a matrix entry or a case (`x, & y > 0 \\`).
    fn skip_row_punctuation(&mut self) {
        while matches!(self.peek(), Some(Tok::Comma | Tok::Period))
            && matches!(
                self.peek_at(self.pos + 1),
                None | Some(Tok::Amp | Tok::RowBreak | Tok::End(_))
            )
        {
            self.pos += 1;
        }
    }
}

/// A row of one entry is that entry; a longer row is a 1 × n matrix.
fn row_or_entry(mut row: Vec<Expr>) -> Expr {
    if row.len() == 1 {
        row.pop().expect("one entry")
    } else {
        Expr::Matrix(Matrix { rows: vec![row] })
    }
}

/// The column indices a `|` of an array's column specification stands
/// before (`c|ccc`: 1); none when the specification repeats (`*{3}{c}`).
fn rules_of(spec: &str) -> Vec<usize> {
    let mut rules = Vec::new();
    let mut columns = 0;
    let mut chars = spec.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '|' => rules.push(columns),
            'l' | 'c' | 'r' => columns += 1,
            // `p{3cm}`, `m{…}`, `b{…}` are columns; `@{…}`, `!{…}`,
            // `>{…}`, `<{…}` decorate them.
            'p' | 'm' | 'b' | 'X' | '@' | '!' | '>' | '<' => {
                if matches!(c, 'p' | 'm' | 'b' | 'X') {
                    columns += 1;
                }
                if chars.peek() == Some(&'{') {
                    let mut depth = 0;
                    for d in chars.by_ref() {
                        match d {
                            '{' => depth += 1,
                            '}' => {
                                depth -= 1;
                                if depth == 0 {
                                    break;
                                }
                            }
                            _ => {}
                        }
                    }
                }
            }
            '*' => return Vec::new(),
            _ => {}
        }
    }
    rules
}
