//! Fuzzing the path from a document's text to the engine: mutated
//! documents and symbols files (the specification documents' and the
//! corpus's LaTeX documents with their macros), and random formulas, are
//! read claim by claim, lowered, evaluated, audited and searched for
//! errata without a panic (errors are fine, and must be one line).

use factor_audit::derivation::truth;
use factor_audit::from_text::claims::TextDerivation;
use factor_audit::from_text::{TextAudit, TextError};
use factor_audit::{Derivation, Printed};
use factor_testing::samples::Sampler;
use proptest::prelude::*;

const DOC000: &str = include_str!("../../documents/000_29653f4af9b68bb8.txt");
const SYMBOLS000: &str = include_str!("../../documents/000_29653f4af9b68bb8.symbols.toml");
const DOC001: &str = include_str!("../../documents/001_85032ab900231dbd.txt");
const SYMBOLS001: &str = include_str!("../../documents/001_85032ab900231dbd.symbols.toml");

/// The corpus: each LaTeX document with its symbols file.
const CORPUS: [(&str, &str, &str); 3] = [
    (
        "cheatsheet_kindr1.tex",
        include_str!("../../documents/corpus/kindr/cheatsheet_kindr1.tex"),
        include_str!("../../documents/corpus/kindr/cheatsheet_kindr1.symbols.toml"),
    ),
    (
        "math.tex",
        include_str!("../../documents/corpus/gtsam/math.tex"),
        include_str!("../../documents/corpus/gtsam/math.symbols.toml"),
    ),
    (
        "LieGroups.tex",
        include_str!("../../documents/corpus/gtsam/LieGroups.tex"),
        include_str!("../../documents/corpus/gtsam/LieGroups.symbols.toml"),
    ),
];

/// `text` with `edits` applied: at each (position, kind, character), a
/// character inserted, deleted or replaced (positions on char boundaries).
fn mutate(text: &str, edits: &[(usize, u8, char)]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for (at, kind, c) in edits {
        if chars.is_empty() {
            chars.push(*c);
            continue;
        }
        let i = at % chars.len();
        match kind % 3 {
            0 => chars.insert(i, *c),
            1 => {
                chars.remove(i);
            }
            _ => chars[i] = *c,
        }
    }
    chars.into_iter().collect()
}

/// Characters that matter to LaTeX and TOML, and a few others.
fn interesting() -> impl Strategy<Value = char> {
    prop::sample::select(vec![
        '\\', '{', '}', '(', ')', '[', ']', '^', '_', '&', '|', '$', '=', '+', '-', '0', '1', '2',
        'x', 'q', ' ', '\n', '"', '#', '.', ',', 'ω', '∂', '%', 'T', 'e',
    ])
}

fn edits() -> impl Strategy<Value = Vec<(usize, u8, char)>> {
    prop::collection::vec((any::<usize>(), any::<u8>(), interesting()), 1..6)
}

/// Evaluates every claim's map and printed formula once.
fn evaluate(audit: &TextAudit) {
    for claim in &audit.claims {
        let ctx = &audit.contexts[claim.context];
        let d = TextDerivation::new(claim, ctx, ctx.sample(&mut Sampler::new(7)));
        let _ = truth(&d);
        if let Printed::Evaluated(m) = d.printed() {
            assert!(m.nrows() > 0);
        }
        let _ = d.conventions();
    }
}

/// Reads claim by claim (what `slamjac audit` does; the strict load is
/// the same path stopping at the first error), then evaluates every claim's
/// map and printed formula once.
fn load_and_evaluate(document: &str, symbols: &str) {
    load_named_and_evaluate("fuzz.md", document, symbols);
}

fn load_named_and_evaluate(name: &str, document: &str, symbols: &str) {
    match TextAudit::read(name, document, symbols) {
        Err(e) => {
            let shown = e.to_string();
            assert!(!shown.contains('\n'), "{shown}");
        }
        Ok(audit) => {
            for u in audit.unread() {
                assert!(!u.error.to_string().contains('\n'), "{}", u.error);
            }
            evaluate(&audit);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Mutated documents against their own symbols files.
    #[test]
    fn mutated_documents_never_panic(e in edits(), which in any::<bool>()) {
        let (doc, symbols) = if which { (DOC000, SYMBOLS000) } else { (DOC001, SYMBOLS001) };
        // Mutations land in the audited part (the formulas) most of the time.
        let start = doc.find("$$").unwrap_or(0);
        let (head, tail) = doc.split_at(start);
        load_and_evaluate(&format!("{head}{}", mutate(tail, &e)), symbols);
    }

    /// Mutated symbols files against their documents.
    #[test]
    fn mutated_symbols_files_never_panic(e in edits(), which in any::<bool>()) {
        let (doc, symbols) = if which { (DOC000, SYMBOLS000) } else { (DOC001, SYMBOLS001) };
        load_and_evaluate(doc, &mutate(symbols, &e));
    }

    /// Random formulas over symbols of every kind, audited end to end (the
    /// erratum search included).
    #[test]
    fn random_formulas_are_audited_or_refused(
        parts in prop::collection::vec(prop::sample::select(vec![
            "a", "v", "M", "R", "T", "q", "I", "0", "1", "2", "\\frac{1}{a}", "v^T", "M^{-1}",
            "\\lfloor v \\rfloor_\\times", "|v|", "|v|^{\\frac{3}{2}}", "\\sin a", "\\cos^{-1}(a)",
            "Exp(v)", "Log(R)", "exp(v)", "log(q)", "J_l(v)", "q \\oplus q", "v \\times v",
            "\\begin{bmatrix} a & 0 \\\\ 0 & a \\end{bmatrix}", "[M \\ 0]", "+", "-", " ",
            "(", ")", "\\sqrt{a}", "R^T", "T^{-1}", "(a, a, a)", "a_1", "v^\\wedge",
        ]), 1..8),
    ) {
        let formula: String = parts.concat();
        let document = format!("$$\\frac{{\\partial f}}{{\\partial v}} = {formula} \\quad (1)$$\n");
        let symbols = "[context.c]\n[context.c.symbols]\n\
            \"a\" = { sample = \"rotation_vector\" }\n\
            \"v\" = { sample = \"vector3\" }\n\
            \"R\" = { sample = \"rotation\" }\n\
            \"T\" = { sample = \"pose\" }\n\
            \"q\" = { sample = \"unit_quaternion\" }\n\
            \"M\" = \"v v^T + I\"\n\
            \"a_1\" = \"|a|\"\n\
            \"J_l\" = { function = \"left_jacobian\" }\n\
            \"f\" = \"|v| v\"\n\
            [[claim]]\nid = \"(1)\"\ncontext = \"c\"\nlabel = \"(1)\"\n";
        match TextAudit::load("fuzz.md", &document, symbols) {
            Err(e) => prop_assert!(!e.to_string().contains('\n')),
            Ok(audit) => {
                for f in audit.run(3) {
                    let keyword = f.finding.verdict.keyword();
                    prop_assert!(["correct", "convention", "wrong", "malformed"].contains(&keyword));
                }
            }
        }
    }
}

proptest! {
    // The corpus documents are larger: fewer cases.
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Mutated corpus documents against their symbols files (a window of
    /// the document, its macro definitions kept first, mutated).
    #[test]
    fn mutated_corpus_documents_never_panic(
        e in edits(),
        which in 0..CORPUS.len(),
        start in any::<prop::sample::Index>(),
    ) {
        let (name, doc, symbols) = CORPUS[which];
        let lines: Vec<&str> = doc.lines().collect();
        let macros: Vec<&str> = lines
            .iter()
            .copied()
            .filter(|l| l.contains("newcommand"))
            .collect();
        let at = start.index(lines.len());
        let window = lines[at..(at + 80).min(lines.len())].join("\n");
        let text = format!("{}\n{}", macros.join("\n"), mutate(&window, &e));
        load_named_and_evaluate(name, &text, symbols);
    }

    /// Mutated corpus symbols files against their documents, their claims
    /// read one by one.
    #[test]
    fn mutated_corpus_symbols_files_never_panic(e in edits(), which in 0..CORPUS.len()) {
        let (name, doc, symbols) = CORPUS[which];
        let symbols = mutate(symbols, &e);
        match TextAudit::read(name, doc, &symbols) {
            Err(err) => prop_assert!(!err.to_string().contains('\n')),
            Ok(audit) => {
                for u in audit.unread() {
                    prop_assert!(!u.error.to_string().contains('\n'));
                }
            }
        }
    }
}

/// Hostile nesting and sizes are errors, not crashes.
#[test]
fn hostile_input_is_bounded() {
    let symbols = "[context.c]\n[context.c.symbols]\n\"x\" = { sample = \"vector3\" }\n\
                   [[claim]]\nid = \"(1)\"\ncontext = \"c\"\nlabel = \"(1)\"\nkind = \"value\"\nof = \"x\"\n";
    // A huge identity is refused by the dimension bound.
    let doc = "$$x = I_{1000000} x \\quad (1)$$\n";
    let f = TextAudit::load("h.md", doc, symbols).unwrap().run(2);
    assert!(
        matches!(&f[0].finding.verdict, factor_audit::Verdict::Malformed(m) if m.contains("dimension")),
        "{:?}",
        f[0].finding.verdict
    );
    // Definitions nested past the bound.
    let mut chain = String::from(
        "[context.c]\n[context.c.symbols]\n\"x\" = { sample = \"vector3\" }\n\"d_0\" = \"x\"\n",
    );
    for k in 1..40 {
        chain.push_str(&format!("\"d_{{{k}}}\" = \"2 d_{{{}}}\"\n", k - 1));
    }
    chain.push_str("[[claim]]\nid = \"(1)\"\ncontext = \"c\"\nlabel = \"(1)\"\nkind = \"value\"\nof = \"d_{39}\"\n");
    let e: TextError = TextAudit::load("h.md", "$$x = x \\quad (1)$$\n", &chain).unwrap_err();
    assert!(e.to_string().contains("nest deeper"), "{e}");
    // Definitions within the bound whose formulas nest deep: evaluation
    // stops at its depth bound (on the audit's own large stack).
    let mut deep = String::from(
        "[context.c]\n[context.c.symbols]\n\"x\" = { sample = \"vector3\" }\n\"d_0\" = \"|x|\"\n",
    );
    for k in 1..=15 {
        deep.push_str(&format!(
            "\"d_{{{k}}}\" = \"{}d_{{{}}}\"\n",
            "-".repeat(40),
            k - 1
        ));
    }
    deep.push_str(
        "[[claim]]\nid = \"(1)\"\ncontext = \"c\"\nlabel = \"(1)\"\nkind = \"value\"\nof = \"x\"\n",
    );
    let f = TextAudit::load("h.md", "$$x = |d_{15}| x \\quad (1)$$\n", &deep)
        .unwrap()
        .run(2);
    assert!(
        matches!(&f[0].finding.verdict, factor_audit::Verdict::Malformed(m) if m.contains("deeper than 400")),
        "{:?}",
        f[0].finding.verdict
    );
    // An oversized document.
    let big = "x".repeat(factor_audit::from_text::MAX_DOCUMENT_BYTES + 1);
    assert!(matches!(
        TextAudit::load("h.md", &big, symbols),
        Err(TextError::TooLarge { .. })
    ));
}
