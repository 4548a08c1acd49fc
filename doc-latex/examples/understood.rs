//! What `doc-latex` understood of a document: every line of every display
//! formula, as canonical LaTeX (or the error that stopped it), with its
//! label, and for a line continuing a chain the chain's left side in
//! brackets.
//!
//! ```sh
//! cargo run -p doc-latex --example understood -- documents/001_85032ab900231dbd.txt
//! ```

use std::io::{ErrorKind, Write};
use std::process::ExitCode;

use doc_latex::{Document, MathKind};

fn main() -> ExitCode {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("error: usage: understood DOCUMENT");
        return ExitCode::from(2);
    };
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {path}: {e}");
            return ExitCode::from(2);
        }
    };
    let doc = match Document::parse(&text) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {path}: {e}");
            return ExitCode::from(1);
        }
    };
    match print(&doc, &mut std::io::stdout().lock()) {
        // A reader closing the pipe early (`| head`) is not an error.
        Err(e) if e.kind() != ErrorKind::BrokenPipe => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
        _ => ExitCode::SUCCESS,
    }
}

fn print(doc: &Document, out: &mut impl Write) -> std::io::Result<()> {
    for f in doc
        .formulas()
        .iter()
        .filter(|f| f.kind == MathKind::Display)
    {
        let label = f
            .label
            .as_deref()
            .map(|l| format!(" ({l})"))
            .unwrap_or_default();
        let claims = match doc.claims(f) {
            Ok(c) => c,
            Err(e) => {
                writeln!(out, "line {}{label}: {e}", f.line)?;
                continue;
            }
        };
        for c in claims {
            let read = match &c.statement {
                Ok(s) => s.to_string(),
                Err(e) => format!("NOT READ: {e}"),
            };
            match (&c.lhs, c.continued) {
                (Some(lhs), true) => writeln!(out, "line {}{label}: [{lhs}] {read}", c.line)?,
                _ => writeln!(out, "line {}{label}: {read}", c.line)?,
            }
        }
    }
    Ok(())
}
