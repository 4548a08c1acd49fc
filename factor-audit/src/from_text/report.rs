//! Findings of an audit from a document's text, and their reports: every
//! claim of the symbols file, with its verdict (the vocabulary of
//! [`crate::verdict`]) or why it could not be read; the formula quoted as
//! printed with its place, the formula as the parser understood it, and the
//! engine's diagnosis with the printed formula corrected, in the
//! document's own terms.

use std::fmt::Write;

use super::errata::Diagnosis;
use super::load::Unread;
use super::symbols::one_line;
use crate::report::note;
use crate::verdict::{Finding, Verdict};

/// Longest expanded correct expression a text report shows (it is in the
/// stored scalars' names, not the document's terms): twice the printed
/// formula, or this many characters for a short one.
pub const MAX_EXPANSION_CHARS: usize = 240;

/// Whether an expanded correct expression is short enough to help a
/// reader of a formula printed as `quote`.
pub fn expansion_fits(expansion: &str, quote: &str) -> bool {
    expansion.chars().count() <= MAX_EXPANSION_CHARS.max(2 * quote.chars().count())
}

/// The audit of one claim of a document.
#[derive(Debug, Clone, PartialEq)]
pub struct TextFinding {
    /// The verdict, as for a transcription.
    pub finding: Finding,
    /// The document line the formula starts on.
    pub line: usize,
    /// The formula's line as printed.
    pub quote: String,
    /// The audited line as understood, rendered back as LaTeX.
    pub understood: String,
    /// The verdict the symbols file expects.
    pub expected: String,
    /// The engine's diagnosis of a wrong or malformed formula.
    pub diagnosis: Option<Diagnosis>,
    /// What a reader should know of how the formula was read.
    pub notes: Vec<String>,
    /// Edited formulas the erratum search evaluated, when it ran.
    pub searched: Option<usize>,
}

impl TextFinding {
    /// Whether it should fail a gated run: a verdict other than expected.
    pub fn is_unexpected(&self) -> bool {
        self.finding.verdict.keyword() != self.expected
    }

    /// The verdict's explanation (a diagnosis of a malformed formula is
    /// added to why it is malformed), then how the formula was read.
    pub fn note(&self) -> String {
        let base = note(&self.finding);
        let base = match (&self.finding.verdict, &self.diagnosis) {
            (Verdict::Malformed(_), Some(d)) => format!("{base}; suspected erratum: {}", d.words),
            _ => base,
        };
        std::iter::once(base)
            .chain(self.notes.iter().cloned())
            .filter(|n| !n.is_empty())
            .collect::<Vec<_>>()
            .join("; ")
    }
}

/// Text from the document or the symbols file (a claim id, a file name,
/// a note quoting them) as one printable line: control, separator and
/// format characters escaped (`slamjac_io::printable`).
fn shown(text: &str) -> std::borrow::Cow<'_, str> {
    slamjac_io::printable::escape(text)
}

/// A fixed-width table for the terminal, one row per claim: the audited
/// ones, then those that could not be read.
pub fn table(findings: &[TextFinding], unread: &[Unread]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<26} {:<22} {:>5} {:<11} {:>9}  note",
        "document", "equation", "line", "verdict", "max err"
    );
    for t in findings {
        let f = &t.finding;
        let error = f
            .max_relative_error
            .map_or("—".into(), |e| format!("{e:.1e}"));
        let expected = if t.is_unexpected() {
            format!(" (UNEXPECTED: {} expected)", t.expected)
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            "{:<26} {:<22} {:>5} {:<11} {:>9}  {}{}",
            shown(&f.label.document),
            shown(&f.label.equation),
            t.line,
            f.verdict.keyword(),
            error,
            shown(&t.note()),
            expected
        );
    }
    for u in unread {
        let expected = if u.is_unexpected() {
            format!(" (UNREAD: {} expected)", u.expected)
        } else {
            String::new()
        };
        let erratum = u
            .suspected_erratum()
            .map(|e| format!(" (suspected erratum: {e})"))
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "{:<26} {:<22} {:>5} {:<11} {:>9}  {}{}{}",
            "",
            shown(&u.id),
            u.line.map_or("—".into(), |l| l.to_string()),
            "unread",
            "—",
            one_line(&u.error.to_string()),
            erratum,
            expected
        );
    }
    out
}

/// A Markdown report: a summary table, then each formula with its quote,
/// what was understood, the verdict, the diagnosis and the corrections,
/// then each claim that could not be read with why.
pub fn markdown(findings: &[TextFinding], unread: &[Unread]) -> String {
    let mut out = String::from(
        "# Derivation audit from the document's text\n\n| document | equation | line | verdict | max relative error | note |\n| --- | --- | --- | --- | --- | --- |\n",
    );
    let cell = |s: &str| shown(s).replace('|', "\\|");
    for t in findings {
        let f = &t.finding;
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} |",
            cell(&f.label.document),
            cell(&f.label.equation),
            t.line,
            f.verdict.keyword(),
            f.max_relative_error
                .map_or("—".into(), |e| format!("{e:.1e}")),
            cell(&t.note())
        );
    }
    for t in findings {
        let f = &t.finding;
        let _ = write!(
            out,
            "\n## {} {} (line {})\n\n{}\n\nAs printed:\n\n```latex\n{}\n```\n\nAs understood:\n\n$$\n{}\n$$\n\n- convention: {}\n- verdict: **{}** {}\n",
            shown(&f.label.document),
            shown(&f.label.equation),
            t.line,
            f.label.claim,
            t.quote,
            t.understood,
            f.label.convention,
            f.verdict.keyword(),
            if t.diagnosis.is_some() && matches!(f.verdict, Verdict::Wrong(_)) {
                String::new()
            } else {
                t.note()
            }
        );
        if let Some(known) = &f.label.known_erratum {
            let _ = writeln!(out, "- recorded note: {known}");
        }
        if let Some(localisation) = &f.localisation {
            let _ = writeln!(out, "- chain rule: {localisation}");
        }
        match (&t.diagnosis, t.searched) {
            (Some(d), Some(n)) => {
                let _ = writeln!(
                    out,
                    "- suspected erratum ({}; {n} edited formulas evaluated): {}\n\nThe printed formula corrected:\n\n$$\n{}\n$$",
                    if d.complete {
                        "the corrected formula agrees at every sample"
                    } else {
                        "partial"
                    },
                    d.words,
                    d.corrected
                );
            }
            (None, Some(n)) => {
                let _ = writeln!(
                    out,
                    "- no edit of the search space fixes it ({n} edited formulas evaluated)"
                );
            }
            _ => {}
        }
        match &f.corrected_latex {
            Some(latex) => {
                let _ = writeln!(
                    out,
                    "\nThe correct expression, expanded:\n\n$$\n{latex}\n$$"
                );
            }
            None if t.diagnosis.is_none()
                && matches!(f.verdict, Verdict::Wrong(_) | Verdict::Malformed(_)) =>
            {
                let _ = writeln!(
                    out,
                    "- no correction in the document's terms: no edit of the search space fixes \
                     it, and the expanded expression is too long to help"
                );
            }
            None => {}
        }
    }
    if !unread.is_empty() {
        let _ = writeln!(out, "\n# Claims that could not be read\n");
        for u in unread {
            let _ = writeln!(
                out,
                "- {} ({}): {}{}{}",
                cell(&u.id),
                u.line
                    .map_or("not found".to_string(), |l| format!("line {l}")),
                one_line(&u.error.to_string()).replace('|', "\\|"),
                u.suspected_erratum()
                    .map(|e| format!("; suspected erratum: {}", e.replace('|', "\\|")))
                    .unwrap_or_default(),
                if u.is_unexpected() {
                    String::new()
                } else {
                    " (expected: the symbols file records it unread)".into()
                }
            );
        }
    }
    out
}
