//! `slamjac audit`: the hand-derived formulas of the two specification
//! documents shipped in `documents/`, audited from their text with their
//! symbols files. (The corpus of public derivations, `documents/corpus/`,
//! is audited document by document, `slamjac audit DOC --symbols FILE`: its
//! texts keep their own licences and are not built into the binary.)

use slamjac_problem::InputError;
use std::path::Path;

use crate::audit_text::{audit_document, check_samples, report_and_gate, report_roles};

use crate::error::CliError;
use crate::outputs;

/// A document shipped in `documents/`: its file name, text and symbols file.
pub struct Shipped {
    /// The file name reports use.
    pub name: &'static str,
    /// The document.
    pub text: &'static str,
    /// Its symbols file.
    pub symbols: &'static str,
}

/// Every document `slamjac audit` audits, built into the binary.
pub const SHIPPED: &[Shipped] = &[
    Shipped {
        name: "000_29653f4af9b68bb8.txt",
        text: include_str!("../documents/000_29653f4af9b68bb8.txt"),
        symbols: include_str!("../documents/000_29653f4af9b68bb8.symbols.toml"),
    },
    Shipped {
        name: "001_85032ab900231dbd.txt",
        text: include_str!("../documents/001_85032ab900231dbd.txt"),
        symbols: include_str!("../documents/001_85032ab900231dbd.symbols.toml"),
    },
];

/// Audits every shipped document from its text at `samples` points a
/// formula, prints the table, writes the optional Markdown and JSON
/// reports, and fails (exit 1) when a verdict is not the one its symbols
/// file expects, or (exit 2) when a claim its file does not expect unread
/// cannot be read, unless `allow_unread`.
pub fn run(
    samples: usize,
    markdown: Option<&Path>,
    json: Option<&Path>,
    allow_unread: bool,
) -> Result<String, CliError> {
    check_samples(samples)?;
    outputs::check(&[], &report_roles(markdown, json))?;
    let mut documents = Vec::with_capacity(SHIPPED.len());
    for d in SHIPPED {
        let audited = audit_document(d.name, d.text, d.symbols, samples)
            .map_err(|e| InputError::new(d.name, e.to_string()))?;
        documents.push((d.name.to_string(), audited));
    }
    report_and_gate(&documents, samples, markdown, json, allow_unread)
}
