//! The guide `docs/guide/auditing.md` stays true: its worked example (the
//! blocks marked `file=…`) audits as it says, the mistake it seeds is
//! diagnosed with the words and correction it quotes, and every TOML block
//! in it is valid TOML.

use factor_audit::Verdict;
use factor_audit::from_text::TextAudit;

fn guide() -> String {
    std::fs::read_to_string(format!(
        "{}/../docs/guide/auditing.md",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("the guide")
}

/// The fenced code blocks: (info string, content).
fn blocks(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut open: Option<(String, String)> = None;
    for line in text.lines() {
        match (&mut open, line.strip_prefix("```")) {
            (None, Some(info)) => open = Some((info.trim().to_string(), String::new())),
            (Some(_), Some("")) => out.push(open.take().expect("open")),
            (Some((_, body)), _) => {
                body.push_str(line);
                body.push('\n');
            }
            (None, None) => {}
        }
    }
    assert!(open.is_none(), "an unclosed code block");
    out
}

fn file(blocks: &[(String, String)], name: &str) -> String {
    blocks
        .iter()
        .find(|(info, _)| info.split_whitespace().any(|w| w == format!("file={name}")))
        .unwrap_or_else(|| panic!("no block file={name}"))
        .1
        .clone()
}

#[test]
fn every_toml_block_is_toml() {
    for (info, body) in blocks(&guide()) {
        if info.split_whitespace().next() == Some("toml")
            && let Err(e) = body.parse::<toml::Table>()
        {
            panic!("{e}\n{body}");
        }
    }
}

#[test]
fn the_worked_example_audits_as_the_guide_says() {
    let text = guide();
    let blocks = blocks(&text);
    let document = file(&blocks, "lie-actions.tex");
    let symbols = file(&blocks, "lie-actions.symbols.toml");
    let audit = TextAudit::read("lie-actions.tex", &document, &symbols).expect("it reads");
    assert!(audit.unread().is_empty(), "{:?}", audit.unread());
    let findings = audit.run(20);
    assert_eq!(findings.len(), 7);
    // The run's table, as the guide prints it.
    let table = blocks
        .iter()
        .find(|(info, body)| info == "text" && body.contains("7 formulas audited"))
        .expect("the run's output")
        .1
        .clone();
    for f in &findings {
        assert_eq!(
            f.finding.verdict,
            Verdict::Correct,
            "{}",
            f.finding.label.equation
        );
        let row = table
            .lines()
            .find(|l| l.contains(&format!(" {} ", f.finding.label.equation)))
            .unwrap_or_else(|| panic!("no row {}", f.finding.label.equation));
        assert!(row.contains(&format!(" {} correct", f.line)), "{row}");
    }
    // The lost sign of step 7.
    let seeded = document.replacen("=R\\Skew{-p}\n", "=R\\Skew{p}\n", 1);
    assert_ne!(seeded, document);
    let mut audit = TextAudit::read("lie-actions.tex", &seeded, &symbols).expect("it reads");
    audit
        .claims
        .retain(|c| c.label.equation == "∂q/∂ω = R[−p]×");
    let f = &audit.run(20)[0];
    assert!(matches!(f.finding.verdict, Verdict::Wrong(_)));
    let d = f.diagnosis.as_ref().expect("a diagnosis");
    assert!(
        text.contains(&format!("suspected erratum: {}", d.words)),
        "{}",
        d.words
    );
    assert!(text.contains(&d.corrected), "{}", d.corrected);
}
