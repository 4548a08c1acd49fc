//! `slamjac audit DOC --symbols FILE`: a Markdown/LaTeX document's formulas
//! audited straight from its text, their symbols given meaning by a
//! symbols file (crate `factor-audit`, module `from_text`). Every claim of
//! the file is reported, with its verdict or why it could not be read.

use std::io::Write;
use std::path::Path;

use factor_audit::Finding;
use factor_audit::from_text::report::{self, TextFinding};
use factor_audit::from_text::{TextAudit, TextError, Unread};
use serde_json::{Value, json};

use slamjac_io::Role;
use slamjac_problem::InputError;
use slamjac_problem::source::{read_source, source_name};

use crate::error::CliError;
use crate::outputs;

/// The most sampled points per formula `audit` accepts. The samples are
/// streamed (memory does not grow with them), so the bound is on time: a run
/// at it takes minutes in a release build, and agreement at that many
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

/// A document's audit: its findings and the claims that could not be read.
pub struct Audited {
    /// The audited claims.
    pub findings: Vec<TextFinding>,
    /// The claims that could not be read.
    pub unread: Vec<Unread>,
}

/// Reads `text` (named `name`) with its symbols file and audits every
/// claim that can be read at `samples` points.
pub fn audit_document(
    name: &str,
    text: &str,
    symbols: &str,
    samples: usize,
) -> Result<Audited, TextError> {
    let audit = TextAudit::read(name, text, symbols)?;
    Ok(Audited {
        findings: audit.run(samples),
        unread: audit.unread().to_vec(),
    })
}

/// Audits the claims the symbols file states about the document at
/// `samples` points each, prints the table, writes the optional Markdown
/// and JSON reports, and fails (exit 1) when a verdict is not the one the
/// symbols file expects; claims that cannot be read fail it too (exit 2)
/// unless `allow_unread` or the file expects them unread. An unreadable
/// document or symbols file is rejected input (exit 2).
pub fn run(
    document: &Path,
    symbols: &Path,
    samples: usize,
    markdown: Option<&Path>,
    json: Option<&Path>,
    allow_unread: bool,
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
    let audited = audit_document(&name, &text, &table, samples).map_err(|e| {
        // Errors in the document are the document's; the others are the
        // symbols file's.
        let at = match &e {
            TextError::Parse(_) | TextError::Formula { .. } => &doc_path,
            TextError::TooLarge { what, .. } if *what == "document" => &doc_path,
            _ => &sym_path,
        };
        InputError::new(source_name(at), e.to_string())
    })?;
    report_and_gate(&[(name, audited)], samples, markdown, json, allow_unread)
}

/// Prints the table of every document's claims, writes the reports, and
/// gates: unexpected verdicts fail (exit 1), then unread claims the files
/// do not expect unread (exit 2) unless `allow_unread`.
pub fn report_and_gate(
    documents: &[(String, Audited)],
    samples: usize,
    markdown: Option<&Path>,
    json: Option<&Path>,
    allow_unread: bool,
) -> Result<String, CliError> {
    let findings: Vec<TextFinding> = documents
        .iter()
        .flat_map(|(_, a)| a.findings.iter().cloned())
        .collect();
    if let Some(path) = markdown {
        let text: String = documents
            .iter()
            .map(|(_, a)| report::markdown(&a.findings, &a.unread))
            .collect::<Vec<_>>()
            .join("\n");
        outputs::write(path, text)?;
    }
    if let Some(path) = json {
        outputs::write(path, json_report(documents))?;
    }
    let mut table = String::new();
    for (_, a) in documents {
        table.push_str(&report::table(&a.findings, &a.unread));
    }
    let unread_count: usize = documents.iter().map(|(_, a)| a.unread.len()).sum();
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
    let unread: Vec<String> = documents
        .iter()
        .flat_map(|(name, a)| {
            a.unread
                .iter()
                .filter(|u| u.is_unexpected())
                .map(move |u| format!("{name} {}: {}", u.id, u.error))
        })
        .collect();
    let summary = format!(
        "{} formulas audited from the text at {samples} points each{}",
        findings.len(),
        if unread_count > 0 {
            format!("; {unread_count} claim(s) could not be read")
        } else {
            String::new()
        }
    );
    if !unexpected.is_empty() {
        // The table goes out before the one-line error, which names the
        // unread claims too (the exit status is the disagreement's).
        let _ = writeln!(std::io::stdout().lock(), "{table}{summary}");
        return Err(CliError::Disagreement {
            disagreeing: unexpected,
            unread: if allow_unread { Vec::new() } else { unread },
        });
    }
    if !unread.is_empty() && !allow_unread {
        let _ = writeln!(std::io::stdout().lock(), "{table}{summary}");
        return Err(InputError::new(
            "audit",
            format!(
                "{} claim(s) could not be read (--allow-unread audits the rest): {}",
                unread.len(),
                unread.join("; ")
            ),
        )
        .into());
    }
    Ok(format!("{table}{summary}"))
}

/// The report files asked for, as `--markdown` and `--json`.
pub fn report_roles<'a>(markdown: Option<&'a Path>, json: Option<&'a Path>) -> Vec<Role<'a>> {
    let markdown = markdown.map(|p| Role::new("--markdown", p));
    let json = json.map(|p| Role::new("--json", p));
    markdown.into_iter().chain(json).collect()
}

/// One object per claim: the verdict engine's fields, plus where it is
/// (`line`), the formula as printed and as understood, the verdict the
/// symbols file expects, and the engine's suggested correction; a claim
/// that could not be read has the verdict `unread` and its `reading_error`.
fn json_report(documents: &[(String, Audited)]) -> String {
    let mut entries: Vec<Value> = Vec::new();
    for (name, a) in documents {
        for t in &a.findings {
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
            entries.push(entry);
        }
        for u in &a.unread {
            entries.push(json!({
                "document": name,
                "equation": u.id,
                "verdict": "unread",
                "line": u.line,
                "printed_latex": u.quote,
                "expected_verdict": u.expected,
                "reading_error": u.error.to_string(),
                "suspected_erratum": u.suspected_erratum(),
            }));
        }
    }
    serde_json::to_string_pretty(&entries).expect("serialisable") + "\n"
}

/// A formula's JSON object: document, equation, claim, verdict (`correct`,
/// `convention`, `wrong` or `malformed`), max relative error, convention
/// note, known erratum and corrected LaTeX.
pub fn finding_json(f: &Finding) -> Value {
    let note = factor_audit::report::note(f);
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
