//! The corpus (`documents/corpus/`): real derivation documents this
//! project did not write, each with its symbols file. Every claim keeps the
//! verdict its symbols file expects (the independent numpy checks beside
//! the documents agree with each), at least 90% of the claims that state a
//! derivative are read, and the ones not read are the ones the file says
//! cannot be. Errors seeded into each document (a sign, an exponent, a
//! transpose, swapped blocks, a missing term) are each found and diagnosed
//! with the right correction.

use factor_audit::Verdict;
use factor_audit::from_text::TextAudit;
use factor_audit::from_text::symbols::ClaimKind;

/// A corpus document: its folder and its name (`.tex` and `.symbols.toml`).
const CORPUS: [(&str, &str); 6] = [
    ("kindr", "cheatsheet_kindr1"),
    ("gtsam", "math"),
    ("gtsam", "LieGroups"),
    ("openvins", "openvins"),
    ("gtsam", "ImuFactor"),
    ("blanco", "se3_techrep"),
];

/// Samples per claim: enough for the verdicts (the CLI's 100 are the gate).
const SAMPLES: usize = 20;

fn read(path: &str) -> String {
    std::fs::read_to_string(format!(
        "{}/../documents/corpus/{path}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn document(dir: &str, name: &str) -> (String, String) {
    (
        read(&format!("{dir}/{name}.tex")),
        read(&format!("{dir}/{name}.symbols.toml")),
    )
}

/// Whether a read claim states a derivative (a Jacobian, a differential, a
/// first-order agreement).
fn states_a_derivative(kind: ClaimKind) -> bool {
    !matches!(kind, ClaimKind::Value)
}

#[test]
fn every_corpus_claim_keeps_its_verdict() {
    for (dir, name) in CORPUS {
        let (text, symbols) = document(dir, name);
        let audit = TextAudit::read(&format!("{name}.tex"), &text, &symbols)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let findings = audit.run(SAMPLES);
        let unexpected: Vec<String> = findings
            .iter()
            .filter(|f| f.is_unexpected())
            .map(|f| {
                format!(
                    "{}: {} (expected {})",
                    f.finding.label.equation,
                    f.finding.verdict.keyword(),
                    f.expected
                )
            })
            .collect();
        assert!(unexpected.is_empty(), "{name}: {unexpected:#?}");
        let surprises: Vec<String> = audit
            .unread()
            .iter()
            .filter(|u| u.is_unexpected())
            .map(|u| format!("{}: {}", u.id, u.error))
            .collect();
        assert!(surprises.is_empty(), "{name}: {surprises:#?}");
        // The unread claims state derivatives (or nothing is known of
        // them): at least 90% of the derivatives are read.
        let read = audit
            .claims
            .iter()
            .filter(|c| states_a_derivative(c.kind))
            .count();
        let unread = audit.unread().len();
        assert!(
            read * 10 >= (read + unread) * 9,
            "{name}: {read} derivative claims read, {unread} not"
        );
    }
}

/// An error seeded into a corpus document: on `line`, `from` becomes `to`.
struct Seed {
    dir: &'static str,
    name: &'static str,
    kind: &'static str,
    claim: &'static str,
    line: usize,
    from: &'static str,
    to: &'static str,
    /// The correction expected when it is not the document's own formula
    /// (an equivalent form), as the report prints it.
    corrected: Option<&'static str>,
}

const SEEDS: &[Seed] = &[
    // kindr: no block matrices to swap.
    Seed {
        dir: "kindr",
        name: "cheatsheet_kindr1",
        kind: "sign",
        claim: "d(v̂₁v₂)/dv₁",
        line: 295,
        from: "&= -\\hat{\\vv}_2",
        to: "&= \\hat{\\vv}_2",
        corrected: None,
    },
    Seed {
        dir: "kindr",
        name: "cheatsheet_kindr1",
        kind: "exponent",
        claim: "_I ω_IB = (…) φ̇",
        line: 321,
        from: "{1-\\cos{\\norm{\\vvph}}}{\\norm{\\vvph}^2}",
        to: "{1-\\cos{\\norm{\\vvph}}}{\\norm{\\vvph}^3}",
        corrected: None,
    },
    Seed {
        dir: "kindr",
        name: "cheatsheet_kindr1",
        kind: "transpose",
        claim: "Γ(−v) = Γ(v)ᵀ",
        line: 304,
        from: "\\vGa(\\vv)^\\transpose",
        to: "\\vGa(\\vv)",
        // The transpose put back on the whole application, bracketed so it
        // reads so whatever `Γ` is (printed on the parenthesis, it would
        // be the group's when the application is a product).
        corrected: Some(
            "\\boldsymbol{\\Gamma}(-\\boldsymbol{v}) = \\left(\\boldsymbol{\\Gamma}(\\boldsymbol{v})\\right)^{T}",
        ),
    },
    Seed {
        dir: "kindr",
        name: "cheatsheet_kindr1",
        kind: "missing term",
        claim: "φ̇ = (…) _I ω_IB",
        line: 323,
        from: "\\left(1 - \\frac{\\norm{\\vvph}}{2}",
        to: "\\left(- \\frac{\\norm{\\vvph}}{2}",
        corrected: None,
    },
    // GTSAM's math.lyx.
    Seed {
        dir: "gtsam",
        name: "math",
        kind: "sign",
        claim: "∂(Rᵀp)/∂ω",
        line: 130,
        from: "=\\Skew{R^{T}p}",
        to: "=-\\Skew{R^{T}p}",
        corrected: None,
    },
    Seed {
        dir: "gtsam",
        name: "math",
        kind: "exponent",
        claim: "∂h/∂ξ = (1/z')[1 0 −x'/z'; 0 1 −y'/z'][[q]× −I₃]",
        line: 412,
        from: "=\\frac{1}{z'}\\left[",
        to: "=\\frac{1}{z'^{2}}\\left[",
        corrected: None,
    },
    Seed {
        dir: "gtsam",
        name: "math",
        kind: "transpose",
        claim: "∂(T₁⁻¹T₂)/∂ξ₁",
        line: 666,
        from: "R_{2}^{T}\\left[t_{2}-t_{1}\\right]_{\\times}R_{1}",
        to: "R_{2}\\left[t_{2}-t_{1}\\right]_{\\times}R_{1}",
        corrected: None,
    },
    Seed {
        dir: "gtsam",
        name: "math",
        kind: "swapped blocks",
        claim: "∂T⁻¹/∂ξ",
        line: 645,
        from: "R & 0\\\\",
        to: "\\Skew tR & 0\\\\",
        corrected: None,
    },
    Seed {
        dir: "gtsam",
        name: "math",
        kind: "missing term",
        claim: "D₁f(ξ) = T(ξ̂ ξ̂_b − ξ̂_b ξ̂)T⁻¹",
        line: 492,
        from: "\\left(\\hat{\\xi}\\hat{\\xi}_{b}-\\hat{\\xi}_{b}\\hat{\\xi}\\right)",
        to: "\\left(\\hat{\\xi}\\hat{\\xi}_{b}\\right)",
        // The term the line before prints, added (audited alone, the claim
        // has no links; with its document's other claims, the second
        // line's `g(T, 0) ξ̂_b D₂g⁻¹(ξ)` fits too, and is reported first).
        corrected: Some(
            "D_{1} f_{\\left(T, \\xi_{b}\\right)}(\\xi) = T \\left(\\hat{\\xi} \\hat{\\xi}_{b}\\right) \
             T^{-1} - T \\hat{\\xi}_{b} \\hat{\\xi} T^{-1}",
        ),
    },
    // GTSAM's Lie Groups for Beginners.
    Seed {
        dir: "gtsam",
        name: "LieGroups",
        kind: "sign",
        claim: "Sim(3) D₁f(ξ) = [−R[p]× R −t; 0 0 −s⁻¹] (homogeneous)",
        line: 517,
        from: "R & -t\\\\",
        to: "R & t\\\\",
        corrected: None,
    },
    Seed {
        dir: "gtsam",
        name: "LieGroups",
        kind: "exponent",
        claim: "Sim(3) D₁f(ξ) = [−R[p]× R −t; 0 0 −s⁻¹] (homogeneous)",
        line: 518,
        from: "-s^{-1}",
        to: "-s^{-2}",
        corrected: None,
    },
    Seed {
        dir: "gtsam",
        name: "LieGroups",
        kind: "transpose",
        claim: "SE(3) inverse action q̂ = [Rᵀ −Rᵀt; 0 1][p; 1]",
        line: 385,
        from: "& -R^{T}t",
        to: "& -Rt",
        corrected: None,
    },
    Seed {
        dir: "gtsam",
        name: "LieGroups",
        kind: "swapped blocks",
        // (Swapping the column blocks of a Jacobian by ξ = [ω; v] is the
        // [v; ω] convention, which the audit names as such.)
        claim: "Sim(3) D₁f(ξ) = [−R[p]× R −t; 0 0 −s⁻¹] (homogeneous)",
        line: 517,
        from: "& R & -t",
        to: "& -t & R",
        corrected: None,
    },
    Seed {
        dir: "gtsam",
        name: "LieGroups",
        kind: "missing term",
        claim: "SE(3) ω × p + v = −p × ω + v",
        line: 358,
        from: "=-p\\times\\omega+v=",
        to: "=-p\\times\\omega=",
        corrected: None,
    },
];

/// The document with `seed` applied: `from` replaced on its line, where it
/// occurs exactly once.
fn seeded(text: &str, seed: &Seed) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let line = &mut lines[seed.line - 1];
    assert_eq!(
        line.matches(seed.from).count(),
        1,
        "{} {}: `{}` on line {}: {line}",
        seed.name,
        seed.kind,
        seed.from,
        seed.line
    );
    *line = line.replacen(seed.from, seed.to, 1);
    lines.join("\n") + "\n"
}

/// The symbols file with only its claim `id` (the others are not read).
fn only_claim(symbols: &str, id: &str) -> String {
    let mut file: toml::Table = symbols.parse().expect("the symbols file is TOML");
    if let Some(toml::Value::Array(claims)) = file.get_mut("claim") {
        claims.retain(|c| c.get("id").and_then(toml::Value::as_str) == Some(id));
    }
    toml::to_string(&file).expect("TOML again")
}

/// `audit` with only the claim `id` kept.
fn only(mut audit: TextAudit, id: &str) -> TextAudit {
    let unread: Vec<String> = audit
        .unread()
        .iter()
        .map(|u| format!("{}: {}", u.id, u.error))
        .collect();
    audit.claims.retain(|c| c.label.equation == id);
    assert_eq!(audit.claims.len(), 1, "{id} is not read: {unread:#?}");
    audit
}

/// Audits `seed`'s claim in the seeded document and checks the diagnosis.
fn check_seed(seed: &Seed) {
    let (text, symbols) = document(seed.dir, seed.name);
    let symbols = only_claim(&symbols, seed.claim);
    let file = format!("{}.tex", seed.name);
    // (Correct as printed: `every_corpus_claim_keeps_its_verdict`.)
    let original = only(
        TextAudit::read(&file, &text, &symbols).expect("the document reads"),
        seed.claim,
    );
    let printed = original.claims[0].with_rhs(&original.claims[0].printed_ast);
    let changed = seeded(&text, seed);
    let audit = only(
        TextAudit::read(&file, &changed, &symbols).expect("the seeded document reads"),
        seed.claim,
    );
    let finding = &audit.run(SAMPLES)[0];
    assert!(
        matches!(
            finding.finding.verdict,
            Verdict::Wrong(_) | Verdict::Malformed(_)
        ),
        "{} {} ({}): {:?}",
        seed.name,
        seed.kind,
        seed.claim,
        finding.finding.verdict
    );
    let d = finding.diagnosis.as_ref().unwrap_or_else(|| {
        panic!(
            "{} {} ({}): no diagnosis of {}",
            seed.name, seed.kind, seed.claim, finding.understood
        )
    });
    assert!(d.complete, "{} {}: {}", seed.name, seed.kind, d.words);
    assert_eq!(
        d.corrected,
        seed.corrected.unwrap_or(&printed),
        "{} {} ({}): {}\n{}",
        seed.name,
        seed.kind,
        seed.claim,
        d.words,
        d.corrected
    );
}

#[test]
fn seeded_errors_are_diagnosed_with_their_correction() {
    // Every kind in every document that has the structure for it.
    for (name, count) in [("cheatsheet_kindr1", 4), ("math", 5), ("LieGroups", 5)] {
        assert_eq!(SEEDS.iter().filter(|s| s.name == name).count(), count);
    }
    std::thread::scope(|scope| {
        for seed in SEEDS {
            scope.spawn(move || check_seed(seed));
        }
    });
}

/// The documents with a planted copy (`NAME.planted.tex`, beside a
/// `NAME.planted.md` whose table names each planted claim by its id).
const PLANTED: [(&str, &str); 3] = [
    ("openvins", "openvins"),
    ("gtsam", "ImuFactor"),
    ("blanco", "se3_techrep"),
];

/// The claim ids of a `.planted.md` table: the first cell of each row,
/// between backquotes.
fn planted_ids(table: &str) -> Vec<String> {
    table
        .lines()
        .filter(|l| l.starts_with("| `"))
        .filter_map(|l| l[3..].split_once('`').map(|(id, _)| id.to_string()))
        .collect()
}

#[test]
fn planted_errors_are_found_wrong() {
    std::thread::scope(|scope| {
        for (dir, name) in PLANTED {
            scope.spawn(move || {
                let text = read(&format!("{dir}/{name}.planted.tex"));
                let symbols = read(&format!("{dir}/{name}.symbols.toml"));
                let ids = planted_ids(&read(&format!("{dir}/{name}.planted.md")));
                assert!(ids.len() >= 4, "{name}: {ids:?}");
                let audit = TextAudit::read(&format!("{name}.planted.tex"), &text, &symbols)
                    .unwrap_or_else(|e| panic!("{name}: {e}"));
                let findings = audit.run(SAMPLES);
                for id in &ids {
                    let finding = findings
                        .iter()
                        .find(|f| &f.finding.label.equation == id)
                        .unwrap_or_else(|| panic!("{name}: the planted claim {id} is not read"));
                    assert!(
                        matches!(
                            finding.finding.verdict,
                            Verdict::Wrong(_) | Verdict::Malformed(_)
                        ),
                        "{name}: planted {id}: {:?}",
                        finding.finding.verdict
                    );
                }
            });
        }
    });
}
