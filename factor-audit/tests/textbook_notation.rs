//! Notation as textbooks write it, end to end: a small LaTeX note
//! (`tests/data/textbook_notes.tex`) with `\mathop{\lim}\limits` of a
//! difference quotient, multi-letter bold (`\mathbf{Rp}` through a macro),
//! `\bm{\mathcal{J}}`, `\buildrel \Delta \over =`, `\cot`, a `\left\{
//! \begin{array} … \right.` cases with trailing punctuation,
//! `J_l^{-1}\left(\phi\right)`, `\Delta` increments, an operator `^\odot`
//! the file defines, a block row `[\mathbf{I}, -\mathbf{P}'^\wedge]`,
//! `\mathrm{Ad}(\mathbf{T})`, `\exp` of an so(3) matrix. Every claim gets its
//! verdict; the wrong one is corrected in the note's terms (primes where
//! printed); the one in notation without meaning is listed with it.

use factor_audit::Verdict;
use factor_audit::from_text::TextAudit;

fn read(path: &str) -> String {
    std::fs::read_to_string(format!("{}/{path}", env!("CARGO_MANIFEST_DIR")))
        .unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn textbook_notation_is_read_and_audited() {
    let text = read("tests/data/textbook_notes.tex");
    let symbols = read("tests/data/textbook_notes.symbols.toml");
    let audit = TextAudit::read("textbook_notes.tex", &text, &symbols).expect("it reads");
    let findings = audit.run(20);
    let verdicts: Vec<(&str, &str)> = findings
        .iter()
        .map(|f| {
            (
                f.finding.label.equation.as_str(),
                f.finding.verdict.keyword(),
            )
        })
        .collect();
    assert_eq!(
        verdicts,
        [
            ("∂(Rp)/∂δφ, the limit", "correct"),
            ("∂(Rp)/∂δφ", "correct"),
            ("∂P'/∂δξ = [I, −P'^∧]", "convention"),
            ("∂P'/∂δξ = P'^⊙", "correct"),
            ("∂P'/∂Δt", "wrong"),
            ("φ = J_l⁻¹(φ)φ", "correct"),
            ("J⁻¹ by cot", "correct"),
            ("J, θ ≠ 0", "correct"),
            ("Ad(T)", "correct"),
            ("Rodrigues", "correct"),
        ]
    );
    assert!(findings.iter().all(|f| !f.is_unexpected()));
    let wrong = &findings[4];
    let d = wrong.diagnosis.as_ref().expect("a diagnosis");
    assert_eq!(d.words, "the whole formula should have the opposite sign");
    assert_eq!(
        d.corrected,
        "\\frac{\\partial \\boldsymbol{P}'}{\\partial \\Delta \\boldsymbol{t}} = \\boldsymbol{I}"
    );
    assert!(matches!(&wrong.finding.verdict, Verdict::Wrong(Some(w)) if *w == d.words));
    // The formula in notation without meaning: listed with its fragment.
    let unread = audit.unread();
    assert_eq!(unread.len(), 1);
    assert_eq!(unread[0].id, "∇f");
    assert!(!unread[0].is_unexpected());
    assert!(
        unread[0].error.to_string().contains("`\\nabla`"),
        "{}",
        unread[0].error
    );
}
