//! The layouts and notations of LaTeX technical reports (found on a report
//! of SE(3) derivatives, a preintegration note and a VIO filter's pages
//! the project had never seen), one test per class: a label names its own
//! row of an `eqnarray`; blocks of a matrix span the empty cells beside
//! them; evaluation bars bind defined symbols and put a derivative at its
//! point, negated or not; a derivative by a set of symbols holds each of
//! them; `\cdot` is a scalar product and a homogeneous 4 × 4 moves a
//! point; a subscripted name the file defines is not a template's
//! application. Each class has right formulas (`correct`) and the same
//! formulas made wrong (`wrong`: a reading never excuses an error).

use factor_audit::from_text::TextAudit;
use factor_audit::from_text::report::TextFinding;

/// Samples per claim.
const SAMPLES: usize = 30;

/// `document` (LaTeX) audited with `symbols` (which says `syntax = "latex"`).
fn audit(document: &str, symbols: &str) -> Vec<TextFinding> {
    TextAudit::load("report.tex", document, symbols)
        .unwrap_or_else(|e| panic!("{e}"))
        .run(SAMPLES)
}

/// Each claim's verdict keyword is the expected one.
fn expect(findings: &[TextFinding], expected: &[(&str, &str)]) {
    for (id, verdict) in expected {
        let f = findings
            .iter()
            .find(|f| f.finding.label.equation == *id)
            .unwrap_or_else(|| panic!("no claim {id}"));
        assert_eq!(f.finding.verdict.keyword(), *verdict, "{id}: {}", f.note());
    }
}

/// A `\label` inside an `eqnarray` names the row it is printed in, before
/// or after the row's `=`.
#[test]
fn a_label_names_its_own_row() {
    let document = "\
\\begin{eqnarray}
\\label{eq:a}
y &=& 2 x
\\\\
\\label{eq:b}
z &=& 4 x
\\\\
w &=& 5 x \\label{eq:c}
\\end{eqnarray}
";
    let symbols = r#"
document = "report.tex"
syntax = "latex"
[context.c.symbols]
"x" = { sample = "scalar" }
"y" = "2 x"
"z" = "3 x"
"w" = "5 x"
[[claim]]
id = "a"
context = "c"
label = "eq:a"
[[claim]]
id = "b"
context = "c"
label = "eq:b"
[[claim]]
id = "c"
context = "c"
label = "eq:c"
"#;
    let findings = audit(document, symbols);
    expect(
        &findings,
        &[("a", "correct"), ("b", "wrong"), ("c", "correct")],
    );
}

/// A block (`0_{3×1}`, `I_3`) centred among empty cells fills them when no
/// column rule or `\hline` separates them; an empty row between cases is a
/// spacer.
#[test]
fn blocks_span_the_empty_cells_beside_them() {
    let layout = "\\left( \\begin{array}{c|ccc}
 ~ & a & b & c \\\\
 0_{3\\times 1} & d & e & f \\\\
 ~ & g & h & i \\\\
\\hline
 j & ~ & 0_{1\\times 3} &
\\end{array} \\right)";
    let document = format!(
        "\\begin{{equation}}\nM = {layout}\n\\end{{equation}}\n\
\\begin{{equation}}\nM_2 = {layout}\n\\end{{equation}}\n\
\\begin{{equation}}\nP = \\left( \\begin{{array}}{{ccc}} & & \\\\ & I_3 & \\\\ & & \\\\ \\hline a & b & c \\end{{array}} \\right)\n\\end{{equation}}\n\
\\begin{{equation}}\nN = \\left\\{{ \\begin{{array}}{{ll}} a & \\text{{, if $x > 0$}} \\\\ ~\\\\ b & \\text{{, otherwise}} \\end{{array}} \\right.\n\\end{{equation}}\n"
    );
    let symbols = r#"
document = "report.tex"
syntax = "latex"
[context.c.symbols]
"s" = { sample = "vector", size = 10 }
"a" = "\\operatorname{entry}(s, 1)"
"b" = "\\operatorname{entry}(s, 2)"
"c" = "\\operatorname{entry}(s, 3)"
"d" = "\\operatorname{entry}(s, 4)"
"e" = "\\operatorname{entry}(s, 5)"
"f" = "\\operatorname{entry}(s, 6)"
"g" = "\\operatorname{entry}(s, 7)"
"h" = "\\operatorname{entry}(s, 8)"
"i" = "\\operatorname{entry}(s, 9)"
"j" = "\\operatorname{entry}(s, 10)"
"x" = "-1"
"I_3" = "\\begin{bmatrix} 1 & 0 & 0 \\\\ 0 & 1 & 0 \\\\ 0 & 0 & 1 \\end{bmatrix}"
"M" = "\\begin{bmatrix} 0 & a & b & c \\\\ 0 & d & e & f \\\\ 0 & g & h & i \\\\ j & 0 & 0 & 0 \\end{bmatrix}"
"M_2" = "\\begin{bmatrix} 0 & a & b & c \\\\ 0 & d & e & f \\\\ 0 & g & h & i \\\\ 0 & j & 0 & 0 \\end{bmatrix}"
"P" = "\\begin{bmatrix} 1 & 0 & 0 \\\\ 0 & 1 & 0 \\\\ 0 & 0 & 1 \\\\ a & b & c \\end{bmatrix}"
"N" = "b"
[[claim]]
id = "a block spanning empty cells"
context = "c"
anchor = "M ="
[[claim]]
id = "the same layout, another matrix"
context = "c"
anchor = "M_2 ="
[[claim]]
id = "I_3 centred in empty cells"
context = "c"
anchor = "P ="
[[claim]]
id = "a spacer row between cases"
context = "c"
anchor = "N ="
case = 2
"#;
    let findings = audit(&document, symbols);
    expect(
        &findings,
        &[
            ("a block spanning empty cells", "correct"),
            ("the same layout, another matrix", "wrong"),
            ("I_3 centred in empty cells", "correct"),
            ("a spacer row between cases", "correct"),
        ],
    );
}

/// `\left. X \right|_{x = 0, A = D}`: a derivative by `x` is taken at
/// zero (on the left side too: the claim is at that point), `A` keeps the
/// printed value, and a negated derivative under the bar is negated at
/// the point.
#[test]
fn evaluation_bars_bind_and_place_derivatives() {
    let document = "\
\\begin{equation}
\\left. \\frac{\\partial y}{\\partial x} \\right|_{x=0} = 2 x + 3
\\end{equation}
\\begin{equation}
\\left. \\frac{\\partial u}{\\partial x} \\right|_{x=0} = 2 x + 4
\\end{equation}
\\begin{equation}
\\left. \\frac{\\partial (A x)}{\\partial x} \\right|_{A = D} = D
\\end{equation}
\\begin{equation}
\\frac{\\partial (3 - y)}{\\partial x} = \\left. -\\frac{\\partial y}{\\partial x} \\right|_{x=0}
\\end{equation}
\\begin{equation}
\\frac{\\partial (4 - y)}{\\partial x} = \\left. -\\frac{\\partial y}{\\partial x} \\right|_{x=0} + 1
\\end{equation}
";
    let symbols = r#"
document = "report.tex"
syntax = "latex"
[context.c.symbols]
"x" = { sample = "scalar", range = [1.0, 2.0] }
"D" = { sample = "scalar", range = [1.0, 2.0] }
"y" = "x^2 + 3 x"
"u" = "x^2 + 3 x"
[[claim]]
id = "the left side's bar"
context = "c"
anchor = "\\frac{\\partial y}{\\partial x} \\right|_{x=0} = 2"
[[claim]]
id = "the left side's bar, wrong"
context = "c"
anchor = "\\frac{\\partial u}{\\partial x}"
[[claim]]
id = "a bar binding a name"
context = "c"
anchor = "\\right|_{A = D}"
[[claim]]
id = "a negated derivative under a bar"
context = "c"
anchor = "\\partial (3 - y)"
kind = "jacobian"
of = "3 - y"
wrt = "x"
at_zero = true
[[claim]]
id = "a negated derivative under a bar, wrong"
context = "c"
anchor = "\\partial (4 - y)"
kind = "jacobian"
of = "4 - y"
wrt = "x"
at_zero = true
"#;
    let findings = audit(document, symbols);
    expect(
        &findings,
        &[
            ("the left side's bar", "correct"),
            ("the left side's bar, wrong", "wrong"),
            ("a bar binding a name", "correct"),
            ("a negated derivative under a bar", "correct"),
            ("a negated derivative under a bar, wrong", "wrong"),
        ],
    );
}

/// `∂e(ω, θ)/∂{ω_x, ω_y, ω_z, θ}` with `θ = ‖ω‖`: the entries of `ω` move
/// while `θ` is held, and `θ` moves while `ω` is held (the report's
/// factorised quaternion exponential); the chain through them is the
/// derivative, and the partial by `ω` alone (θ held) is not.
#[test]
fn a_derivative_by_a_set_of_symbols_holds_each_of_them() {
    let document = "\
\\begin{equation}
\\frac{\\partial e}{\\partial \\omega}
= \\frac{\\partial e(\\omega,\\theta)}{\\partial \\{ \\omega_x,\\omega_y,\\omega_z, \\theta \\} }
\\frac{\\partial \\{ \\omega_x,\\omega_y,\\omega_z, \\theta \\} }{\\partial \\{ \\omega_x,\\omega_y,\\omega_z \\} }
\\end{equation}
\\begin{equation}
\\frac{\\partial e}{\\partial \\omega} = \\frac{\\partial e(\\omega,\\theta)}{\\partial \\{ \\omega_x,\\omega_y,\\omega_z \\} }
\\end{equation}
";
    let symbols = r#"
document = "report.tex"
syntax = "latex"
[context.c.symbols]
"\\omega" = { sample = "rotation_vector", components = ["\\omega_x", "\\omega_y", "\\omega_z"] }
"\\theta" = "\\|\\omega\\|"
"e" = "\\begin{bmatrix} \\cos\\frac{\\theta}{2} \\\\ \\frac{\\sin\\frac{\\theta}{2}}{\\theta} \\omega \\end{bmatrix}"
[[claim]]
id = "the chain through the set"
context = "c"
anchor = "\\omega_z, \\theta \\} }{"
[[claim]]
id = "the partial holding θ"
context = "c"
anchor = "\\omega_z \\} }"
occurrence = 2
"#;
    let findings = audit(document, symbols);
    expect(
        &findings,
        &[
            ("the chain through the set", "correct"),
            ("the partial holding θ", "wrong"),
        ],
    );
}

/// `p \cdot d` between two columns is their scalar product; a homogeneous
/// 4 × 4 matrix times a 3-vector moves the point; a key of the symbols
/// file may be any expression the document prints.
#[test]
fn dot_products_homogeneous_points_and_expression_keys() {
    let document = "\
\\begin{equation}
s = p \\cdot d + 1
\\end{equation}
\\begin{equation}
s_2 = p \\cdot d + 1
\\end{equation}
\\begin{equation}
q = T p
\\end{equation}
\\begin{equation}
q_2 = T p
\\end{equation}
\\begin{equation}
y = e^{-v} + e^{v}
\\end{equation}
";
    let symbols = r#"
document = "report.tex"
syntax = "latex"
[context.c.symbols]
"p" = { sample = "vector3" }
"d" = { sample = "vector3" }
"s" = "p^\\top d + 1"
"s_2" = "p^\\top d + 2"
"R_s" = { sample = "rotation" }
"t" = { sample = "vector3" }
"T" = "\\begin{bmatrix} \\operatorname{matrix}(R_s) & t \\\\ 0 & 1 \\end{bmatrix}"
"q" = "\\operatorname{matrix}(R_s) p + t"
"q_2" = "\\operatorname{matrix}(R_s) p - t"
"v" = { sample = "vector3" }
"e^{v}" = "\\operatorname{matrix}(\\operatorname{Exp}(v))"
"e^{-v}" = "\\operatorname{matrix}(\\operatorname{Exp}(-v))"
"y" = "\\operatorname{matrix}(\\operatorname{Exp}(v)) + \\operatorname{matrix}(\\operatorname{Exp}(v))^\\top"
[[claim]]
id = "a scalar product"
context = "c"
anchor = "s ="
[[claim]]
id = "a scalar product, wrong"
context = "c"
anchor = "s_2 ="
[[claim]]
id = "a homogeneous matrix moves a point"
context = "c"
anchor = "q ="
[[claim]]
id = "a homogeneous matrix moves a point, wrong"
context = "c"
anchor = "q_2 ="
[[claim]]
id = "expression keys"
context = "c"
anchor = "y ="
"#;
    let findings = audit(document, symbols);
    expect(
        &findings,
        &[
            ("a scalar product", "correct"),
            ("a scalar product, wrong", "wrong"),
            ("a homogeneous matrix moves a point", "correct"),
            ("a homogeneous matrix moves a point, wrong", "wrong"),
            ("expression keys", "correct"),
        ],
    );
}

/// `x_n` a name the file defines (a component) is that value, not a
/// subscripted template `x` applied; the same name made wrong stays wrong.
#[test]
fn a_defined_subscripted_name_is_its_value() {
    let document = "\
\\begin{equation}
y = x
\\end{equation}
\\begin{equation}
y_2 = x
\\end{equation}
";
    let symbols = r#"
document = "report.tex"
syntax = "latex"
[context.c.symbols]
"z_s" = { sample = "vector", size = 2 }
"\\mathbf{z}" = { latex = "z_s", components = ["x_n", "y_n"] }
"x" = "x_n (1 + y_n)"
"y" = "\\operatorname{entry}(z_s, 1) (1 + \\operatorname{entry}(z_s, 2))"
"y_2" = "\\operatorname{entry}(z_s, 2) (1 + \\operatorname{entry}(z_s, 1))"
[[claim]]
id = "x_n a component"
context = "c"
anchor = "y ="
[[claim]]
id = "x_n a component, wrong"
context = "c"
anchor = "y_2 ="
"#;
    let findings = audit(document, symbols);
    expect(
        &findings,
        &[
            ("x_n a component", "correct"),
            ("x_n a component, wrong", "wrong"),
        ],
    );
}
