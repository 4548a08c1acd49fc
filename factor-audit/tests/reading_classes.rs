//! The audit never calls a correct formula wrong: one test per class of
//! misreading found on derivation documents the project had never seen
//! (the precedence of scripts, multi-line equations, function dispatch,
//! partials holding other arguments, first-order claims, VIO notation,
//! addressing, errata found while reading). Each test audits small
//! documents written in the style of the class, with formulas that are
//! right (they must be `correct`, or `ambiguous` where the notation really
//! allows two readings) and the same formulas made wrong (they must stay
//! `wrong`: a reading never excuses an error).

use factor_audit::Verdict;
use factor_audit::from_text::TextAudit;
use factor_audit::from_text::report::TextFinding;

/// Samples per claim: enough to separate readings, few enough to keep the
/// tests fast.
const SAMPLES: usize = 30;

/// `document` (Markdown) audited with `symbols`.
fn audit(document: &str, symbols: &str) -> Vec<TextFinding> {
    TextAudit::load("notes.md", document, symbols)
        .unwrap_or_else(|e| panic!("{e}"))
        .run(SAMPLES)
}

/// The finding of claim `id`.
fn finding<'a>(findings: &'a [TextFinding], id: &str) -> &'a TextFinding {
    findings
        .iter()
        .find(|f| f.finding.label.equation == id)
        .unwrap_or_else(|| panic!("no claim {id}"))
}

/// The verdict keyword of claim `id`.
fn verdict(findings: &[TextFinding], id: &str) -> &'static str {
    finding(findings, id).finding.verdict.keyword()
}

/// Class 1: a postfix operator on a parenthesised group after a factor
/// applies to the group, not to the whole product; and "as understood"
/// shows the grouping, never the input echoed.
#[test]
fn scripts_on_a_group_after_a_factor_apply_to_the_group() {
    let document = "\
$$ R Q^{\\top} R^{\\top} = R (R Q)^\\top $$

$$ R Q^{-1} R^{-1} = R (R Q)^{-1} $$

$$ R [Q a]_\\times = R (Q a)^\\wedge $$

$$ \\omega \\times R p = \\omega \\times (R p) $$

$$ Q^{\\top} R^{\\top} R^{\\top} = R (R Q)^\\top $$
";
    let symbols = r#"
document = "notes.md"
[context.c.symbols]
"R" = { sample = "rotation" }
"Q" = { sample = "rotation" }
"a" = { sample = "vector3" }
"\\omega" = { sample = "vector3" }
"p" = { sample = "vector3" }

[[claim]]
id = "transpose"
context = "c"
anchor = "R Q^{\\top} R^{\\top} = R (R Q)^\\top"

[[claim]]
id = "inverse"
context = "c"
anchor = "R (R Q)^{-1}"

[[claim]]
id = "hat"
context = "c"
anchor = "R (Q a)^\\wedge"

[[claim]]
id = "cross"
context = "c"
anchor = "\\omega \\times (R p)"

[[claim]]
id = "the whole transposed, which is not what is printed"
context = "c"
anchor = "Q^{\\top} R^{\\top} R^{\\top}"
expected = "wrong"
"#;
    let findings = audit(document, symbols);
    for id in ["transpose", "inverse", "hat", "cross"] {
        assert_eq!(verdict(&findings, id), "correct", "{id}");
    }
    // The grouping is shown as evaluated.
    assert!(
        finding(&findings, "transpose")
            .understood
            .ends_with("R \\cdot \\left(R \\cdot Q\\right)^{\\top}"),
        "{}",
        finding(&findings, "transpose").understood
    );
    assert!(
        finding(&findings, "cross")
            .understood
            .ends_with("\\omega \\times \\left(R \\cdot p\\right)"),
        "{}",
        finding(&findings, "cross").understood
    );
    // `(R R Q)^T` is not what `R (R Q)^T` means, under any reading.
    let whole = finding(
        &findings,
        "the whole transposed, which is not what is printed",
    );
    assert!(
        matches!(whole.finding.verdict, Verdict::Wrong(_)),
        "{:?}",
        whole.finding.verdict
    );
}

/// Class 1, the safety net: a formula whose notation the symbol table
/// reads one way but its author meant another is `ambiguous`, with the
/// reading that agrees written with explicit brackets; never `wrong`.
#[test]
fn a_formula_right_under_another_reading_is_ambiguous_not_wrong() {
    // `\sin \theta \phi` is read `sin(θ) φ`; the author meant `sin(θ φ)`.
    let document = "\
$$ \\frac{\\partial y}{\\partial \\theta} = \\phi \\cos \\theta \\phi $$
";
    let symbols = r#"
document = "notes.md"
[context.c.symbols]
"\\theta" = { sample = "scalar" }
"\\phi" = { sample = "scalar" }
"y" = "\\sin(\\theta \\phi)"

[[claim]]
id = "d sin(θφ)/dθ"
context = "c"
anchor = "\\phi \\cos \\theta \\phi"
expected = "ambiguous"
"#;
    let findings = audit(document, symbols);
    let f = finding(&findings, "d sin(θφ)/dθ");
    let Verdict::Ambiguous(reading) = &f.finding.verdict else {
        panic!("{:?}", f.finding.verdict)
    };
    assert!(
        reading.contains("\\operatorname{cos}\\left(\\theta \\cdot \\phi\\right)"),
        "{reading}"
    );
    assert!(
        reading.contains("applied to every factor after it"),
        "{reading}"
    );
}

/// Class 3: `\exp` dispatches on the structure of its argument: the
/// matrix exponential of a 4 × 4 matrix that is no twist, the group's
/// exponential of a twist; and a symbols file can redefine `\exp`.
#[test]
fn exp_of_a_general_matrix_is_the_matrix_exponential() {
    let document = "\
$$ \\Phi = \\exp(F \\Delta t) $$

$$ T p = \\exp(\\xi^\\wedge) p $$

$$ \\Psi = \\exp(F \\Delta t) $$

$$ M = \\exp(-v) B $$
";
    let symbols = r#"
document = "notes.md"
[context.c.symbols]
"F" = { sample = "matrix", shape = [4, 4] }
"\\Delta t" = { sample = "scalar", range = [0.1, 0.5] }
"\\Phi" = "\\operatorname{expm}(F \\Delta t)"
"\\xi" = { sample = "vector", size = 6 }
"T" = "\\operatorname{Exp}(\\xi)"
"p" = { sample = "vector3" }

[context.redefined.symbols]
"F" = { sample = "matrix", shape = [4, 4] }
"\\Delta t" = { sample = "scalar", range = [0.1, 0.5] }
"\\Psi" = "\\operatorname{expm}(F \\Delta t)"
"\\exp" = { function = "expm" }

[[claim]]
id = "general matrix exponential"
context = "c"
anchor = "\\Phi = \\exp"

[[claim]]
id = "SE(3) exponential"
context = "c"
anchor = "T p"

[[claim]]
id = "exp redefined"
context = "redefined"
anchor = "\\Psi = \\exp"

[[claim]]
id = "exp of a 3-vector times a rotation"
context = "by type"
anchor = "M = \\exp(-v) B"

[context."by type".symbols]
"v" = { sample = "vector3" }
"B" = { sample = "rotation" }
"M" = "\\operatorname{Exp}(-v) B"
"#;
    let findings = audit(document, symbols);
    for id in [
        "general matrix exponential",
        "SE(3) exponential",
        "exp redefined",
        "exp of a 3-vector times a rotation",
    ] {
        assert_eq!(verdict(&findings, id), "correct", "{id}");
    }
    // The quaternion exponential of a 3-vector does not multiply a matrix:
    // the types chose the rotation, and the report says so.
    let by_type = finding(&findings, "exp of a 3-vector times a rotation");
    assert!(
        by_type.note().contains("`exp` read as `Exp`"),
        "{}",
        by_type.note()
    );
}

/// Class 2: a sum continued over rows (`\\ &+`, a row ending in `+`,
/// `\notag`, in `align`, `split` and `multline`) is audited whole.
#[test]
fn a_sum_continued_over_rows_is_audited_whole() {
    let document = "\
\\begin{align}
\\frac{\\partial y}{\\partial x} &= 2 x \\sin x \\notag \\\\
&\\quad + x^2 \\cos x
\\end{align}

$$
\\begin{split}
\\frac{\\partial z}{\\partial x} &= 3 x^2 \\cos x - \\\\
& x^3 \\sin x
\\end{split}
$$

\\begin{multline}
\\frac{\\partial w}{\\partial x} = \\cos x \\\\
- x \\sin x
\\end{multline}

\\begin{align}
\\frac{\\partial u}{\\partial x} &= 2 x \\sin x \\notag \\\\
&\\quad - x^2 \\cos x
\\end{align}
";
    let symbols = r#"
document = "notes.md"
[context.c.symbols]
"x" = { sample = "scalar", range = [0.2, 2.0] }
"y" = "x^2 \\sin x"
"z" = "x^3 \\cos x"
"w" = "x \\cos x"
"u" = "x^2 \\sin x"

[[claim]]
id = "align, notag, &+"
context = "c"
anchor = "\\frac{\\partial y}{\\partial x}"

[[claim]]
id = "split, a row ending in -"
context = "c"
anchor = "\\frac{\\partial z}{\\partial x}"

[[claim]]
id = "multline"
context = "c"
anchor = "\\frac{\\partial w}{\\partial x}"

[[claim]]
id = "a sign wrong on the second row"
context = "c"
anchor = "\\frac{\\partial u}{\\partial x}"
expected = "wrong"
"#;
    let findings = audit(document, symbols);
    for id in ["align, notag, &+", "split, a row ending in -", "multline"] {
        assert_eq!(verdict(&findings, id), "correct", "{id}");
    }
    let wrong = finding(&findings, "a sign wrong on the second row");
    assert_eq!(wrong.finding.verdict.keyword(), "wrong");
    // The diagnosis is about the continued row, not "columns … are wrong".
    let d = wrong.diagnosis.as_ref().expect("a diagnosis");
    assert!(d.corrected.contains("+ x^{2}"), "{}", d.corrected);
}

/// Class 5: `\approx` and `\simeq` between values claim agreement to first
/// order in the small quantities printed (increments, expanded about
/// zero): the same value there and the same derivative. BCH for a small
/// angle and a linearised propagation in two small quantities are
/// `correct`; a wrong Jacobian, or sides that differ at the expansion
/// point, are `wrong` (never `malformed`).
#[test]
fn first_order_claims_are_audited_as_first_order() {
    let document = "\
$$ \\operatorname{Exp}(\\phi + \\delta\\phi) \\approx \\operatorname{Exp}(\\phi) \\operatorname{Exp}(J_r(\\phi) \\delta\\phi) $$

$$ \\operatorname{Log}(\\operatorname{Exp}(\\phi) \\operatorname{Exp}(\\delta\\phi)) \\approx \\phi + J_r^{-1}(\\phi) \\delta\\phi $$

$$ \\delta x_{k+1} \\simeq F \\delta x_k + G \\delta n $$

$$ \\operatorname{Exp}(\\phi + \\delta\\theta) \\approx \\operatorname{Exp}(\\phi) \\operatorname{Exp}(J_l(\\phi) \\delta\\theta) $$

$$ \\operatorname{Exp}(\\phi + \\delta\\psi) \\approx \\operatorname{Exp}(J_r(\\phi) \\delta\\psi) $$
";
    let symbols = r#"
document = "notes.md"
[context.c.symbols]
"\\phi" = { sample = "rotation_vector" }
"\\delta\\phi" = { sample = "vector3" }
"\\delta\\theta" = { sample = "vector3" }
"\\delta\\psi" = { sample = "vector3" }
"J_r" = { function = "right_jacobian" }
"J_l" = { function = "left_jacobian" }
"x_k" = { sample = "vector", size = 2 }
"\\delta x_k" = { sample = "vector", size = 2 }
"\\delta n" = { sample = "vector", size = 2 }
"f" = { args = ["x", "n"], latex = "\\begin{bmatrix} \\sin(\\operatorname{entry}(x, 1)) + \\operatorname{entry}(x, 2)^2 + \\operatorname{entry}(n, 1) \\\\ \\operatorname{entry}(x, 1) \\operatorname{entry}(x, 2) + \\cos(\\operatorname{entry}(n, 2)) \\end{bmatrix}" }
"\\delta x_{k+1}" = "f(x_k + \\delta x_k, \\delta n) - f(x_k, 0_2)"
"F" = "\\begin{bmatrix} \\cos(\\operatorname{entry}(x_k, 1)) & 2 \\operatorname{entry}(x_k, 2) \\\\ \\operatorname{entry}(x_k, 2) & \\operatorname{entry}(x_k, 1) \\end{bmatrix}"
"G" = "\\begin{bmatrix} 1 & 0 \\\\ 0 & 0 \\end{bmatrix}"

[[claim]]
id = "BCH, right Jacobian"
context = "c"
anchor = "\\operatorname{Exp}(\\phi + \\delta\\phi)"

[[claim]]
id = "Log of a perturbed Exp"
context = "c"
anchor = "\\operatorname{Log}(\\operatorname{Exp}(\\phi)"

[[claim]]
id = "linearised propagation"
context = "c"
anchor = "\\delta x_{k+1}"

[[claim]]
id = "BCH with the left Jacobian"
context = "c"
anchor = "J_l(\\phi) \\delta\\theta"
expected = "wrong"

[[claim]]
id = "BCH without the point"
context = "c"
anchor = "\\operatorname{Exp}(\\phi + \\delta\\psi)"
expected = "wrong"
"#;
    let findings = audit(document, symbols);
    for id in [
        "BCH, right Jacobian",
        "Log of a perturbed Exp",
        "linearised propagation",
    ] {
        assert_eq!(verdict(&findings, id), "correct", "{id}");
    }
    assert_eq!(verdict(&findings, "BCH with the left Jacobian"), "wrong");
    let gap = finding(&findings, "BCH without the point");
    assert!(
        matches!(&gap.finding.verdict, Verdict::Wrong(Some(w)) if w.contains("expansion point")),
        "{:?}",
        gap.finding.verdict
    );
}

/// Class 6: VIO and robotics notation: frame pre-scripts (`{}^{C}_{I}R`,
/// `\text{}^{I_k}_{G}`, a line starting with `^G v`), `\lfloor a \rfloor`
/// for the skew matrix, `\cdots` among arguments, `\mathbf{0}_3` sized by
/// its neighbours, and JPL quaternions stated once in the symbols file.
#[test]
fn vio_notation_is_read() {
    let document = "\
\\f[ {}^{C}\\mathbf{p}_f = {}^{C}_{I}\\mathbf{R} \\, {}^{I}_{G}\\mathbf{R} ({}^{G}\\mathbf{p}_f - {}^{G}\\mathbf{p}_I) + {}^{C}\\mathbf{p}_I \\f]

\\f[ \\frac{\\partial {}^{C}\\mathbf{p}_f}{\\partial \\delta\\boldsymbol{\\theta}} = {}^{C}_{I}\\mathbf{R} \\lfloor \\text{}^{I}_{G}\\mathbf{R} ({}^{G}\\mathbf{p}_f - {}^{G}\\mathbf{p}_I) \\rfloor \\f]

\\f[ \\frac{\\partial \\mathbf{h}({}^{C}\\mathbf{p}_f, \\cdots)}{\\partial {}^{C}\\mathbf{p}_f} = \\begin{bmatrix} \\frac{1}{z} & 0 & -\\frac{x}{z^2} \\\\ 0 & \\frac{1}{z} & -\\frac{y}{z^2} \\end{bmatrix} \\f]

\\f[ \\frac{\\partial {}^{G}\\mathbf{p}_I}{\\partial \\mathbf{x}_I} = \\begin{bmatrix} \\mathbf{I}_3 & \\mathbf{0}_3 \\end{bmatrix} \\f]

\\f[ ^{G}\\mathbf{v} = {}^{I}_{G}\\mathbf{R}^\\top \\, {}^{I}\\mathbf{v} \\f]

\\f[ \\mathbf{C}(\\bar{q}) = (2 q_4^2 - 1) \\mathbf{I}_3 - 2 q_4 \\lfloor \\mathbf{q} \\rfloor + 2 \\mathbf{q} \\mathbf{q}^\\top \\f]
";
    let symbols = |quaternions: &str| {
        format!(
            r#"
document = "notes.md"
{quaternions}
[context.c.symbols]
"{{}}^{{C}}_{{I}}\\mathbf{{R}}" = {{ sample = "rotation" }}
"{{}}^{{I}}_{{G}}\\mathbf{{R}}" = {{ sample = "rotation", update = "\\operatorname{{Exp}}(-\\delta) {{}}^{{I}}_{{G}}\\mathbf{{R}}" }}
"{{}}^{{G}}\\mathbf{{p}}_f" = {{ sample = "vector3" }}
"{{}}^{{C}}\\mathbf{{p}}_I" = {{ sample = "vector3" }}
"\\mathbf{{x}}_I" = {{ sample = "vector", size = 6 }}
"{{}}^{{G}}\\mathbf{{p}}_I" = "\\operatorname{{rows}}(\\mathbf{{x}}_I, 1, 3)"
"{{}}^{{C}}\\mathbf{{p}}_f" = {{ latex = "{{}}^{{C}}_{{I}}\\mathbf{{R}} \\, {{}}^{{I}}_{{G}}\\mathbf{{R}} ({{}}^{{G}}\\mathbf{{p}}_f - {{}}^{{G}}\\mathbf{{p}}_I) + {{}}^{{C}}\\mathbf{{p}}_I", components = ["x", "y", "z"] }}
"\\delta\\boldsymbol{{\\theta}}" = {{ perturbs = "{{}}^{{I}}_{{G}}\\mathbf{{R}}" }}
"\\mathbf{{h}}" = "\\begin{{bmatrix}} x / z \\\\ y / z \\end{{bmatrix}}"
"{{}}^{{I}}\\mathbf{{v}}" = {{ sample = "vector3" }}
"^{{G}}\\mathbf{{v}}" = "({{}}^{{I}}_{{G}}\\mathbf{{R}})^{{-1}} {{}}^{{I}}\\mathbf{{v}}"
"\\bar{{q}}" = {{ sample = "unit_quaternion" }}
"\\mathbf{{q}}" = "\\operatorname{{vector}}(\\bar{{q}})"
"q_4" = "\\operatorname{{scalar}}(\\bar{{q}})"
"\\mathbf{{C}}" = {{ function = "rotation" }}

[[claim]]
id = "the point in the camera"
context = "c"
anchor = "{{}}^{{C}}\\mathbf{{p}}_f = "

[[claim]]
id = "JPL orientation error, bare floor"
context = "c"
anchor = "\\partial \\delta\\boldsymbol{{\\theta}}"

[[claim]]
id = "an ellipsis among the arguments"
context = "c"
anchor = "\\cdots"

[[claim]]
id = "0_3 beside I_3"
context = "c"
anchor = "\\mathbf{{0}}_3"

[[claim]]
id = "a line starting with a pre-script"
context = "c"
anchor = "^{{G}}\\mathbf{{v}} ="

[[claim]]
id = "C(q) of JPL"
context = "c"
anchor = "\\mathbf{{C}}(\\bar{{q}})"
expected = "{expected}"
"#,
            expected = if quaternions.is_empty() {
                "wrong"
            } else {
                "correct"
            }
        )
    };
    let jpl = audit(document, &symbols("quaternions = \"jpl\""));
    for f in &jpl {
        assert_eq!(
            f.finding.verdict.keyword(),
            "correct",
            "{}: {}",
            f.finding.label.equation,
            f.note()
        );
    }
    assert!(
        finding(&jpl, "0_3 beside I_3")
            .note()
            .contains("sized by its block row and column"),
        "{}",
        finding(&jpl, "0_3 beside I_3").note()
    );
    // Without the statement, C(q) is Hamilton's rotation: the JPL formula
    // is its transpose, and the audit says so.
    let hamilton = audit(document, &symbols(""));
    assert_eq!(verdict(&hamilton, "C(q) of JPL"), "wrong");
}

/// Class 4: a chain rule written as a sum of products of partials, each
/// holding the function's other arguments (`∂f/∂x = ∂g/∂x + ∂g/∂r ∂r/∂x`),
/// is read so: a partial printed beside another of the same map holds the
/// other variables; a link stated in words or a claim says what it holds
/// with `holding`. The same formula with a sign wrong stays `wrong`.
#[test]
fn partials_hold_the_other_arguments() {
    let document = "\
$$ \\frac{\\partial f}{\\partial x} = \\frac{\\partial g}{\\partial x} + \\frac{\\partial g}{\\partial r} \\frac{\\partial r}{\\partial x} $$

$$ \\frac{\\partial v}{\\partial x} = \\frac{\\partial g}{\\partial x} - \\frac{\\partial g}{\\partial r} \\frac{\\partial r}{\\partial x} $$

$$ \\frac{\\partial u}{\\partial x} = \\frac{\\partial h}{\\partial x} + \\frac{\\partial h}{\\partial r} \\frac{\\partial r}{\\partial x} $$

$$ \\frac{\\partial h}{\\partial x} = 2 x r $$
";
    let symbols = r#"
document = "notes.md"
[context.c.symbols]
"x" = { sample = "scalar", range = [0.5, 2.0] }
"y" = { sample = "scalar", range = [0.5, 2.0] }
"r" = "x^2"
"g" = "x r + y"
"f" = "g"
"h" = "x^2 r"
"u" = "h"
"v" = "g"

[[claim]]
id = "a sum of products of partials"
context = "c"
anchor = "\\frac{\\partial f}{\\partial x} ="

[[claim]]
id = "a sign wrong"
context = "c"
anchor = "\\frac{\\partial v}{\\partial x} ="
expected = "wrong"

[[claim]]
id = "∂h/∂x, holding r"
context = "c"
anchor = "\\frac{\\partial h}{\\partial x} = 2 x r"
holding = ["r"]

[[claim]]
id = "through the claim that states ∂h/∂x"
context = "c"
anchor = "\\frac{\\partial u}{\\partial x} ="
"#;
    let findings = audit(document, symbols);
    for id in [
        "a sum of products of partials",
        "∂h/∂x, holding r",
        "through the claim that states ∂h/∂x",
    ] {
        assert_eq!(verdict(&findings, id), "correct", "{id}");
    }
    assert_eq!(verdict(&findings, "a sign wrong"), "wrong");
}

/// Class 7: the same sentence before the same display in two sections is
/// addressed by `section` or `occurrence`; an `after` quote that spans a
/// display is refused (never the display after it); `chain` with `line`
/// is refused; a `\label` on one line of a display names that line.
#[test]
fn claims_are_addressed_and_anchors_never_move() {
    let document = "\
# Points

The Jacobian is:

$$ \\frac{\\partial y}{\\partial x} = 2 x $$

# Lines

The Jacobian is:

$$ \\frac{\\partial y}{\\partial x} = 3 x^2 $$

\\begin{align}
\\frac{\\partial y}{\\partial x} &= 2 x \\\\
\\frac{\\partial z}{\\partial x} &= 3 x^2 \\label{eq:z}
\\end{align}
";
    let symbols = |claims: &str| {
        format!(
            r#"
document = "notes.md"
[context.points.symbols]
"x" = {{ sample = "scalar" }}
"y" = "x^2"
"z" = "x^3"
[context.lines.symbols]
"x" = {{ sample = "scalar" }}
"y" = "x^3"
"z" = "x^3"
{claims}
"#
        )
    };
    let findings = audit(
        document,
        &symbols(
            r##"
[[claim]]
id = "points, by section"
context = "points"
section = "Points"
after = "The Jacobian is:"

[[claim]]
id = "lines, by section"
context = "lines"
section = "# Lines"
after = "The Jacobian is:"

[[claim]]
id = "lines, by occurrence"
context = "lines"
occurrence = 2
after = "The Jacobian is:"

[[claim]]
id = "a \\label names its line"
context = "lines"
label = "eq:z"
"##,
        ),
    );
    for f in &findings {
        assert_eq!(
            f.finding.verdict.keyword(),
            "correct",
            "{}",
            f.finding.label.equation
        );
    }
    assert_eq!(finding(&findings, "a \\label names its line").line, 15);
    let refused = |claim: &str, message: &str| {
        let e = TextAudit::load("notes.md", document, &symbols(claim))
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(e.contains(message), "{e}");
    };
    refused(
        "[[claim]]\nid = \"two places\"\ncontext = \"points\"\nafter = \"The Jacobian is:\"",
        "or say which with `section`",
    );
    refused(
        "[[claim]]\nid = \"spans\"\ncontext = \"points\"\nafter = \"The Jacobian is: $$ \\\\frac\"\nsection = \"Points\"",
        "spans the formula on line 5",
    );
    refused(
        "[[claim]]\nid = \"chain and line\"\ncontext = \"points\"\nanchor = \"2 x $$\"\nchain = true\nline = 1",
        "`chain` follows the chain",
    );
}

/// Class 8: what reading finds wrong with a printed formula (an empty
/// matrix entry) is a suspected erratum of the claim left unread; one
/// symbol of the file that cannot be read fails only the claims that use
/// it.
#[test]
fn errata_found_while_reading_are_diagnosed_and_bad_symbols_stay_local() {
    let document = "\
$$ \\frac{\\partial y}{\\partial x} = \\begin{bmatrix} 2 x & \\\\ 0 & 1 \\end{bmatrix} $$

$$ \\frac{\\partial u}{\\partial x} = 2 x $$

$$ \\frac{\\partial v}{\\partial x} = w $$
";
    let symbols = r#"
document = "notes.md"
[context.c.symbols]
"x" = { sample = "scalar" }
"y" = "\\begin{bmatrix} x^2 \\\\ 0 \\end{bmatrix}"
"u" = "x^2"
"v" = "x^3"
"w" = "\\frac{1}{"

[[claim]]
id = "an empty entry"
context = "c"
anchor = "\\partial y"

[[claim]]
id = "untouched by the bad symbol"
context = "c"
anchor = "\\partial u"

[[claim]]
id = "uses the bad symbol"
context = "c"
anchor = "\\partial v"
"#;
    let audit = TextAudit::read("notes.md", document, symbols).expect("the file loads");
    let findings = audit.run(SAMPLES);
    assert_eq!(verdict(&findings, "untouched by the bad symbol"), "correct");
    let unread = audit.unread();
    let empty = unread.iter().find(|u| u.id == "an empty entry").unwrap();
    let erratum = empty.suspected_erratum().expect("a suspected erratum");
    assert!(erratum.contains("is empty"), "{erratum}");
    let bad = unread
        .iter()
        .find(|u| u.id == "uses the bad symbol")
        .unwrap();
    assert!(
        bad.error.to_string().contains("cannot be read"),
        "{}",
        bad.error
    );
}

/// Class 6 continued: a function whose subscript is an argument (a
/// retraction `\Phi_{R_0}(θ)`, composed `\Phi_{\Phi_{R_0}(θ)}(δ)`), the vee
/// written as an accent over nothing (`\{…\}\check{}`), and a derivative by
/// an expression (`∂(T^{-1} p)/∂(T^{-1})`).
#[test]
fn subscripted_functions_empty_accents_and_derivatives_by_expressions() {
    let document = "\
$$ \\Phi_{R_{0}}\\left(\\theta\\right) \\exp\\left([\\delta]_\\times\\right) = \\Phi_{\\Phi_{R_{0}}\\left(\\theta\\right)}\\left(\\delta\\right) $$

$$ \\omega = \\left\\{ R^{T} \\dot{R} \\right\\} \\check{} $$

$$ \\frac{\\partial (M^{-1} p)}{\\partial (M^{-1})} = p^{T} \\otimes I_3 $$
";
    let symbols = r#"
document = "notes.md"
[context.c.symbols]
"R_{0}" = { sample = "rotation" }
"\\theta" = { sample = "vector3" }
"\\delta" = { sample = "vector3" }
"\\Phi" = { args = ["x"], sub = "A", latex = "A \\exp([x]_\\times)" }
"R" = { sample = "rotation" }
"\\omega" = { sample = "vector3" }
"\\dot{R}" = "R [\\omega]_\\times"
"M" = { sample = "matrix", shape = [3, 3], range = [1, 2] }
"p" = { sample = "vector3" }

[[claim]]
id = "retractions composed"
context = "c"
anchor = "\\Phi_{\\Phi_{R_{0}}"

[[claim]]
id = "the vee as an empty accent"
context = "c"
anchor = "\\check{}"

[[claim]]
id = "by an expression, vec column by column"
context = "c"
anchor = "\\partial (M^{-1})"
"#;
    let findings = audit(document, symbols);
    for f in &findings {
        assert_eq!(
            f.finding.verdict.keyword(),
            "correct",
            "{}: {}",
            f.finding.label.equation,
            f.note()
        );
    }
}
