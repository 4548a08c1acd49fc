//! A document's formulas, found by label or anchor, and read as claims: one
//! per line, each with the left side of the chain it belongs to.
//!
//! A display that starts with a relation (`= …`) continues the chain of the
//! displays just before it (with only whitespace and label lines between):
//! its left side is the last chain head of that run of displays.

use std::ops::Range;
use std::sync::OnceLock;

use crate::ast::{Expr, Statement};
use crate::error::{Lines, LookupError, ParseError};
use crate::extract::{MathKind, Syntax, extract};
use crate::lines::{Line, lines};
use crate::macros::Vocabulary;
use crate::parser::{Parser, Place};

/// How to read a document: its syntax, and words its formulas use as
/// function names (`between(a, b)`) besides the built-in ones.
#[derive(Debug, Clone, Copy, Default)]
pub struct Options<'a> {
    /// Markdown (the default) or LaTeX.
    pub syntax: Syntax,
    /// Extra function words.
    pub words: &'a [&'a str],
}

/// A Markdown/LaTeX document and the formulas found in it.
#[derive(Debug, Clone)]
pub struct Document {
    text: String,
    lines: Lines,
    formulas: Vec<Formula>,
    /// Its macros and function words.
    vocabulary: Vocabulary,
    /// Every formula's claims, read run by run on the first lookup that
    /// needs them, so that lookups stay linear in the document together.
    read: OnceLock<Vec<Result<Vec<Claim>, ParseError>>>,
}

/// One formula of a document, as printed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Formula {
    /// Its position among the document's formulas.
    pub index: usize,
    /// Display or inline.
    pub kind: MathKind,
    /// Its equation label, without parentheses (`"5"`, `"4.27"`).
    pub label: Option<String>,
    /// Its `\label{…}` names (`eq:Rot3action`).
    pub names: Vec<String>,
    /// The bytes between its delimiters.
    pub span: Range<usize>,
    /// The 1-based line where it starts.
    pub line: usize,
    /// The LaTeX between its delimiters.
    pub source: String,
    /// `source` with the label blanked out (same length).
    math: String,
    /// Only whitespace since the previous display: it may continue its chain.
    follows_display: bool,
    /// The alignment environment its delimiters open (`\begin{align}`).
    environment: Option<String>,
}

/// One line of a formula, read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Claim {
    /// The formula's label.
    pub label: Option<String>,
    /// The 1-based document line the claim starts on.
    pub line: usize,
    /// Its bytes in the document.
    pub span: Range<usize>,
    /// Its LaTeX as printed.
    pub source: String,
    /// The line starts with a relation: its left side is written earlier.
    pub continued: bool,
    /// The left side of the chain this line belongs to: its own head, or for
    /// a continued line the head of the chain it continues (`None` when that
    /// could not be read, or the line has no top-level relation).
    pub lhs: Option<Expr>,
    /// The line's statement.
    pub statement: Result<Statement, ParseError>,
    /// Side notes printed after it (`\quad θ = |ω|`, `(BCH formula)`).
    pub notes: Vec<Result<Statement, ParseError>>,
    /// The environment around the whole display (`cases`, `split`, …) when
    /// the display never closes it: it was read as closed at its end.
    pub unclosed_environment: Option<String>,
}

impl Claim {
    /// The value the line arrives at ([`Statement::rhs`]), if it was read.
    pub fn rhs(&self) -> Option<&Expr> {
        self.statement.as_ref().ok()?.rhs()
    }
}

/// How to find a formula: by its printed label or by a piece of its text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Locator<'a> {
    /// An equation label, with or without parentheses (`"(5)"`, `"4.27"`),
    /// or the name of a `\label{…}` (`eq:Rot3action`).
    Label(&'a str),
    /// A piece of LaTeX inside the formula (whitespace does not matter) or,
    /// failing that, of the prose just before it.
    Anchor(&'a str),
}

/// Where an anchor was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Found<'d> {
    /// Inside this formula's LaTeX.
    Formula(&'d Formula),
    /// Only in the prose, at this line; the formula is the first display
    /// after it.
    Prose {
        /// The document line of the anchor.
        line: usize,
        /// The display after it.
        after: &'d Formula,
    },
}

impl<'a> Locator<'a> {
    /// `"(5)"` or `"(4.27)"` is a label, anything else an anchor.
    pub fn parse(s: &'a str) -> Self {
        let t = s.trim();
        let inner = t.strip_prefix('(').and_then(|t| t.strip_suffix(')'));
        match inner {
            Some(l)
                if !l.trim().is_empty()
                    && l.trim().bytes().all(|c| c.is_ascii_digit() || c == b'.') =>
            {
                Locator::Label(l.trim())
            }
            _ => Locator::Anchor(s),
        }
    }
}

impl Document {
    /// The formulas of a Markdown `text`; fails only on a display never
    /// closed.
    pub fn parse(text: &str) -> Result<Self, ParseError> {
        Self::parse_with(text, Options::default())
    }

    /// The formulas of `text` read as `options` say; fails only on a
    /// display never closed.
    pub fn parse_with(text: &str, options: Options) -> Result<Self, ParseError> {
        let lines = Lines::new(text);
        let vocabulary = Vocabulary::scan(text, options.words, options.syntax == Syntax::Latex);
        let formulas = extract(text, options.syntax)?
            .into_iter()
            .enumerate()
            .map(|(index, f)| {
                let source = text[f.span.clone()].to_string();
                let mut math = source.clone();
                if let Some(r) = &f.label_span {
                    math.replace_range(r.clone(), &" ".repeat(r.len()));
                }
                Formula {
                    index,
                    kind: f.kind,
                    label: f.label,
                    names: f.names,
                    line: lines.line_of(f.span.start),
                    span: f.span,
                    source,
                    math,
                    follows_display: f.follows_display,
                    environment: f.environment,
                }
            })
            .collect();
        Ok(Document {
            text: text.to_string(),
            lines,
            formulas,
            vocabulary,
            read: OnceLock::new(),
        })
    }

    /// Its macros and function words: what the caller reads LaTeX written
    /// about the document with ([`crate::parse_expr_with`]).
    pub fn vocabulary(&self) -> &Vocabulary {
        &self.vocabulary
    }

    /// The document's text.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Every formula, in order.
    pub fn formulas(&self) -> &[Formula] {
        &self.formulas
    }

    /// The formula a locator names: the one carrying the label, or the one
    /// whose LaTeX contains the anchor (else the first display after the
    /// anchor's place in the prose). Exactly one must match.
    pub fn find(&self, locator: Locator) -> Result<&Formula, LookupError> {
        match locator {
            Locator::Label(l) => {
                let l = l
                    .trim()
                    .trim_start_matches('(')
                    .trim_end_matches(')')
                    .trim();
                let shown = || crate::error::one_line(l, 60);
                let found: Vec<&Formula> = self
                    .formulas
                    .iter()
                    .filter(|f| f.label.as_deref() == Some(l) || f.names.iter().any(|n| n == l))
                    .collect();
                match found.as_slice() {
                    [f] => Ok(f),
                    [] => Err(LookupError::NoLabel(shown())),
                    many => Err(LookupError::DuplicateLabel {
                        label: shown(),
                        count: many.len(),
                    }),
                }
            }
            Locator::Anchor(a) => {
                let key = squeeze(a);
                let found: Vec<&Formula> = self
                    .formulas
                    .iter()
                    .filter(|f| squeeze(&f.source).contains(&key))
                    .collect();
                match found.as_slice() {
                    [f] => Ok(f),
                    [] => self.display_after(a),
                    many => Err(ambiguous(a, many.iter().map(|f| f.line).collect())),
                }
            }
        }
    }

    /// Where an anchor is: the one formula whose LaTeX holds it, or, when
    /// none does, its one place in the prose and the display after it; the
    /// caller says whether the latter will do (it never is silently).
    pub fn locate(&self, anchor: &str) -> Result<Found<'_>, LookupError> {
        let key = squeeze(anchor);
        let found: Vec<&Formula> = self
            .formulas
            .iter()
            .filter(|f| squeeze(&f.source).contains(&key))
            .collect();
        match found.as_slice() {
            [f] => Ok(Found::Formula(f)),
            [] => {
                let at = self.place_in_text(anchor)?;
                let after = self.display_after(anchor)?;
                Ok(Found::Prose {
                    line: self.lines.line_of(at),
                    after,
                })
            }
            many => Err(ambiguous(anchor, many.iter().map(|f| f.line).collect())),
        }
    }

    /// The first display after the one place the anchor occurs in the text.
    fn display_after(&self, anchor: &str) -> Result<&Formula, LookupError> {
        let at = self.place_in_text(anchor)?;
        self.formulas
            .iter()
            .find(|f| f.kind == MathKind::Display && f.span.start > at)
            .ok_or_else(|| LookupError::NothingAfterAnchor(crate::error::one_line(anchor, 60)))
    }

    /// The byte offset of the one occurrence of `anchor` in the text
    /// (whitespace not counted).
    fn place_in_text(&self, anchor: &str) -> Result<usize, LookupError> {
        let key = squeeze(anchor);
        if key.is_empty() {
            return Err(LookupError::NoAnchor(String::new()));
        }
        let (squeezed, offsets): (String, Vec<usize>) = self
            .text
            .char_indices()
            .filter(|(_, c)| !c.is_whitespace())
            .map(|(i, c)| (c, i))
            .unzip();
        let hits: Vec<usize> = squeezed
            .match_indices(&key)
            .map(|(i, _)| offsets[squeezed[..i].chars().count()])
            .collect();
        match hits.as_slice() {
            [at] => Ok(*at),
            [] => Err(LookupError::NoAnchor(crate::error::one_line(anchor, 60))),
            many => Err(ambiguous(
                anchor,
                many.iter().map(|at| self.lines.line_of(*at)).collect(),
            )),
        }
    }

    /// The claims of a formula of this document, one per line.
    pub fn claims(&self, formula: &Formula) -> Result<Vec<Claim>, ParseError> {
        self.all_claims()[formula.index].clone()
    }

    /// Every formula's claims, read once.
    fn all_claims(&self) -> &[Result<Vec<Claim>, ParseError>] {
        self.read.get_or_init(|| {
            let mut all = Vec::with_capacity(self.formulas.len());
            while all.len() < self.formulas.len() {
                let run = self.run_of(all.len());
                all.extend(self.read_run(run).into_iter().map(|(_, c)| c));
            }
            all
        })
    }

    /// The claims of every formula of a run (read once, see [`Document::all_claims`]).
    fn run_claims(&self, run: Range<usize>) -> Vec<(usize, Result<Vec<Claim>, ParseError>)> {
        let all = self.all_claims();
        run.map(|i| (i, all[i].clone())).collect()
    }

    /// The one line (of any formula) whose LaTeX contains the anchor, read.
    pub fn claim(&self, anchor: &str) -> Result<Claim, LookupError> {
        let (formula, line) = self.line_with(anchor)?;
        let claims = self.claims(&self.formulas[formula])?;
        claims
            .into_iter()
            .nth(line)
            .ok_or(LookupError::Empty(self.formulas[formula].line))
    }

    /// A chain of equalities: the line a locator names (a label names the
    /// formula's first line) and the lines after it that continue it, across
    /// displays, skipping side notes. The last claim is the chain's result.
    pub fn chain(&self, locator: Locator) -> Result<Vec<Claim>, LookupError> {
        let (formula, line) = match locator {
            Locator::Label(_) => (self.find(locator)?.index, 0),
            Locator::Anchor(a) => self.line_with(a)?,
        };
        let mut chain = Vec::new();
        for (i, claims) in self.run_claims(self.run_of(formula)) {
            if i < formula {
                continue;
            }
            let lines = self.lines_of(i)?;
            let claims = claims?;
            for (k, (claim, l)) in claims.into_iter().zip(&lines).enumerate() {
                if i == formula && k < line {
                    continue;
                }
                if chain.is_empty() || l.continued {
                    chain.push(claim);
                } else if l.heads_chain {
                    return Ok(chain);
                }
            }
        }
        if chain.is_empty() {
            return Err(LookupError::Empty(self.formulas[formula].line));
        }
        Ok(chain)
    }

    /// `(formula, line)` of the one line containing the anchor; failing
    /// that, the first line of the display after its place in the prose.
    fn line_with(&self, anchor: &str) -> Result<(usize, usize), LookupError> {
        let key = squeeze(anchor);
        let mut found = Vec::new();
        for f in &self.formulas {
            let Ok(lines) = self.lines_of(f.index) else {
                if squeeze(&f.source).contains(&key) {
                    found.push((f.index, 0));
                }
                continue;
            };
            for (k, l) in lines.iter().enumerate() {
                let text = &f.source[l.span.clone()];
                if squeeze(text).contains(&key) {
                    found.push((f.index, k));
                }
            }
        }
        match found.as_slice() {
            [one] => Ok(*one),
            [] => Ok((self.display_after(anchor)?.index, 0)),
            many => Err(ambiguous(
                anchor,
                many.iter().map(|(f, _)| self.formulas[*f].line).collect(),
            )),
        }
    }

    /// The one line of any formula whose LaTeX holds the anchor, read;
    /// unlike [`Document::claim`], an anchor found only in the prose is an
    /// error ([`LookupError::AnchorInProse`]) naming where it is.
    pub fn claim_in_formulas(&self, anchor: &str) -> Result<Claim, LookupError> {
        let key = squeeze(anchor);
        let in_formula = self
            .formulas
            .iter()
            .any(|f| squeeze(&f.source).contains(&key));
        if !in_formula {
            let at = self.place_in_text(anchor)?;
            return Err(LookupError::AnchorInProse {
                anchor: crate::error::one_line(anchor, 60),
                line: self.lines.line_of(at),
            });
        }
        self.claim(anchor)
    }

    /// The formula's lines, or the error that keeps it from being split.
    fn lines_of(&self, index: usize) -> Result<Vec<Line>, ParseError> {
        let f = &self.formulas[index];
        lines(
            &f.math,
            &self.vocabulary,
            f.span.start,
            f.environment.as_deref(),
        )
        .map_err(|(offset, kind)| {
            ParseError::at(
                &self.text,
                &self.lines,
                f.span.start + offset,
                f.label.as_deref(),
                kind,
            )
        })
    }

    /// The displays whose chains `index` may continue or be continued by.
    fn run_of(&self, index: usize) -> Range<usize> {
        let mut start = index;
        while start > 0 && self.formulas[start].follows_display {
            start -= 1;
        }
        let mut end = index + 1;
        while end < self.formulas.len() && self.formulas[end].follows_display {
            end += 1;
        }
        start..end
    }

    /// The claims of every formula of a run, chain heads carried along.
    fn read_run(&self, run: Range<usize>) -> Vec<(usize, Result<Vec<Claim>, ParseError>)> {
        let mut head: Option<Expr> = None;
        run.map(|i| {
            let f = &self.formulas[i];
            let lines = match self.lines_of(i) {
                Ok(lines) => lines,
                Err(e) => {
                    head = None;
                    return (i, Err(e));
                }
            };
            let place = Place {
                text: &self.text,
                lines: &self.lines,
                base: f.span.start,
                label: f.label.as_deref(),
            };
            let claims = lines
                .into_iter()
                .map(|line| {
                    let mut statements = line
                        .statements
                        .into_iter()
                        .map(|toks| Parser::new(&f.math, toks, place)?.statement());
                    let statement = statements.next().expect("a line has a statement");
                    let notes: Vec<_> = statements.collect();
                    let own_head = statement.as_ref().ok().and_then(|s| s.head.clone());
                    let lhs = if line.continued {
                        head.clone()
                    } else if line.heads_chain {
                        head = own_head.clone();
                        own_head
                    } else {
                        None
                    };
                    let span = f.span.start + line.span.start..f.span.start + line.span.end;
                    Claim {
                        label: f.label.clone(),
                        line: self.lines.line_of(span.start),
                        source: self.text[span.clone()].to_string(),
                        span,
                        continued: line.continued,
                        lhs,
                        statement,
                        notes,
                        unclosed_environment: line.unclosed,
                    }
                })
                .collect();
            (i, Ok(claims))
        })
        .collect()
    }
}

/// `s` without whitespace: anchors match however the LaTeX is spaced.
fn squeeze(s: &str) -> String {
    s.chars().filter(|c| !c.is_whitespace()).collect()
}

fn ambiguous(anchor: &str, lines: Vec<usize>) -> LookupError {
    LookupError::AmbiguousAnchor {
        anchor: crate::error::one_line(anchor, 60),
        count: lines.len(),
        lines,
    }
}
