//! The 14 formulas of document 001 that the audit transcribes, located by
//! label in the document and read: structural facts about each tree,
//! checked against the printed formula.

use crate::common;

use common::*;
use doc_latex::ast::{Accent, Base, DerivativeKind, Expr, Font, Head, PostfixOp, Sign, Symbol};

/// The frame-annotated symbols of the document, e.g. `{}_W \hat{\mathbf{p}}_C`.
fn framed(e: &Expr) -> (String, &Symbol) {
    let s = symbol(e);
    (tex(s.pre_sub.as_ref().expect("a pre-subscript")), s)
}

fn transposed(e: &Expr) -> &Expr {
    match e {
        Expr::Postfix {
            base,
            op: PostfixOp::Transpose,
        } => base,
        other => panic!("not transposed: {}", tex(other)),
    }
}

fn hatted(e: &Expr) -> &Expr {
    match e {
        Expr::Postfix {
            base,
            op: PostfixOp::Hat,
        } => base,
        other => panic!("no ^\\wedge: {}", tex(other)),
    }
}

/// `1 / ‖a − b‖` with `a`, `b` the framed points, as in (4.17) and after.
fn one_over_distance(e: &Expr, numerator: &str) {
    let (num, den) = fraction(e);
    assert_eq!(tex(num), numerator);
    let Expr::Norm { double: true, body } = den else {
        panic!("not a ‖…‖ norm: {}", tex(den))
    };
    let terms = body.terms();
    assert_eq!(terms.len(), 2);
    assert_eq!(terms[1].0, Sign::Minus);
    assert_eq!(
        symbol(terms[0].1).sub.as_deref().map(tex).as_deref(),
        Some("C")
    );
    assert_eq!(
        symbol(terms[1].1).sub.as_deref().map(tex).as_deref(),
        Some("L")
    );
}

#[test]
fn eq3_4_to_3_6_camera_position() {
    let doc = doc001();
    // (3.4) p̂_C = −(t̂_CB + t̂_BW), all in frame W.
    let c = only_claim(&doc, "(3.4)");
    let (frame, p) = framed(c.lhs.as_ref().unwrap());
    assert_eq!(frame, "W");
    assert_eq!(
        (p.font, p.accent, &p.base),
        (Font::Bold, Some(Accent::Hat), &Base::Letter('p'))
    );
    let terms = negated(rhs(&c)).terms();
    assert_eq!(terms.len(), 2);
    assert!(terms.iter().all(|(_, t)| framed(t).0 == "W"));
    // (3.5) and (3.6) continue it: `= …` with the same left side.
    for label in ["(3.5)", "(3.6)"] {
        let c5 = only_claim(&doc, label);
        assert!(c5.continued);
        assert_eq!(c5.lhs, c.lhs);
    }
    // (3.5) = −(Ĉ_WB C_BC {}_C t_CB + Ĉ_WB {}_B t̂_BW)
    let c5 = only_claim(&doc, "(3.5)");
    let terms = negated(rhs(&c5)).terms();
    let first = terms[0].1.factors();
    assert_eq!(first.len(), 3);
    assert_eq!(symbol(first[0]).accent, Some(Accent::Hat));
    assert_eq!(framed(first[2]).0, "C");
    assert_eq!(framed(terms[1].1.factors()[1]).0, "B");
    // (3.6) = −Ĉ_WB (C_BC {}_C t_CB + {}_B t̂_BW): a symbol before a
    // parenthesised group is kept as written, an application.
    let c6 = only_claim(&doc, "(3.6)");
    let Expr::Apply {
        head: Head::Symbol(c_wb),
        args,
        ..
    } = negated(rhs(&c6))
    else {
        panic!()
    };
    assert_eq!(tex(&Expr::Symbol(c_wb.clone())), "\\hat{C}_{W B}");
    assert_eq!(args.len(), 1);
    assert_eq!(args[0].terms().len(), 2);
}

#[test]
fn eq4_5_parallel_rotation_jacobian() {
    let doc = doc001();
    let c = only_claim(&doc, "(4.5)");
    let (of, wrt, partial) = derivative(c.lhs.as_ref().unwrap());
    assert!(partial);
    assert_eq!(tex(of), "\\varepsilon_{1}");
    // ∂/∂ δφ with a bold δ: an increment symbol.
    let dphi = symbol(wrt);
    assert_eq!(
        (dphi.delta, &dphi.base),
        (Some(Font::Bold), &Base::Command("phi".into()))
    );
    // −{}_C ñᵀ C_CB C_BW {}_W x_L^∧
    let f = negated(rhs(&c)).factors();
    assert_eq!(f.len(), 4);
    let n = symbol(transposed(f[0]));
    assert_eq!(
        (n.accent, tex(n.pre_sub.as_ref().unwrap()).as_str()),
        (Some(Accent::Tilde), "C")
    );
    assert_eq!(
        (tex(f[1]).as_str(), tex(f[2]).as_str()),
        ("C_{C B}", "C_{B W}")
    );
    assert_eq!(framed(hatted(f[3])).0, "W");
}

#[test]
fn eq4_6_parallel_translation_jacobian() {
    let doc = doc001();
    let c = only_claim(&doc, "(4.6)");
    assert_eq!(
        tex(derivative(c.lhs.as_ref().unwrap()).1),
        "\\boldsymbol{\\delta} \\boldsymbol{t}"
    );
    let m = rhs(&c);
    assert_eq!(shape(m), (1, 3));
    assert!((0..3).all(|j| tex(entry(m, 0, j)) == "0"));
}

#[test]
fn eq4_14_norm_derivative() {
    let doc = doc001();
    let c = only_claim(&doc, "(4.14)");
    // d‖w‖/dw: a total derivative.
    let Expr::Derivative { kind, of, wrt } = c.lhs.as_ref().unwrap() else {
        panic!()
    };
    assert_eq!(*kind, DerivativeKind::Total);
    assert!(matches!(of.as_ref(), Expr::Norm { double: true, .. }));
    assert_eq!(symbol(wrt).font, Font::Bold);
    let f = rhs(&c).factors();
    assert_eq!(tex(f[0]), "\\frac{1}{\\left\\| \\boldsymbol{w} \\right\\|}");
    assert_eq!(tex(transposed(f[1])), "\\boldsymbol{w}");
}

#[test]
fn eq4_15_inverse_norm_derivative() {
    let doc = doc001();
    let c = only_claim(&doc, "(4.15)");
    let (of, _, partial) = derivative(c.lhs.as_ref().unwrap());
    assert!(!partial);
    assert_eq!(tex(of), "\\frac{1}{\\left\\| \\boldsymbol{w} \\right\\|}");
    // −wᵀ/‖w‖³
    let f = negated(rhs(&c)).factors();
    let (norm, three) = power(fraction(f[0]).1);
    assert!(matches!(norm, Expr::Norm { double: true, .. }));
    assert_eq!(tex(three), "3");
    assert_eq!(tex(f[1]), "\\boldsymbol{w}^{T}");
}

#[test]
fn eq4_16_normalisation_both_forms() {
    let doc = doc001();
    let claims = labelled(&doc, "(4.16)");
    assert_eq!(claims.len(), 2);
    let (of, _, partial) = derivative(claims[0].lhs.as_ref().unwrap());
    assert!(!partial);
    assert_eq!(
        tex(of),
        "\\frac{\\boldsymbol{w}}{\\left\\| \\boldsymbol{w} \\right\\|}"
    );
    // First form: I/‖w‖ − w wᵀ/‖w‖³.
    let terms = rhs(&claims[0]).terms();
    assert_eq!(tex(terms[0].1.factors()[1]), "I");
    let second = terms[1].1.factors();
    assert_eq!(tex(power(fraction(second[0]).1).1), "3");
    assert_eq!(second.len(), 3);
    // Second form, continuing the first: (I − w/‖w‖ (w/‖w‖)ᵀ)/‖w‖.
    assert!(claims[1].continued);
    assert_eq!(claims[1].lhs, claims[0].lhs);
    let f = rhs(&claims[1]).factors();
    let inner = f[1].terms();
    assert_eq!(tex(inner[0].1), "I");
    let outer = inner[1].1.factors();
    assert_eq!(transposed(outer[1]), outer[0]);
}

#[test]
fn eq4_17_bearing_to_anchor_jacobian() {
    let doc = doc001();
    let c = only_claim(&doc, "(4.17)");
    let (of, wrt, _) = derivative(c.lhs.as_ref().unwrap());
    assert_eq!(tex(of), "\\boldsymbol{v}");
    assert_eq!(framed(wrt).0, "w");
    let f = rhs(&c).factors();
    one_over_distance(f[0], "1");
    // (I − v vᵀ)
    assert_eq!(tex(f[1]), "I - \\boldsymbol{v} \\boldsymbol{v}^{T}");
}

#[test]
fn eq4_26_and_4_27_camera_position_jacobians() {
    let doc = doc001();
    let c = only_claim(&doc, "(4.26)");
    let (_, wrt, _) = derivative(c.lhs.as_ref().unwrap());
    assert_eq!(symbol(wrt).delta, Some(Font::Plain));
    // −({}_w t_CB + {}_w t_BW)^∧
    let terms = hatted(negated(rhs(&c))).terms();
    assert_eq!(terms.len(), 2);
    assert!(
        terms
            .iter()
            .all(|(s, t)| *s == Sign::Plus && framed(t).0 == "w")
    );
    let c = only_claim(&doc, "(4.27)");
    assert_eq!(
        tex(derivative(c.lhs.as_ref().unwrap()).1),
        "\\delta \\boldsymbol{t}"
    );
    assert_eq!(tex(negated(rhs(&c))), "I");
}

#[test]
fn eq4_33_distance_rotation_jacobian() {
    let doc = doc001();
    let c = only_claim(&doc, "(4.33)");
    // Continues the chain of (4.28): ∂ε₂/∂δφ.
    assert!(c.continued);
    let (of, wrt, _) = derivative(c.lhs.as_ref().unwrap());
    assert_eq!(
        (tex(of).as_str(), tex(wrt).as_str()),
        ("\\varepsilon_{2}", "\\delta \\phi")
    );
    // −_W ñᵀ ( (I − v vᵀ)(t_CB + t_BW)^∧ / ‖p_C − p_L‖ + v^∧ )
    let f = negated(rhs(&c)).factors();
    assert_eq!(f.len(), 2);
    assert_eq!(framed(transposed(f[0])).0, "W");
    let terms = f[1].terms();
    assert_eq!(terms.len(), 2);
    let inner = terms[0].1.factors();
    one_over_distance(inner[0], "1");
    assert_eq!(tex(inner[1]), "I - \\boldsymbol{v} \\boldsymbol{v}^{T}");
    assert_eq!(hatted(inner[2]).terms().len(), 2);
    assert_eq!(tex(terms[1].1), "\\boldsymbol{v}^{\\wedge}");
}

#[test]
fn eq4_38_distance_translation_jacobian() {
    let doc = doc001();
    let c = only_claim(&doc, "(4.38)");
    let (_, wrt, _) = derivative(c.lhs.as_ref().unwrap());
    assert_eq!(tex(wrt), "\\delta \\boldsymbol{t}");
    // −1/‖p_C − p_L‖ · _W ñᵀ (I − v vᵀ)
    let f = rhs(&c).factors();
    assert_eq!(f.len(), 3);
    one_over_distance(f[0], "-1");
    assert_eq!(framed(transposed(f[1])).0, "W");
    assert_eq!(tex(f[2]), "I - \\boldsymbol{v} \\boldsymbol{v}^{T}");
}
