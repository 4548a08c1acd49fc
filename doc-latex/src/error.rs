//! Errors: a parse error names the formula, the byte offset and the fragment
//! it stopped at, on one line; a lookup error says what was not found.

use thiserror::Error;

/// What went wrong while reading a formula.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum ErrorKind {
    /// A `\` at the end of the input.
    #[error("lone backslash")]
    LoneBackslash,
    /// A `{` without its `}` or the reverse.
    #[error("unbalanced braces")]
    UnbalancedBraces,
    /// A `$$` display that is never closed.
    #[error("display math `$$` is never closed")]
    UnterminatedDisplay,
    /// A command the parser does not know.
    #[error("unknown command `\\{0}`")]
    UnknownCommand(String),
    /// An environment the parser does not know (or does not allow here).
    #[error("unknown environment `{0}`")]
    UnknownEnvironment(String),
    /// An alignment environment (`aligned`, `split`, …) inside an expression:
    /// only a whole display may be one.
    #[error("alignment environment `{0}` inside an expression")]
    NestedAlignment(String),
    /// `\end{a}` closing `\begin{b}`, or a `\begin` never closed.
    #[error("`\\begin{{{0}}}` is not closed by its `\\end`")]
    UnclosedEnvironment(String),
    /// A `&` outside a matrix, `cases` or alignment environment.
    #[error("stray `&`")]
    StrayAmpersand,
    /// A `\\` outside a matrix or multi-line environment.
    #[error("stray row break `\\\\`")]
    StrayRowBreak,
    /// An opening delimiter without its closing one (or a mismatched pair).
    #[error("`{open}` is not closed by `{expected}`")]
    Unclosed {
        /// The opening delimiter as printed.
        open: String,
        /// The closing delimiter it needs.
        expected: String,
    },
    /// Something the grammar does not allow at this place.
    #[error("unexpected `{0}`")]
    Unexpected(String),
    /// The input ended where an operand was needed.
    #[error("missing operand after `{0}`")]
    MissingOperand(String),
    /// A relation (`=`, `\approx`, …) with nothing on its left inside a group.
    #[error("relation `{0}` without a left side")]
    RelationWithoutLeftSide(String),
    /// `x^a^b` or `x_a_b`.
    #[error("double {0}script")]
    DoubleScript(&'static str),
    /// An empty group, matrix entry or list item.
    #[error("empty {0}")]
    Empty(&'static str),
    /// A group mixing `,` (a tuple) with row separators (a block row).
    #[error("a group mixes `,` with row separators")]
    MixedSeparators,
    /// A font or accent over more than one symbol.
    #[error("`\\{0}` over something other than one symbol")]
    NotASymbol(String),
    /// `\lfloor x \rfloor` with a subscript other than the `_\times` of a
    /// skew matrix.
    #[error("`\\lfloor … \\rfloor` with a subscript other than `_\\times`")]
    FloorSubscript,
    /// Nesting deeper than [`crate::MAX_DEPTH`].
    #[error("nesting deeper than {0} levels")]
    TooDeep(usize),
    /// A macro whose expansion does not end, or grows past the bounds of
    /// [`crate::macros`] (or uses a parameter it does not have).
    #[error("the macro `\\{0}` expands without end or past the bounds")]
    MacroExpansion(String),
}

/// A formula that could not be read: where (equation label, document line,
/// byte offset) and the fragment of LaTeX at that place. Displays as one line.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error(
    "{}, line {line}, byte {offset}: {} at `{fragment}`",
    place(.label),
    one_line(&.kind.to_string(), FRAGMENT_CHARS)
)]
pub struct ParseError {
    /// The equation label of the formula, as printed without parentheses
    /// (`"5"`, `"4.27"`), when it has one.
    pub label: Option<String>,
    /// The 1-based line of the document (or input) the error is on.
    pub line: usize,
    /// Byte offset of the offending fragment in the document (or input).
    pub offset: usize,
    /// The LaTeX from the offset on (at most [`FRAGMENT_CHARS`] characters,
    /// whitespace collapsed to single spaces).
    pub fragment: String,
    /// What is wrong.
    pub kind: ErrorKind,
}

/// Longest fragment quoted in a [`ParseError`].
pub const FRAGMENT_CHARS: usize = 40;

fn place(label: &Option<String>) -> String {
    match label {
        Some(l) => format!("equation ({l})"),
        None => "formula".to_string(),
    }
}

impl ParseError {
    /// An error of `kind` at byte `offset` of `text` (a whole document or a
    /// standalone input, whose line starts are `lines`), in the formula
    /// labelled `label`.
    pub(crate) fn at(
        text: &str,
        lines: &Lines,
        offset: usize,
        label: Option<&str>,
        kind: ErrorKind,
    ) -> Self {
        let offset = floor_char_boundary(text, offset.min(text.len()));
        ParseError {
            label: label.map(str::to_string),
            line: lines.line_of(offset),
            offset,
            fragment: one_line(&text[offset..], FRAGMENT_CHARS),
            kind,
        }
    }
}

/// Where the lines of a text start, to turn byte offsets into line numbers
/// in logarithmic time.
#[derive(Debug, Clone)]
pub(crate) struct Lines {
    starts: Vec<usize>,
}

impl Lines {
    /// The line starts of `text`.
    pub(crate) fn new(text: &str) -> Self {
        let starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Lines { starts }
    }

    /// The 1-based line holding byte `offset`.
    pub(crate) fn line_of(&self, offset: usize) -> usize {
        self.starts.partition_point(|&s| s <= offset)
    }
}

/// A document lookup that found nothing, or more than one thing.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum LookupError {
    /// No formula carries the label.
    #[error("no formula is labelled ({0})")]
    NoLabel(String),
    /// Several formulas carry the label.
    #[error("{count} formulas are labelled ({label})")]
    DuplicateLabel {
        /// The label.
        label: String,
        /// How many formulas carry it.
        count: usize,
    },
    /// The anchor occurs nowhere in the document.
    #[error("the anchor `{0}` occurs nowhere in the document")]
    NoAnchor(String),
    /// The anchor occurs in several places; quote more of it, or say which.
    #[error(
        "the anchor `{anchor}` occurs in {count} places (lines {}); quote more of it, or say \
         which with `section` (a piece of its heading) or `occurrence` (1 to {count})",
        lines.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")
    )]
    AmbiguousAnchor {
        /// The anchor (on one line).
        anchor: String,
        /// How many places it occurs in.
        count: usize,
        /// The document line of each place.
        lines: Vec<usize>,
    },
    /// The anchor is in the prose only, not in any formula.
    #[error(
        "the anchor `{anchor}` is in no formula, only in the prose at line {line}; to audit the \
         display after it, locate it with `after`"
    )]
    AnchorInProse {
        /// The anchor (on one line).
        anchor: String,
        /// Its line.
        line: usize,
    },
    /// The anchor is in the prose, and no display formula follows it.
    #[error("no display formula follows the anchor `{0}`")]
    NothingAfterAnchor(String),
    /// No heading holds the quoted section.
    #[error("no heading holds `{0}`")]
    NoSection(String),
    /// Several headings hold the quoted section.
    #[error(
        "the section `{section}` is in several headings (lines {}); quote more of it",
        lines.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")
    )]
    AmbiguousSection {
        /// The quote.
        section: String,
        /// The line of each heading.
        lines: Vec<usize>,
    },
    /// The occurrence asked for is past the places the quote matches.
    #[error("`{quote}` occurs in {count} place(s) here, so there is no occurrence {occurrence}")]
    NoOccurrence {
        /// The quote.
        quote: String,
        /// How many places it occurs in.
        count: usize,
        /// The occurrence asked for.
        occurrence: usize,
    },
    /// A quote locating the display after it spans a formula: the display
    /// after would not be the one it is written before.
    #[error(
        "the quote `{quote}` spans the formula on line {line}: quote the prose before a display \
         only"
    )]
    QuoteSpansFormula {
        /// The quote.
        quote: String,
        /// The formula's line.
        line: usize,
    },
    /// The formula found holds no math (`$$(4.25)$$`).
    #[error("the formula on line {0} holds no math")]
    Empty(usize),
    /// The formula found could not be split into lines.
    #[error(transparent)]
    Parse(#[from] ParseError),
}

/// `s` with whitespace runs collapsed to one space, cut to `max` characters.
pub(crate) fn one_line(s: &str, max: usize) -> String {
    let mut out = String::new();
    let mut space = false;
    for (n, c) in s.chars().enumerate() {
        if n >= max {
            out.push('…');
            break;
        }
        if c.is_whitespace() || c.is_control() {
            space = true;
        } else {
            if space && !out.is_empty() {
                out.push(' ');
            }
            space = false;
            out.push(c);
        }
    }
    out
}

fn floor_char_boundary(s: &str, mut i: usize) -> usize {
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn displays_on_one_line_with_label_and_fragment() {
        let text = "ab\n$$\\frac{1}\n{2$$";
        let e = ParseError::at(
            text,
            &Lines::new(text),
            5,
            Some("5"),
            ErrorKind::UnbalancedBraces,
        );
        let shown = e.to_string();
        assert_eq!(
            shown,
            "equation (5), line 2, byte 5: unbalanced braces at `\\frac{1} {2$$`"
        );
        assert!(!shown.contains('\n'));
    }

    #[test]
    fn fragment_is_cut_and_offset_kept_on_a_char_boundary() {
        let text = "ωωωω";
        let e = ParseError::at(text, &Lines::new(text), 3, None, ErrorKind::Empty("group"));
        assert_eq!(e.offset, 2);
        assert_eq!(one_line(&"x".repeat(100), 4), "xxxx…");
    }
}
