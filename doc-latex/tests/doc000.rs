//! The 23 formulas of document 000 that the audit transcribes, located by
//! label or anchor in the document and read: structural facts about each
//! tree, checked against the printed formula (mistakes included).

use crate::common;

use common::*;
use doc_latex::Locator;
use doc_latex::ast::{Accent, Base, Expr, Font, Head, MulOp, PostfixOp, Rel, Sign};

fn function_name(e: &Expr) -> (&str, &[Expr]) {
    match e {
        Expr::Apply {
            head: Head::Function(f),
            args,
            ..
        } => (&f.name, args),
        other => panic!("not a function application: {}", tex(other)),
    }
}

fn symbol_applied(e: &Expr) -> (String, &[Expr]) {
    match e {
        Expr::Apply {
            head: Head::Symbol(s),
            args,
            ..
        } => (tex(&Expr::Symbol(s.clone())), args),
        other => panic!("not a symbol applied: {}", tex(other)),
    }
}

/// `J(β)^{-1}`: a symbol applied, with the exponent `-1` printed on its
/// closing parenthesis (the symbol table decides whether it inverts the
/// call or the group); its head and arguments.
fn inverted_application(e: &Expr) -> (String, &[Expr]) {
    let Expr::Apply {
        scripts: Some(chain),
        ..
    } = e
    else {
        panic!("no scripts on a parenthesis: {}", tex(e))
    };
    assert!(
        matches!(chain.as_ref(), Expr::Power { base, exponent }
            if **base == Expr::Placeholder && tex(exponent) == "-1"),
        "not an inverse: {}",
        tex(e)
    );
    symbol_applied(e)
}

#[test]
fn s1_quaternion_exp() {
    let doc = doc000();
    let c = doc.claim("exp(\\omega) = \\begin{pmatrix}").unwrap();
    let (name, args) = function_name(c.lhs.as_ref().unwrap());
    assert_eq!((name, tex(&args[0]).as_str()), ("exp", "\\omega"));
    // `= (½ sinc(θ/2) ω̂ ; cos(θ/2)) ∈ S^3`: a 2 × 1 matrix, then membership.
    let steps = &statement(&c).steps;
    assert_eq!(steps[1].0, Rel::In);
    assert_eq!(tex(&steps[1].1), "S^{3}");
    let m = rhs(&c);
    assert_eq!(shape(m), (2, 1));
    let top = entry(m, 0, 0).factors();
    assert_eq!(tex(top[0]), "\\frac{1}{2}");
    let (sinc, arg) = function_name(top[1]);
    assert_eq!(
        (sinc, tex(&arg[0]).as_str()),
        ("sinc", "\\frac{\\theta}{2}")
    );
    assert_eq!(symbol(top[2]).accent, Some(Accent::Hat));
    assert_eq!(function_name(entry(m, 1, 0)).0, "cos");
    // The side notes θ = |ω| and ω̂ = ω/|ω|.
    let notes: Vec<String> = c
        .notes
        .iter()
        .map(|n| n.as_ref().unwrap().to_string())
        .collect();
    assert_eq!(
        notes,
        [
            "\\theta = \\left| \\omega \\right|",
            "\\hat{\\omega} = \\frac{\\omega}{\\left| \\omega \\right|}"
        ]
    );
}

#[test]
fn s1_quaternion_log() {
    let doc = doc000();
    let c = doc.claim("log(q) =").unwrap();
    assert_eq!(function_name(c.lhs.as_ref().unwrap()).0, "log");
    // 2*cos^{-1}(q_4) / |q| · q, with a bold q (the vector part).
    let f = rhs(&c).factors();
    assert_eq!(f.len(), 2);
    let (num, den) = fraction(f[0]);
    let Expr::Product { first, rest } = num else {
        panic!("numerator {}", tex(num))
    };
    assert_eq!(tex(first), "2");
    assert_eq!(rest[0].0, MulOp::Star);
    let Expr::Apply {
        head: Head::Function(acos),
        args,
        ..
    } = &rest[0].1
    else {
        panic!()
    };
    assert_eq!(acos.name, "cos");
    assert_eq!(tex(acos.power.as_ref().unwrap()), "-1");
    assert_eq!(tex(&args[0]), "q_{4}");
    assert!(matches!(den, Expr::Norm { double: false, body } if symbol(body).font == Font::Bold));
    assert_eq!(symbol(f[1]).font, Font::Bold);
}

#[test]
fn eq1_bch_both_cases() {
    let doc = doc000();
    let c = only_claim(&doc, "(1)");
    let (log, args) = function_name(c.lhs.as_ref().unwrap());
    assert_eq!(log, "Log");
    assert_eq!(args[0].factors().len(), 2);
    assert_eq!(statement(&c).steps[0].0, Rel::Approx);
    let Expr::Cases(cases) = rhs(&c) else {
        panic!("not cases")
    };
    assert_eq!(cases.len(), 2);
    // |ω₁| < ε: J_l(ω₂)^{-1} ω₁ + ω₂; |ω₂| < ε: J_r(ω₁)^{-1} ω₂ + ω₁.
    for (case, (j, small, other)) in cases.iter().zip([("J_{l}", 1, 2), ("J_{r}", 2, 1)]) {
        let terms = case.value.terms();
        let first = terms[0].1.factors();
        let (head, args) = inverted_application(first[0]);
        assert_eq!(head, j);
        assert_eq!(tex(&args[0]), format!("\\omega_{{{other}}}"));
        assert_eq!(tex(first[1]), format!("\\omega_{{{small}}}"));
        assert_eq!(terms[1], (Sign::Plus, &args[0]));
        assert_eq!(
            tex(case.condition.as_ref().unwrap()),
            format!("\\left| \\omega_{{{small}}} \\right| < \\epsilon")
        );
    }
}

#[test]
fn s1_left_and_right_jacobians() {
    let doc = doc000();
    let c = doc
        .claim("J_l(\\omega) = Exp(\\omega)J_r(\\omega)")
        .unwrap();
    let (jl, _) = symbol_applied(c.lhs.as_ref().unwrap());
    assert_eq!(jl, "J_{l}");
    let f = rhs(&c).factors();
    assert_eq!(function_name(f[0]).0, "Exp");
    assert_eq!(symbol_applied(f[1]).0, "J_{r}");
}

#[test]
fn eq2_projection_jacobian() {
    let doc = doc000();
    let c = only_claim(&doc, "(2)");
    assert!(statement(&c).implied);
    let (of, wrt, partial) = derivative(c.lhs.as_ref().unwrap());
    assert!(partial);
    assert_eq!(tex(of), "p_{i}'");
    assert!(matches!(wrt, Expr::Tuple(t) if t.len() == 3));
    let f = rhs(&c).factors();
    assert_eq!((shape(f[0]), shape(f[1])), ((2, 3), (3, 3)));
    assert_eq!(tex(entry(f[0], 0, 2)), "c_{u}");
    assert_eq!(tex(entry(f[1], 0, 0)), "\\frac{1}{P_{z}}");
    // -P_x/P_z²: the 2 stays on the symbol (index or power: the symbol table
    // decides).
    let (num, den) = fraction(negated(entry(f[1], 0, 2)));
    assert_eq!(tex(num), "P_{x}");
    assert_eq!(tex(symbol(den).sup.as_ref().unwrap()), "2");
    assert!((0..3).all(|j| tex(entry(f[1], 2, j)) == "0"));
}

#[test]
fn eq3_point_transform_jacobian() {
    let doc = doc000();
    let c = only_claim(&doc, "(3)");
    let (of, wrt, partial) = derivative(c.lhs.as_ref().unwrap());
    assert!(partial);
    assert_eq!(tex(of), "\\left(P_{x}, P_{y}, P_{z}\\right)");
    assert_eq!(tex(wrt), "\\left(x, y, z\\right)");
    assert_eq!(tex(rhs(&c)), "R_{j}");
}

#[test]
fn eq4_pose_transform_jacobian() {
    let doc = doc000();
    let c = only_claim(&doc, "(4)");
    // Printed ∂(P_x, P_y, P_z)/ξ_j: the denominator lacks its ∂, so this is
    // a fraction over a differential, not a derivative node.
    let (num, den) = fraction(c.lhs.as_ref().unwrap());
    assert!(matches!(num, Expr::Differential(t) if matches!(**t, Expr::Tuple(_))));
    assert_eq!(tex(den), "\\xi_{j}");
    let Expr::Shaped { base, rows, cols } = rhs(&c) else {
        panic!("no shape annotation")
    };
    assert_eq!((*rows, *cols), (3, 6));
    assert_eq!(shape(base), (1, 2));
    assert_eq!(tex(entry(base, 0, 0)), "I");
    let Expr::Skew(inner) = negated(entry(base, 0, 1)) else {
        panic!("not a skew matrix")
    };
    // R_j^w P_i + t_j (the ^w of ^wP_i printed on R_j).
    assert_eq!(tex(inner), "R_{j}^{w} P_{i} + t_{j}");
}

#[test]
fn eq5_point_jacobian_both_lines() {
    let doc = doc000();
    let claims = labelled(&doc, "(5)");
    assert_eq!(claims.len(), 2);
    // The `cases` environment is never closed in the document.
    assert_eq!(claims[0].unclosed_environment.as_deref(), Some("cases"));
    // Line 1: ∂ρ/∂(w P_i) = chain = -K (2×3) · D (3×3) · R_j.
    let (of, wrt, _) = derivative(claims[0].lhs.as_ref().unwrap());
    assert_eq!(
        (tex(of).as_str(), tex(wrt).as_str()),
        ("\\rho_{i j}", "w P_{i}")
    );
    let steps = &statement(&claims[0]).steps;
    let chain = steps[0].1.factors();
    assert_eq!(chain.len(), 3);
    assert!(chain.iter().all(|d| matches!(d, Expr::Derivative { .. })));
    let f = negated(rhs(&claims[0])).factors();
    assert_eq!(
        (shape(f[0]), shape(f[1]), tex(f[2]).as_str()),
        ((2, 3), (3, 3), "R_{j}")
    );
    // Line 2: -K (2×3) · D (printed 4×3, its second row repeated) · [I −⌊…⌋×].
    let (_, wrt, _) = derivative(claims[1].lhs.as_ref().unwrap());
    assert_eq!(tex(wrt), "\\xi_{j}");
    let f = negated(rhs(&claims[1])).factors();
    assert_eq!(
        (shape(f[0]), shape(f[1]), shape(f[2])),
        ((2, 3), (4, 3), (1, 2))
    );
    assert_eq!(matrix(f[1]).rows[1], matrix(f[1]).rows[2]);
    assert_eq!(tex(entry(f[2], 0, 0)), "I");
    assert!(matches!(negated(entry(f[2], 0, 1)), Expr::Skew(_)));
}

#[test]
fn eq6_line_distance_jacobian() {
    let doc = doc000();
    let c = only_claim(&doc, "(6)");
    let (of, wrt, _) = derivative(c.lhs.as_ref().unwrap());
    assert_eq!(
        (tex(of).as_str(), tex(wrt).as_str()),
        ("\\gamma_{i j}", "l_{i}")
    );
    let f = rhs(&c).factors();
    let (one, root) = fraction(f[0]);
    assert_eq!(tex(one), "1");
    // √(l_i^{12} + l_i^{22}): the squares of l¹, l² printed as indices 12, 22.
    assert_eq!(
        tex(root),
        "\\sqrt{l_{i}^{12} + l_{i}^{22}}",
        "as printed in (6), unlike the l_i^{{1^2}} of (11)"
    );
    let Expr::Shaped { base, rows, cols } = f[1] else {
        panic!("no 2 × 3 annotation")
    };
    assert_eq!((shape(base), *rows, *cols), ((2, 3), 2, 3));
    assert_eq!(tex(entry(base, 0, 2)), "1");
    assert_eq!(tex(entry(base, 1, 2)), "1");
    let terms = entry(base, 0, 0).terms();
    assert_eq!(tex(terms[0].1), "p_{i}^{1 '}");
    assert_eq!(terms[1].0, Sign::Minus);
    let (num, _) = fraction(terms[1].1);
    assert_eq!(tex(num), "l_{i}^{1} l_{i}^{T} p_{i}'");
}

#[test]
fn eq7_image_line_jacobian() {
    let doc = doc000();
    let c = only_claim(&doc, "(7)");
    let (of, wrt, _) = derivative(c.lhs.as_ref().unwrap());
    assert_eq!((tex(of).as_str(), tex(wrt).as_str()), ("l_{i}", "L_{c}"));
    // [𝒦 0]_{3×6}: a block row written with a `\ ` between its blocks.
    let Expr::Shaped { base, rows, cols } = rhs(&c) else {
        panic!()
    };
    assert_eq!((shape(base), *rows, *cols), ((1, 2), 3, 6));
    assert_eq!(symbol(entry(base, 0, 0)).font, Font::Calligraphic);
    assert_eq!(tex(entry(base, 0, 1)), "0");
}

#[test]
fn eq8_line_transform_jacobian() {
    let doc = doc000();
    let c = only_claim(&doc, "(8)");
    let Expr::Shaped { base, rows, cols } = rhs(&c) else {
        panic!()
    };
    assert_eq!((shape(base), *rows, *cols), ((2, 2), 6, 6));
    let f = entry(base, 0, 1).factors();
    assert!(matches!(f[0], Expr::Skew(t) if tex(t) == "t_{w}^{c}"));
    assert_eq!(tex(f[1]), "R_{w}^{c}");
    assert_eq!(tex(entry(base, 1, 0)), "0");
    assert_eq!(tex(entry(base, 1, 1)), "R_{w}^{c}");
}

#[test]
fn eq9_orthonormal_line_jacobian() {
    let doc = doc000();
    let c = only_claim(&doc, "(9)");
    let steps = &statement(&c).steps;
    // = lim_{δφ→0} (L_w(φ+δφ) − L_w(φ))/δφ = [[…]]_{6×4}
    let Expr::Limit { under, body } = &steps[0].1 else {
        panic!("no limit")
    };
    assert_eq!(tex(under), "\\delta \\phi \\to 0");
    assert_eq!(tex(fraction(body).1), "\\delta \\phi");
    let Expr::Shaped { base, rows, cols } = rhs(&c) else {
        panic!()
    };
    assert_eq!((shape(base), *rows, *cols), ((2, 2), 6, 4));
    assert!(matches!(negated(entry(base, 0, 0)), Expr::Skew(x) if tex(x) == "\\omega_{1} u_{1}"));
    assert_eq!(tex(entry(base, 0, 1)), "-\\omega_{2} u_{1}");
    assert!(matches!(negated(entry(base, 1, 0)), Expr::Skew(x) if tex(x) == "\\omega_{2} u_{2}"));
    assert_eq!(tex(entry(base, 1, 1)), "\\omega_{1} u_{2}");
}

#[test]
fn eq10_camera_line_pose_jacobian() {
    let doc = doc000();
    // The label is printed as a display of its own, `$$(10)$$`.
    let c = only_claim(&doc, "(10)");
    let (of, wrt, _) = derivative(c.lhs.as_ref().unwrap());
    assert_eq!((tex(of).as_str(), tex(wrt).as_str()), ("L_{c}", "\\xi_{j}"));
    // The final matrix has no `&`: two rows of one entry each; the first a
    // sum of three skew terms, the second −⌊R_j v_w⌋× alone.
    let m = matrix(rhs(&c));
    assert_eq!(m.shape(), Some((2, 1)));
    let terms = m.rows[0][0].terms();
    assert_eq!(terms.len(), 3);
    assert!(
        terms
            .iter()
            .all(|(s, t)| *s == Sign::Minus && matches!(t, Expr::Skew(_)))
    );
    assert_eq!(
        tex(&m.rows[1][0]),
        "-\\lfloor R_{j} v_{w} \\rfloor_{\\times}"
    );
}

#[test]
fn eq11_line_residual_line_jacobian() {
    let doc = doc000();
    let c = only_claim(&doc, "(11)");
    // `= …` continues the display before it, ∂γ/∂φ = (6)(7)(8)(9).
    assert!(c.continued);
    let (of, wrt, _) = derivative(c.lhs.as_ref().unwrap());
    assert_eq!(
        (tex(of).as_str(), tex(wrt).as_str()),
        ("\\gamma_{i j}", "\\phi_{i}")
    );
    let f = rhs(&c).factors();
    assert_eq!(f.len(), 5);
    assert_eq!(
        tex(fraction(f[0]).1),
        "\\sqrt{l_{i}^{1^{2}} + l_{i}^{2^{2}}}"
    );
    assert_eq!(shape(f[1]), (2, 3));
    assert_eq!(shape(f[2]), (1, 2));
    // [R ⌊t⌋×R; 0 R]: the first row's blocks separated by `\ ` only.
    assert_eq!(shape(f[3]), (2, 2));
    assert_eq!(
        tex(entry(f[3], 0, 1)),
        "\\lfloor t_{w}^{c} \\rfloor_{\\times} R_{w}^{c}"
    );
    assert_eq!(shape(f[4]), (2, 2));
    // The chain the previous display states.
    let chain = doc
        .claim("\\frac{\\partial \\gamma_{ij}}{\\partial \\phi_i} =")
        .unwrap();
    assert_eq!(rhs(&chain).factors().len(), 4);
}

#[test]
fn eq12_line_residual_pose_jacobian() {
    let doc = doc000();
    let c = only_claim(&doc, "(12)");
    let (_, wrt, _) = derivative(c.lhs.as_ref().unwrap());
    assert_eq!(tex(wrt), "\\xi_{j}");
    let f = rhs(&c).factors();
    assert_eq!(f.len(), 4);
    assert_eq!(
        (shape(f[1]), shape(f[2]), shape(f[3])),
        ((2, 3), (1, 2), (2, 2))
    );
    // p_i^{1^{\prime}}: the prime on the 1 inside the superscript.
    assert!(matches!(
        symbol(entry(f[1], 0, 0).terms()[0].1).sup.as_deref(),
        Some(Expr::Primed { primes: 1, .. })
    ));
    assert_eq!(entry(f[3], 0, 0).terms().len(), 2);
    assert_eq!(tex(entry(f[3], 1, 1)), "0");
}

#[test]
fn eq13_plane_pose_chain_rule() {
    let doc = doc000();
    let c = only_claim(&doc, "(13)");
    let (of, wrt, _) = derivative(c.lhs.as_ref().unwrap());
    assert_eq!(
        (tex(of).as_str(), tex(wrt).as_str()),
        ("E(\\xi, \\omega)", "\\xi")
    );
    let links: Vec<(String, String)> = rhs(&c)
        .factors()
        .into_iter()
        .map(|d| {
            let (of, wrt, partial) = derivative(d);
            assert!(partial);
            (tex(of), tex(wrt))
        })
        .collect();
    let expected = [("E", "u"), ("u", "\\phi"), ("\\phi", "y"), ("y", "\\xi")];
    let expected: Vec<(String, String)> = expected
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    assert_eq!(links, expected);
}

#[test]
fn s4a_de_du() {
    let doc = doc000();
    // Five displays: the difference quotient, a note defining β, and three
    // `= …` continuations; the note is skipped.
    let chain = doc
        .chain(Locator::Anchor("\\frac{\\partial E}{\\partial u} ="))
        .unwrap();
    assert_eq!(chain.len(), 4);
    let last = chain.last().unwrap();
    let (of, wrt, _) = derivative(last.lhs.as_ref().unwrap());
    assert_eq!((tex(of).as_str(), tex(wrt).as_str()), ("E", "u"));
    assert_eq!(inverted_application(rhs(last)).0, "J_{l}");
    // The BCH step keeps its note `(BCH formula)`.
    assert_eq!(chain[2].notes.len(), 1);
}

#[test]
fn s4a_du_dphi() {
    let doc = doc000();
    let chain = doc
        .chain(Locator::Anchor("\\frac{\\partial u}{\\partial \\phi} &="))
        .unwrap();
    assert_eq!(chain.len(), 2);
    let m = rhs(&chain[1]);
    // ( 2cos⁻¹(φ₄)/|φ_v| I − 2cos⁻¹(φ₄)/|q|^{3/2} φ_v φ_vᵀ | 2cos⁻¹(φ₄)/√(1−φ₄²) φ_v )
    assert_eq!(shape(m), (1, 2));
    let terms = entry(m, 0, 0).terms();
    assert_eq!(terms.len(), 2);
    let first = terms[0].1.factors();
    assert_eq!(tex(fraction(first[0]).1), "\\left| \\phi_{v} \\right|");
    assert_eq!(tex(first[1]), "I_{3 \\times 3}");
    assert_eq!(terms[1].0, Sign::Minus);
    let second = terms[1].1.factors();
    let (norm, exponent) = power(fraction(second[0]).1);
    assert_eq!(tex(norm), "\\left| q \\right|");
    let (three, two) = fraction(exponent);
    assert_eq!((tex(three).as_str(), tex(two).as_str()), ("3", "2"));
    assert_eq!(tex(second[2]), "\\phi_{v}^{T}");
    let right = entry(m, 0, 1).factors();
    assert_eq!(tex(fraction(right[0]).1), "\\sqrt{1 - \\phi_{4}^{2}}");
    // The numerator 2 cos⁻¹(φ₄) in all three places.
    assert_eq!(tex(fraction(right[0]).0), "2 \\cos^{-1}(\\phi_{4})");
}

#[test]
fn s4a_dphi_dy() {
    let doc = doc000();
    let c = doc
        .claim("\\frac{\\partial \\phi}{\\partial y} &=")
        .unwrap();
    let (of, wrt, _) = derivative(c.lhs.as_ref().unwrap());
    assert_eq!((tex(of).as_str(), tex(wrt).as_str()), ("\\phi", "y"));
    // = ∂(y/|y|)/∂y = I/|y| − y yᵀ/|y|^{3/2}
    let steps = &statement(&c).steps;
    assert_eq!(
        tex(derivative(&steps[0].1).0),
        "\\frac{y}{\\left| y \\right|}"
    );
    let terms = rhs(&c).terms();
    assert_eq!(
        tex(terms[0].1),
        "\\frac{1}{\\left| y \\right|} I_{4 \\times 4}"
    );
    let f = terms[1].1.factors();
    let (_, exponent) = power(fraction(f[0]).1);
    assert_eq!(tex(exponent), "\\frac{3}{2}");
    assert_eq!((tex(f[1]).as_str(), tex(f[2]).as_str()), ("y", "y^{T}"));
    // Its side note `(y = (…)) \in R^4)` has an extra `)`.
    assert!(c.notes[0].is_err());
}

#[test]
fn s4a_dy_dxi() {
    let doc = doc000();
    // The chain printed under ∂g/∂ξ (g for y): seven lines, one garbled.
    let chain = doc
        .chain(Locator::Anchor("\\frac{\\partial g}{\\partial \\xi}"))
        .unwrap();
    assert_eq!(chain.len(), 7);
    assert_eq!(chain.iter().filter(|c| c.statement.is_err()).count(), 1);
    let last = chain.last().unwrap();
    let (of, _, _) = derivative(last.lhs.as_ref().unwrap());
    assert_eq!(tex(of), "g");
    // ( (Rᵀ q_v^∧ δφ ; tᵀ q_v^∧ δφ) ) / (δξ = (δφ  δρ)ᵀ): a stack over the
    // tangent; no δρ term is left in the stack.
    let (stack, den) = fraction(rhs(last));
    let (top, bottom) = fraction(stack);
    assert_eq!(
        (tex(top).as_str(), tex(bottom).as_str()),
        (
            "R^{T} q_{v}^{\\hat{\\omega}^{\\wedge}} \\delta \\phi",
            "t^{T} q_{v}^{\\hat{\\omega}^{\\wedge}} \\delta \\phi"
        )
    );
    assert!(!tex(stack).contains("\\rho"));
    let Expr::Relation { first, rest } = den else {
        panic!("the denominator is δξ = …")
    };
    assert_eq!(tex(first), "\\delta \\xi");
    assert_eq!(rest[0].0, Rel::Eq);
    let Expr::Postfix {
        base,
        op: PostfixOp::Transpose,
    } = &rest[0].1
    else {
        panic!("(δφ δρ)ᵀ")
    };
    assert_eq!(shape(base), (1, 2));
    let dphi = symbol(entry(base, 0, 0));
    assert_eq!(
        (dphi.delta, &dphi.base),
        (Some(Font::Plain), &Base::Command("phi".into()))
    );
}

#[test]
fn s4b_de_domega() {
    let doc = doc000();
    let chain = doc
        .chain(Locator::Anchor(
            "\\frac{\\partial E(\\xi,\\omega)}{\\partial \\omega} &=",
        ))
        .unwrap();
    assert_eq!(chain.len(), 7);
    let last = chain.last().unwrap();
    let (of, wrt, _) = derivative(last.lhs.as_ref().unwrap());
    assert_eq!(
        (tex(of).as_str(), tex(wrt).as_str()),
        ("E(\\xi, \\omega)", "\\omega")
    );
    let inverse = negated(rhs(last));
    assert_eq!(inverted_application(inverse).0, "J_{r}");
    // T_w^{c\,T}: the transpose stripped from the frame index c.
    let first = statement(&chain[0]).to_string();
    assert!(first.contains("T_{w}^{c T} q(\\hat{\\omega})"), "{first}");
}
