//! `slamjac audit`: the documents' hand-derived formulas against the truth.

use std::io::Write;
use std::path::Path;

use factor_audit::{Finding, audit_documents, report};
use serde_json::{Value, json};

use slamjac_io::Role;

use crate::error::{CliError, InputError};
use crate::outputs;

/// The most sampled points per formula `audit` accepts. The samples are
/// streamed (memory does not grow with them), so the bound is on time: a run
/// at it takes about 20 s in a release build, and agreement at that many
/// points says no more than at the default 100.
pub const MAX_SAMPLES: usize = 100_000;

/// `Ok` when `samples` lies in `1..=MAX_SAMPLES`, else the one-line error
/// (exit 2) of both audits.
pub fn check_samples(samples: usize) -> Result<(), CliError> {
    if (1..=MAX_SAMPLES).contains(&samples) {
        Ok(())
    } else {
        Err(InputError::new(
            "--samples",
            format!("{samples} is out of range: must be between 1 and {MAX_SAMPLES}"),
        )
        .into())
    }
}

/// Audits every transcribed formula at `samples` points, prints the table,
/// writes the optional Markdown and JSON reports, and fails (exit 1) when a
/// formula that is not a known erratum disagrees with the truth. `samples`
/// must lie in `1..=MAX_SAMPLES` (else exit 2).
pub fn run(
    samples: usize,
    markdown: Option<&Path>,
    json: Option<&Path>,
) -> Result<String, CliError> {
    check_samples(samples)?;
    outputs::check(&[], &report_roles(markdown, json))?;
    let findings = audit_documents(samples);
    if let Some(path) = markdown {
        outputs::write(path, report::markdown(&findings))?;
    }
    if let Some(path) = json {
        outputs::write(path, json_report(&findings))?;
    }
    let table = report::table(&findings);
    let unexpected: Vec<String> = findings
        .iter()
        .filter(|f| f.is_unexpected())
        .map(|f| format!("{} {}", f.label.document, f.label.equation))
        .collect();
    if unexpected.is_empty() {
        Ok(format!(
            "{table}{} formulas audited at {samples} points each",
            findings.len()
        ))
    } else {
        // The table goes out before the one-line error.
        let _ = write!(std::io::stdout().lock(), "{table}");
        Err(CliError::Disagreement(unexpected))
    }
}

/// The report files asked for, as `--markdown` and `--json`.
pub fn report_roles<'a>(markdown: Option<&'a Path>, json: Option<&'a Path>) -> Vec<Role<'a>> {
    let markdown = markdown.map(|p| Role::new("--markdown", p));
    let json = json.map(|p| Role::new("--json", p));
    markdown.into_iter().chain(json).collect()
}

/// One object per formula (see [`finding_json`]).
fn json_report(findings: &[Finding]) -> String {
    let entries: Vec<Value> = findings.iter().map(finding_json).collect();
    serde_json::to_string_pretty(&entries).expect("serialisable") + "\n"
}

/// A formula's JSON object: document, equation, claim, verdict (`correct`,
/// `convention`, `wrong` or `malformed`), max relative error, convention
/// note, known erratum and corrected LaTeX.
pub fn finding_json(f: &Finding) -> Value {
    let note = report::note(f);
    json!({
        "document": f.label.document,
        "equation": f.label.equation,
        "claim": f.label.claim,
        "verdict": f.verdict.keyword(),
        "max_relative_error": f.max_relative_error.filter(|e| e.is_finite()),
        "convention_note": (!note.is_empty()).then_some(note),
        "known_erratum": f.label.known_erratum,
        "corrected_latex": f.corrected_latex,
        "chain_localisation": f.localisation,
        "samples": f.samples,
    })
}
