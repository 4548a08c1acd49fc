//! Auditing straight from a document's text: the two specification
//! documents with their symbols files give every one of their 37 verdicts
//! (those the transcribed catalogues gave before they were retired); the
//! engine diagnoses errata with no recorded text; a user's notes with a
//! deliberate mistake are audited and the mistake diagnosed; bad input gets
//! errors naming what is wrong.

use factor_audit::Verdict;
use factor_audit::from_text::report::TextFinding;
use factor_audit::from_text::{TextAudit, TextError};

const DOCUMENTS: [&str; 2] = ["000_29653f4af9b68bb8", "001_85032ab900231dbd"];

fn read(path: &str) -> String {
    std::fs::read_to_string(format!("{}/{path}", env!("CARGO_MANIFEST_DIR")))
        .unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// A document and its symbols file (or a variant of it), audited.
fn audit_text(name: &str, symbols: &str, samples: usize) -> Vec<TextFinding> {
    let text = read(&format!("../documents/{name}.txt"));
    TextAudit::load(&format!("{name}.txt"), &text, symbols)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .run(samples)
}

fn shipped_symbols(name: &str) -> String {
    read(&format!("../documents/{name}.symbols.toml"))
}

fn find<'a>(findings: &'a [TextFinding], equation: &str) -> &'a TextFinding {
    findings
        .iter()
        .find(|f| f.finding.label.equation == equation)
        .unwrap_or_else(|| panic!("no {equation}"))
}

/// Every formula of the specification documents is audited from the text,
/// with the verdict the retired transcribed catalogues gave it; and every
/// verdict is the one the symbols files expect.
#[test]
fn the_37_formulas_keep_their_verdicts() {
    let mut from_text = Vec::new();
    for name in DOCUMENTS {
        from_text.extend(audit_text(name, &shipped_symbols(name), 100));
    }
    let verdicts: Vec<(&str, &str)> = from_text
        .iter()
        .map(|f| {
            (
                f.finding.label.equation.as_str(),
                f.finding.verdict.keyword(),
            )
        })
        .collect();
    let wrong = [
        "§I exp",
        "§IV-A ∂u/∂φ",
        "§IV-A ∂φ/∂y",
        "§IV-A ∂y/∂ξ",
        "(13)",
    ];
    let convention = ["(4)", "§IV-A ∂E/∂u"];
    let malformed = ["(5) ∂ρ/∂ξ", "(10)"];
    assert_eq!(verdicts.len(), 37);
    for (equation, keyword) in &verdicts {
        let expected = if wrong.contains(equation) {
            "wrong"
        } else if convention.contains(equation) {
            "convention"
        } else if malformed.contains(equation) {
            "malformed"
        } else {
            "correct"
        };
        assert_eq!(*keyword, expected, "{equation}");
    }
    let unexpected: Vec<_> = from_text.iter().filter(|f| f.is_unexpected()).collect();
    assert!(unexpected.is_empty(), "{unexpected:#?}");
    // The chain rules are localised from the text too.
    let all: Vec<_> = from_text.iter().map(|f| f.finding.clone()).collect();
    let localised = |e: &str| {
        all.iter()
            .find(|f| f.label.equation == e)
            .and_then(|f| f.localisation.clone())
    };
    assert_eq!(
        localised("(5) ∂ρ/∂ξ").as_deref(),
        Some("wrong link(s): (4) (convention); right: (2)")
    );
    assert_eq!(
        localised("(13)").as_deref(),
        Some(
            "wrong link(s): §IV-A ∂E/∂u (convention), §IV-A ∂u/∂φ (wrong), \
             §IV-A ∂φ/∂y (wrong), §IV-A ∂y/∂ξ (wrong); right: none"
        )
    );
}

/// The symbols file with every recorded `erratum` note removed.
fn without_recorded_errata(symbols: &str) -> String {
    let mut file: toml::Table = toml::from_str(symbols).expect("TOML");
    let mut removed = 0;
    if let Some(toml::Value::Array(claims)) = file.get_mut("claim") {
        for claim in claims {
            if let toml::Value::Table(t) = claim {
                removed += usize::from(t.remove("erratum").is_some());
            }
        }
    }
    let text = toml::to_string(&file).expect("TOML");
    assert!(!text.contains("erratum"), "{removed} removed");
    text
}

/// With no recorded erratum text anywhere, the engine still names the
/// errata it can diagnose by itself: the diagnoses do not change when the
/// recorded notes are removed, and they name the exponent errors that the
/// whole-matrix errata of the verdict engine cannot ("no simple erratum
/// fits").
#[test]
fn the_engine_diagnoses_errata_without_recorded_texts() {
    let name = DOCUMENTS[0];
    let shipped = audit_text(name, &shipped_symbols(name), 100);
    let bare = audit_text(name, &without_recorded_errata(&shipped_symbols(name)), 100);
    for (a, b) in shipped.iter().zip(&bare) {
        assert_eq!(a.diagnosis, b.diagnosis, "{}", a.finding.label.equation);
        assert_eq!(a.finding.verdict, b.finding.verdict);
        assert!(b.finding.label.known_erratum.is_none());
    }
    let diagnosed: Vec<(&str, String, bool)> = bare
        .iter()
        .filter_map(|f| {
            f.diagnosis.as_ref().map(|d| {
                (
                    f.finding.label.equation.as_str(),
                    d.words.clone(),
                    d.complete,
                )
            })
        })
        .collect();
    let words = |e: &str| {
        diagnosed
            .iter()
            .find(|(eq, ..)| *eq == e)
            .unwrap_or_else(|| panic!("no diagnosis of {e}: {diagnosed:#?}"))
    };
    assert_eq!(
        words("§IV-A ∂φ/∂y"),
        &(
            "§IV-A ∂φ/∂y",
            "exponent 3/2 of |y| should be 3".to_string(),
            true
        )
    );
    let (_, du, complete) = words("§IV-A ∂u/∂φ");
    assert!(!complete);
    assert_eq!(
        du,
        "exponent 3/2 of |q| should be 3 (then columns 1, 2 and 3 agree; column 4 is still wrong)"
    );
    assert_eq!(
        words("§I exp"),
        &(
            "§I exp",
            "`\\hat{\\omega}` should be `\\omega`".to_string(),
            true
        )
    );
    let (_, five, _) = words("(5) ∂ρ/∂ξ");
    assert!(
        five.starts_with("row 2 of the 4 × 3 matrix (factor 2 of the product) should not be there")
            && five.contains("halves of the tangent swapped"),
        "{five}"
    );
    // Exactly these four; the others are beyond single and paired edits.
    assert_eq!(diagnosed.len(), 4, "{diagnosed:#?}");
    for e in ["(10)", "(13)", "§IV-A ∂y/∂ξ"] {
        assert!(find(&bare, e).diagnosis.is_none(), "{e}");
        assert!(find(&bare, e).searched.is_some_and(|n| n > 0), "{e}");
    }
    // The corrected LaTeX is the printed formula edited, not the truth.
    let dphi = find(&bare, "§IV-A ∂φ/∂y").diagnosis.as_ref().unwrap();
    assert_eq!(
        dphi.corrected,
        "\\frac{\\partial \\phi}{\\partial y} = \\frac{1}{\\left| y \\right|} I_{4 \\times 4} \
         - \\frac{1}{\\left| y \\right|^{3}} y y^{T}"
    );
}

/// A user's notes (Markdown with LaTeX and a symbols file) with one
/// deliberate mistake: the sign of the rotation block of a point-to-plane
/// ICP Jacobian. The audit finds it, diagnoses it and corrects the printed
/// formula; the right equations pass.
#[test]
fn a_users_notes_are_audited_and_their_mistake_diagnosed() {
    let notes = read("tests/data/icp_notes.md");
    let symbols = read("tests/data/icp_notes.symbols.toml");
    let findings = TextAudit::load("icp_notes.md", &notes, &symbols)
        .expect("the notes load")
        .run(50);
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
        [("(1)", "correct"), ("(2)", "wrong"), ("(3)", "correct")]
    );
    let mistake = find(&findings, "(2)");
    assert!(mistake.is_unexpected());
    assert_eq!(mistake.line, 11);
    let d = mistake.diagnosis.as_ref().expect("a diagnosis");
    assert!(d.complete);
    assert_eq!(
        d.words,
        "the sign of `\\lfloor R p + t \\rfloor_{\\times}` should be flipped"
    );
    assert_eq!(
        d.corrected,
        "\\frac{\\partial r}{\\partial \\xi} = n^{T} \\begin{bmatrix} -\\lfloor R p + t \
         \\rfloor_{\\times} & I \\end{bmatrix}"
    );
    assert_eq!(
        mistake.finding.verdict,
        Verdict::Wrong(Some(d.words.clone()))
    );
}

fn load_error(document: &str, symbols: &str) -> String {
    let e: TextError = TextAudit::load("notes.md", document, symbols).unwrap_err();
    let shown = e.to_string();
    assert!(!shown.contains('\n'), "{shown}");
    shown
}

const NOTE: &str = "$$\\frac{\\partial r}{\\partial x} = 2 a x^T \\quad (1)$$\n";

fn symbols_with(extra: &str) -> String {
    format!(
        "[context.c]\n[context.c.symbols]\n\"x\" = {{ sample = \"vector3\" }}\n\"r\" = \"x^T x\"\n{extra}\n\
         [[claim]]\nid = \"(1)\"\ncontext = \"c\"\nlabel = \"(1)\"\n"
    )
}

#[test]
fn errors_name_the_equation_the_symbol_and_the_fragment() {
    // An undefined symbol: the equation, its line and the symbol.
    assert_eq!(
        load_error(NOTE, &symbols_with("")),
        "equation (1), line 1: undefined symbol at `a`"
    );
    // With `a` defined, the notes load and are right.
    let ok = TextAudit::load("notes.md", NOTE, &symbols_with("\"a\" = \"1\"")).unwrap();
    assert_eq!(ok.run(10)[0].finding.verdict, Verdict::Correct);
    // Malformed LaTeX in the document: the label and the fragment.
    let broken = "$$\\frac{\\partial r}{\\partial x} = 2 a x^T} \\quad (1)$$\n";
    let e = load_error(broken, &symbols_with("\"a\" = \"1\""));
    assert!(e.starts_with("equation (1), line 1"), "{e}");
    assert!(e.contains("unbalanced braces"), "{e}");
    // A definition using an undefined symbol names the definition.
    let e = load_error(NOTE, &symbols_with("\"a\" = \"b + 1\""));
    assert_eq!(e, "symbol `a`: undefined symbol at `b`");
    // A definition in terms of itself.
    let e = load_error(NOTE, &symbols_with("\"a\" = \"c\"\n\"c\" = \"2 a\""));
    assert!(e.contains("defined in terms of itself"), "{e}");
    // A claim-level reading is named with its equation.
    let claim_symbols = format!(
        "{}[claim.symbols]\n\"a\" = \"\\\\frac{{1}}\"\n",
        symbols_with("")
    );
    let e = load_error(NOTE, &claim_symbols);
    assert!(
        e.starts_with("equation (1), symbol `a`: cannot read"),
        "{e}"
    );
    // A definition quoted in an error stays on one line (a newline inside it,
    // found by the fuzz test), and a control character is escaped.
    let e = load_error(
        NOTE,
        &symbols_with("\"a\" = \"\"\"\\\\begin{bmatrix} 1 \\\\\n\\u001b d{bmatrix}\"\"\"\n"),
    );
    // (A symbol that cannot be read fails the claims that use it: the
    // error names the equation, then the symbol.)
    assert!(
        e.starts_with("equation (1), line 1: the symbols file's meaning of it cannot be read: symbol `a`: cannot read"),
        "{e}"
    );
    assert!(!e.contains('\n') && !e.contains('\u{1b}'), "{e}");
    assert!(e.contains("\\u001b"), "{e}");
    // A wrong key, an unknown sampler, a missing label, TOML syntax.
    assert!(load_error(NOTE, &symbols_with("\"a\" = { feld = 1 }")).contains("symbol `a`"));
    assert!(
        load_error(NOTE, &symbols_with("\"a\" = { sample = \"dice\" }"))
            .contains("no sampler `dice`")
    );
    let missing = symbols_with("\"a\" = \"1\"").replace("label = \"(1)\"", "label = \"(9)\"");
    assert_eq!(
        load_error(NOTE, &missing),
        "equation (1): no formula is labelled (9)"
    );
    assert!(load_error(NOTE, "[[claim]\n").starts_with("symbols file, line 1:"));
    // Shapes that do not fit are a verdict, not an error: a malformed formula.
    let bad = "$$\\frac{\\partial r}{\\partial x} = \\begin{bmatrix} 1 & 2 \\end{bmatrix} x \\quad (1)$$\n";
    let f = TextAudit::load("notes.md", bad, &symbols_with(""))
        .unwrap()
        .run(5);
    assert_eq!(
        f[0].finding.verdict,
        Verdict::Malformed("a 1 × 2 matrix times a 3 × 1 matrix".into())
    );
}

/// A symbols file that states no claim audits nothing, so it would pass
/// any gate: it is refused; too many claims are counted in claims.
#[test]
fn an_empty_or_oversized_list_of_claims_is_refused() {
    for empty in ["", "document = \"notes.md\"\n", "[context.c]\n"] {
        assert_eq!(
            load_error(NOTE, empty),
            "the symbols file states no claim ([[claim]] tables): nothing to audit"
        );
    }
    let claim = "[[claim]]\nid = \"(1)\"\ncontext = \"c\"\nlabel = \"(1)\"\n";
    let many = format!(
        "[context.c]\n{}",
        claim.repeat(factor_audit::from_text::symbols::MAX_CLAIMS + 1)
    );
    assert_eq!(
        load_error(NOTE, &many),
        "the symbols file states more than 200 claims"
    );
}

/// Claim ids come from the symbols file: the terminal table and the
/// Markdown report show their control and invisible characters escaped.
#[test]
fn claim_ids_are_shown_escaped_in_the_reports() {
    let symbols = symbols_with("\"a\" = \"1\"").replace(
        "id = \"(1)\"",
        "id = \"(1)\\u001b[2J\\u0007\\ufeff\\u200b\"",
    );
    let findings = TextAudit::load("notes.md", NOTE, &symbols).unwrap().run(5);
    // The same id on a claim that cannot be read (its symbol undefined):
    // the rows of unread claims show it escaped too.
    let unread = TextAudit::read("notes.md", NOTE, &symbols.replace("\"a\" = \"1\"", ""))
        .unwrap()
        .unread()
        .to_vec();
    assert_eq!(unread.len(), 1);
    let reports = [
        factor_audit::from_text::report::table(&findings, &[]),
        factor_audit::from_text::report::markdown(&findings, &[]),
        factor_audit::from_text::report::table(&[], &unread),
        factor_audit::from_text::report::markdown(&[], &unread),
    ];
    for report in &reports {
        assert!(
            report.contains("(1)\\u001b[2J\\u0007\\ufeff\\u200b"),
            "{report}"
        );
        assert!(
            !report.contains(['\u{1b}', '\u{7}', '\u{feff}', '\u{200b}']),
            "{report}"
        );
    }
}
