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
    /// Its headings, in order.
    headings: Vec<Heading>,
}

/// A heading of the document: LaTeX's `\section{…}` and its kin,
/// Markdown's `#`, Doxygen's `@section name Title`.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Heading {
    /// Where it starts.
    at: usize,
    /// Its depth: a chapter or page 0, a section 1, a subsection 2, …
    level: usize,
    /// Its line as printed.
    text: String,
}

/// Where lookups search: a section of the document (from its heading to
/// the next heading of the same or a higher level) and, of several places
/// a quote matches there, which one (1-based, in document order).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Region {
    range: Option<Range<usize>>,
    occurrence: Option<usize>,
}

impl Region {
    /// The whole document, and a quote must match once.
    pub fn everywhere() -> Self {
        Region::default()
    }

    fn holds(&self, at: usize) -> bool {
        self.range.as_ref().is_none_or(|r| r.contains(&at))
    }

    /// The one place of `found` (by their lines, for the error), or the
    /// occurrence the region names.
    fn pick<T: Copy>(
        &self,
        quote: &str,
        found: Vec<(T, usize)>,
        none: impl FnOnce() -> Result<T, LookupError>,
    ) -> Result<T, LookupError> {
        match (found.as_slice(), self.occurrence) {
            ([], _) => none(),
            ([(one, _)], None | Some(1)) => Ok(*one),
            (many, Some(k)) if (1..=many.len()).contains(&k) => Ok(many[k - 1].0),
            (many, Some(k)) => Err(LookupError::NoOccurrence {
                quote: crate::error::one_line(quote, 60),
                count: many.len(),
                occurrence: k,
            }),
            (many, None) => Err(ambiguous(quote, many.iter().map(|(_, l)| *l).collect())),
        }
    }
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
        let formulas: Vec<Formula> = extract(text, options.syntax)?
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
        let headings = headings(text, &formulas);
        Ok(Document {
            text: text.to_string(),
            lines,
            formulas,
            vocabulary,
            read: OnceLock::new(),
            headings,
        })
    }

    /// The region of the section whose heading holds `section` (whitespace
    /// not counted), with the `occurrence` of a quote to take there.
    pub fn region(
        &self,
        section: Option<&str>,
        occurrence: Option<usize>,
    ) -> Result<Region, LookupError> {
        let range = match section {
            None => None,
            Some(quote) => {
                let key = squeeze(quote);
                let found: Vec<&Heading> = self
                    .headings
                    .iter()
                    .filter(|h| !key.is_empty() && squeeze(&h.text).contains(&key))
                    .collect();
                let shown = || crate::error::one_line(quote, 60);
                let h = match found.as_slice() {
                    [h] => *h,
                    [] => return Err(LookupError::NoSection(shown())),
                    many => {
                        return Err(LookupError::AmbiguousSection {
                            section: shown(),
                            lines: many.iter().map(|h| self.lines.line_of(h.at)).collect(),
                        });
                    }
                };
                let end = self
                    .headings
                    .iter()
                    .find(|n| n.at > h.at && n.level <= h.level)
                    .map_or(self.text.len(), |n| n.at);
                Some(h.at..end)
            }
        };
        Ok(Region { range, occurrence })
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
        self.find_in(&Region::everywhere(), locator)
    }

    /// [`Document::find`] in a region.
    pub fn find_in(&self, region: &Region, locator: Locator) -> Result<&Formula, LookupError> {
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
                    .filter(|f| region.holds(f.span.start))
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
                let found = self.formulas_with(region, a);
                let index = region.pick(a, found, || Ok(self.display_after(region, a)?.index))?;
                Ok(&self.formulas[index])
            }
        }
    }

    /// The formulas of `region` whose LaTeX holds `anchor`, with their lines.
    fn formulas_with(&self, region: &Region, anchor: &str) -> Vec<(usize, usize)> {
        let key = squeeze(anchor);
        self.formulas
            .iter()
            .filter(|f| region.holds(f.span.start) && squeeze(&f.source).contains(&key))
            .map(|f| (f.index, f.line))
            .collect()
    }

    /// Where an anchor is: the one formula whose LaTeX holds it, or, when
    /// none does, its one place in the prose and the display after it; the
    /// caller says whether the latter will do (it never is silently).
    pub fn locate(&self, anchor: &str) -> Result<Found<'_>, LookupError> {
        self.locate_in(&Region::everywhere(), anchor)
    }

    /// [`Document::locate`] in a region.
    pub fn locate_in(&self, region: &Region, anchor: &str) -> Result<Found<'_>, LookupError> {
        let found = self.formulas_with(region, anchor);
        if found.is_empty() {
            let (at, _) = self.place_in_text(region, anchor)?;
            let after = self.display_after(region, anchor)?;
            return Ok(Found::Prose {
                line: self.lines.line_of(at),
                after,
            });
        }
        let index = region.pick(anchor, found, || unreachable!("some formula holds it"))?;
        Ok(Found::Formula(&self.formulas[index]))
    }

    /// The first display after the one place the quote occurs in the text
    /// of `region`; a quote that spans a display is an error (the display
    /// after it is never taken for the one it spans; inline math may be
    /// quoted).
    fn display_after(&self, region: &Region, quote: &str) -> Result<&Formula, LookupError> {
        let (start, end) = self.place_in_text(region, quote)?;
        if let Some(f) = self
            .formulas
            .iter()
            .find(|f| f.kind == MathKind::Display && f.span.start < end && start < f.span.end)
        {
            return Err(LookupError::QuoteSpansFormula {
                quote: crate::error::one_line(quote, 60),
                line: f.line,
            });
        }
        self.formulas
            .iter()
            .find(|f| f.kind == MathKind::Display && f.span.start >= end)
            .ok_or_else(|| LookupError::NothingAfterAnchor(crate::error::one_line(quote, 60)))
    }

    /// The bytes of the one occurrence of `quote` in the text of `region`
    /// (whitespace not counted), or of the occurrence it names.
    fn place_in_text(&self, region: &Region, quote: &str) -> Result<(usize, usize), LookupError> {
        let key = squeeze(quote);
        if key.is_empty() {
            return Err(LookupError::NoAnchor(String::new()));
        }
        let (squeezed, offsets): (String, Vec<usize>) = self
            .text
            .char_indices()
            .filter(|(_, c)| !c.is_whitespace())
            .map(|(i, c)| (c, i))
            .unzip();
        let key_chars = key.chars().count();
        let hits: Vec<((usize, usize), usize)> = squeezed
            .match_indices(&key)
            .map(|(i, _)| {
                let first = squeezed[..i].chars().count();
                let last = offsets[first + key_chars - 1];
                let end = last + self.text[last..].chars().next().map_or(1, char::len_utf8);
                (offsets[first], end)
            })
            .filter(|(start, _)| region.holds(*start))
            .map(|place| (place, self.lines.line_of(place.0)))
            .collect();
        region.pick(quote, hits, || {
            Err(LookupError::NoAnchor(crate::error::one_line(quote, 60)))
        })
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
        self.claim_in(&Region::everywhere(), anchor)
    }

    /// [`Document::claim`] in a region.
    pub fn claim_in(&self, region: &Region, anchor: &str) -> Result<Claim, LookupError> {
        let (formula, line) = self.line_with(region, anchor)?;
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
        self.chain_in(&Region::everywhere(), locator)
    }

    /// [`Document::chain`] in a region.
    pub fn chain_in(&self, region: &Region, locator: Locator) -> Result<Vec<Claim>, LookupError> {
        let (formula, line) = match locator {
            Locator::Label(_) => (self.find_in(region, locator)?.index, 0),
            Locator::Anchor(a) => self.line_with(region, a)?,
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
    fn line_with(&self, region: &Region, anchor: &str) -> Result<(usize, usize), LookupError> {
        let key = squeeze(anchor);
        let mut found = Vec::new();
        for f in self.formulas.iter().filter(|f| region.holds(f.span.start)) {
            let Ok(lines) = self.lines_of(f.index) else {
                if squeeze(&f.source).contains(&key) {
                    found.push(((f.index, 0), f.line));
                }
                continue;
            };
            for (k, l) in lines.iter().enumerate() {
                let text = &f.source[l.span.clone()];
                if squeeze(text).contains(&key) {
                    found.push(((f.index, k), f.line));
                }
            }
        }
        region.pick(anchor, found, || {
            Ok((self.display_after(region, anchor)?.index, 0))
        })
    }

    /// The one line of any formula whose LaTeX holds the anchor, read;
    /// unlike [`Document::claim`], an anchor found only in the prose is an
    /// error ([`LookupError::AnchorInProse`]) naming where it is.
    pub fn claim_in_formulas(&self, anchor: &str) -> Result<Claim, LookupError> {
        self.claim_in_formulas_of(&Region::everywhere(), anchor)
    }

    /// [`Document::claim_in_formulas`] in a region.
    pub fn claim_in_formulas_of(
        &self,
        region: &Region,
        anchor: &str,
    ) -> Result<Claim, LookupError> {
        if self.formulas_with(region, anchor).is_empty() {
            let (at, _) = self.place_in_text(region, anchor)?;
            return Err(LookupError::AnchorInProse {
                anchor: crate::error::one_line(anchor, 60),
                line: self.lines.line_of(at),
            });
        }
        self.claim_in(region, anchor)
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

/// The headings of `text` outside its formulas: LaTeX's `\chapter`,
/// `\section`, `\subsection`, `\subsubsection`, `\paragraph` (starred or
/// not); Markdown's `#` lines; Doxygen's `@page`, `@section`,
/// `@subsection`, `@subsubsection` (or with `\`) lines.
fn headings(text: &str, formulas: &[Formula]) -> Vec<Heading> {
    const LATEX: [(&str, usize); 5] = [
        ("\\chapter", 0),
        ("\\section", 1),
        ("\\subsection", 2),
        ("\\subsubsection", 3),
        ("\\paragraph", 4),
    ];
    const DOXYGEN: [(&str, usize); 4] = [
        ("page", 0),
        ("section", 1),
        ("subsection", 2),
        ("subsubsection", 3),
    ];
    let in_formula = |at: usize| formulas.iter().any(|f| f.span.contains(&at));
    let mut out = Vec::new();
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        let trimmed = line.trim_start();
        let start = at + (line.len() - trimmed.len());
        at += line.len();
        if in_formula(start) {
            continue;
        }
        let level = if let Some(hashes) = trimmed
            .strip_prefix('#')
            .map(|rest| 1 + rest.chars().take_while(|c| *c == '#').count())
            .filter(|n| trimmed[*n..].starts_with(' '))
        {
            Some(hashes)
        } else if let Some((_, level)) = LATEX.iter().find(|(cmd, _)| {
            trimmed
                .strip_prefix(cmd)
                .is_some_and(|rest| rest.starts_with('{') || rest.starts_with("*{"))
        }) {
            Some(*level)
        } else {
            DOXYGEN
                .iter()
                .find(|(cmd, _)| {
                    ["@", "\\"].iter().any(|p| {
                        trimmed
                            .strip_prefix(p)
                            .and_then(|r| r.strip_prefix(cmd))
                            .is_some_and(|rest| rest.starts_with(' '))
                    })
                })
                .map(|(_, level)| *level)
        };
        if let Some(level) = level {
            out.push(Heading {
                at: start,
                level,
                text: trimmed.trim_end().to_string(),
            });
        }
    }
    out
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
