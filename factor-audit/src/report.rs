//! Audit reports: a terminal table and Markdown (the command line writes
//! the JSON).

use std::fmt::Write;

use crate::verdict::{Finding, Verdict};

fn error_text(f: &Finding) -> String {
    f.max_relative_error
        .map_or("—".into(), |e| format!("{e:.1e}"))
}

/// The verdict's explanation: the convention, the suspected erratum or why
/// the formula is malformed (empty when correct).
pub fn note(f: &Finding) -> String {
    match &f.verdict {
        Verdict::Correct => String::new(),
        Verdict::Convention(c) => c.clone(),
        Verdict::Wrong(Some(e)) => format!("suspected erratum: {e}"),
        Verdict::Wrong(None) => "no simple erratum fits".into(),
        Verdict::Malformed(m) => m.clone(),
        Verdict::Ambiguous(reading) => format!("correct when read as {reading}"),
    }
}

/// A fixed-width table for the terminal, one row per formula.
pub fn table(findings: &[Finding]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<26} {:<22} {:<11} {:>9}  note",
        "document", "equation", "verdict", "max err"
    );
    for f in findings {
        let known = if f.label.known_erratum.is_some() && f.verdict != Verdict::Correct {
            " (known)"
        } else {
            ""
        };
        let _ = writeln!(
            out,
            "{:<26} {:<22} {:<11} {:>9}  {}{}",
            f.label.document,
            f.label.equation,
            f.verdict.keyword(),
            error_text(f),
            note(f),
            known
        );
    }
    out
}

/// A Markdown report: a summary table, then each disagreement in detail with
/// its corrected LaTeX.
pub fn markdown(findings: &[Finding]) -> String {
    let mut out = String::from(
        "# Derivation audit\n\n| document | equation | claim | verdict | max relative error | note |\n| --- | --- | --- | --- | --- | --- |\n",
    );
    for f in findings {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} |",
            f.label.document,
            f.label.equation,
            f.label.claim,
            f.verdict.keyword(),
            error_text(f),
            note(f).replace('|', "\\|")
        );
    }
    for f in findings.iter().filter(|f| f.verdict != Verdict::Correct) {
        let _ = write!(
            out,
            "\n## {} {}\n\n{}\n\n- convention stated: {}\n- verdict: **{}** {}\n",
            f.label.document,
            f.label.equation,
            f.label.claim,
            f.label.convention,
            f.verdict.keyword(),
            note(f)
        );
        if let Some(known) = &f.label.known_erratum {
            let _ = writeln!(out, "- known erratum: {known}");
        }
        if let Some(localisation) = &f.localisation {
            let _ = writeln!(out, "- chain rule: {localisation}");
        }
        if let Some(latex) = &f.corrected_latex {
            let _ = writeln!(out, "\nCorrect expression:\n\n$$\n{latex}\n$$");
        }
    }
    out
}
