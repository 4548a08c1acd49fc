//! `slamjac audit DOC --symbols FILE`: a Markdown/LaTeX document's formulas
//! audited straight from its text, their symbols given meaning by a
//! symbols file (crate `factor-audit`, module `from_text`).

use std::io::Write;
use std::path::Path;

use factor_audit::from_text::report::{self, TextFinding};
use factor_audit::from_text::{TextAudit, TextError};
use serde_json::{Value, json};

use slamjac_io::Role;

use crate::audit::{check_samples, finding_json, report_roles};
use crate::error::{CliError, InputError};
use crate::outputs;
use crate::source::{read_source, source_name};

/// Audits the claims the symbols file states about the document at
/// `samples` points each, prints the table, writes the optional Markdown
/// and JSON reports, and fails (exit 1) when a verdict is not the one the
/// symbols file expects; an unreadable document or symbols file, or one
/// the other cannot make sense of, is rejected input (exit 2).
pub fn run(
    document: &Path,
    symbols: &Path,
    samples: usize,
    markdown: Option<&Path>,
    json: Option<&Path>,
) -> Result<String, CliError> {
    check_samples(samples)?;
    outputs::check(
        &[
            Role::new("DOCUMENT", document),
            Role::new("--symbols", symbols),
        ],
        &report_roles(markdown, json),
    )?;
    let (doc_path, sym_path) = (
        document.display().to_string(),
        symbols.display().to_string(),
    );
    let text = read_source(&doc_path)?;
    let table = read_source(&sym_path)?;
    let name = document
        .file_name()
        .map_or_else(|| doc_path.clone(), |n| n.to_string_lossy().into_owned());
    let audit = TextAudit::load(&name, &text, &table).map_err(|e| {
        // Errors in the document's formulas are the document's; the
        // others are the symbols file's.
        let at = match &e {
            TextError::Parse(_) | TextError::Formula { .. } => &doc_path,
            TextError::TooLarge { what, .. } if *what == "document" => &doc_path,
            _ => &sym_path,
        };
        InputError::new(source_name(at), e.to_string())
    })?;
    let findings = audit.run(samples);
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
        .map(|f| {
            format!(
                "{} {} ({} where {} is expected)",
                f.finding.label.document,
                f.finding.label.equation,
                f.finding.verdict.keyword(),
                f.expected
            )
        })
        .collect();
    if unexpected.is_empty() {
        Ok(format!(
            "{table}{} formulas audited from the text at {samples} points each",
            findings.len()
        ))
    } else {
        // The table goes out before the one-line error.
        let _ = write!(std::io::stdout().lock(), "{table}");
        Err(CliError::Disagreement(unexpected))
    }
}

/// One object per formula: the catalogues' fields, plus where it is
/// (`line`), the formula as printed and as understood, the verdict the
/// symbols file expects, and the engine's suggested correction.
fn json_report(findings: &[TextFinding]) -> String {
    let entries: Vec<Value> = findings
        .iter()
        .map(|t| {
            let mut entry = finding_json(&t.finding);
            if let Value::Object(map) = &mut entry {
                map.insert("line".into(), json!(t.line));
                map.insert("printed_latex".into(), json!(t.quote));
                map.insert("understood_latex".into(), json!(t.understood));
                map.insert("expected_verdict".into(), json!(t.expected));
                map.insert(
                    "suggested_correction".into(),
                    t.diagnosis.as_ref().map_or(Value::Null, |d| {
                        json!({
                            "words": d.words,
                            "latex": d.corrected,
                            "complete": d.complete,
                            "edits": d.edits,
                        })
                    }),
                );
                map.insert("edited_formulas_evaluated".into(), json!(t.searched));
            }
            entry
        })
        .collect();
    serde_json::to_string_pretty(&entries).expect("serialisable") + "\n"
}
