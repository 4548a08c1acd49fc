//! Findings of an audit from a document's text, and their reports: the
//! verdict (the same vocabulary as the transcribed catalogues), the formula
//! quoted as printed with its place, the formula as the parser understood
//! it, and the engine's diagnosis with the corrected LaTeX.

use std::fmt::Write;

use super::errata::Diagnosis;
use crate::report::note;
use crate::verdict::{Finding, Verdict};

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
    /// Edited formulas the erratum search evaluated, when it ran.
    pub searched: Option<usize>,
}

impl TextFinding {
    /// Whether it should fail a gated run: a verdict other than expected.
    pub fn is_unexpected(&self) -> bool {
        self.finding.verdict.keyword() != self.expected
    }

    /// The verdict's explanation (a diagnosis of a malformed formula is
    /// added to why it is malformed).
    pub fn note(&self) -> String {
        let base = note(&self.finding);
        match (&self.finding.verdict, &self.diagnosis) {
            (Verdict::Malformed(_), Some(d)) => format!("{base}; suspected erratum: {}", d.words),
            _ => base,
        }
    }
}

/// Text from the document or the symbols file (a claim id, a file name,
/// a note quoting them) as one printable line: control, separator and
/// format characters escaped (`slamjac_io::printable`).
fn shown(text: &str) -> std::borrow::Cow<'_, str> {
    slamjac_io::printable::escape(text)
}

/// A fixed-width table for the terminal, one row per formula.
pub fn table(findings: &[TextFinding]) -> String {
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
    out
}

/// A Markdown report: a summary table, then each formula with its quote,
/// what was understood, the verdict, the diagnosis and the corrections.
pub fn markdown(findings: &[TextFinding]) -> String {
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
        if let Some(latex) = &f.corrected_latex {
            let _ = writeln!(
                out,
                "\nThe correct expression, expanded:\n\n$$\n{latex}\n$$"
            );
        }
    }
    out
}
