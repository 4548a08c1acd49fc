//! The audit's verdicts on the transcribed formulas of document 000 §I–§II,
//! and on derivations built to be right, wrong or right under another
//! convention, so the engine itself is shown to discriminate.

use factor_core::Scalar;
use factor_core::audit::verdict::audit;
use factor_core::audit::{Derivation, Label, Printed, Verdict, audit_documents};
use factor_core::lie::So3;
use factor_core::lie::so3::hat;
use factor_core::manifold::{Manifold, Perturbation};
use factor_core::testing::samples::Sampler;
use nalgebra::{DMatrix, Vector3};

fn verdict_of(equation: &str) -> Verdict {
    audit_documents(100)
        .into_iter()
        .find(|f| f.label.equation == equation)
        .unwrap_or_else(|| panic!("no formula {equation}"))
        .verdict
}

#[test]
fn document_000_preliminaries_and_point_factor() {
    let findings = audit_documents(100);
    let verdicts: Vec<(&str, &str)> = findings
        .iter()
        .map(|f| (f.label.equation, f.verdict.keyword()))
        .collect();
    assert_eq!(
        verdicts,
        vec![
            ("§I exp", "wrong"),
            ("§I log", "correct"),
            ("(1) |ω₁| < ε", "correct"),
            ("(1) |ω₂| < ε", "correct"),
            ("§I Jl = Exp Jr", "correct"),
            ("(2)", "correct"),
            ("(3)", "correct"),
            ("(4)", "convention"),
            ("(5) ∂ρ/∂^wP", "correct"),
            ("(5) ∂ρ/∂ξ", "malformed"),
        ]
    );
    // Every disagreement found is recorded as a known erratum, so the gate passes.
    assert!(findings.iter().all(|f| !f.is_unexpected()), "{findings:#?}");
    // Wrong and malformed formulas come with the correct expression.
    for f in findings
        .iter()
        .filter(|f| matches!(f.verdict, Verdict::Wrong(_) | Verdict::Malformed(_)))
    {
        let latex = f.corrected_latex.as_deref().expect("corrected LaTeX");
        assert!(latex.starts_with("\\begin{bmatrix}"), "{latex}");
    }
    assert!(matches!(verdict_of("(4)"), Verdict::Convention(c) if c.contains("swapped")));
    // The chain rule (5) ∂ρ/∂ξ is localised to its link (4).
    let composed = findings
        .iter()
        .find(|f| f.label.equation == "(5) ∂ρ/∂ξ")
        .expect("(5)");
    assert_eq!(
        composed.localisation.as_deref(),
        Some("wrong link(s): (4) (convention); right: (2)")
    );
}

/// `∂(R p)/∂δ` under `R ← Exp(δ) R` is `−[R p]×`; the derivation below prints
/// it with a chosen sign and side, so the audit must tell them apart.
struct RotatedPoint {
    rotation: So3<f64>,
    point: Vector3<f64>,
    printed_sign: f64,
    printed_side: Perturbation,
}

impl Derivation for RotatedPoint {
    fn label(&self) -> Label {
        Label {
            document: "user notes",
            equation: "(7)",
            claim: "∂(R p)/∂δ under R ← Exp(δ) R",
            convention: "left perturbation",
            known_erratum: None,
        }
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 3]
    }
    fn parameters(&self) -> Vec<(&'static str, f64)> {
        let q = self.rotation.quaternion;
        let p = self.point;
        vec![
            ("q_x", q.x),
            ("q_y", q.y),
            ("q_z", q.z),
            ("q_w", q.w),
            ("p_x", p.x),
            ("p_y", p.y),
            ("p_z", p.z),
        ]
    }
    fn input_names(&self) -> Vec<&'static str> {
        vec!["\\delta_1", "\\delta_2", "\\delta_3"]
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        let rotation =
            So3::from_quaternion(factor_core::lie::Quaternion::new(p[0], p[1], p[2], p[3]));
        let point = Vector3::new(p[4], p[5], p[6]);
        rotation
            .retract(x, Perturbation::Left)
            .rotate(&point)
            .as_slice()
            .to_vec()
    }
    fn printed(&self) -> Printed {
        let m = match self.printed_side {
            Perturbation::Left => -hat(&self.rotation.rotate(&self.point)),
            Perturbation::Right => -self.rotation.matrix() * hat(&self.point),
        } * self.printed_sign;
        Printed::Evaluated(DMatrix::from_column_slice(3, 3, m.as_slice()))
    }
    fn conventions(&self) -> Vec<(&'static str, DMatrix<f64>)> {
        let right = -self.rotation.matrix() * hat(&self.point);
        vec![(
            "right perturbation R ← R Exp(δ)",
            DMatrix::from_column_slice(3, 3, right.as_slice()),
        )]
    }
}

fn sample(sign: f64, side: Perturbation) -> impl Fn(&mut Sampler) -> RotatedPoint {
    move |s| RotatedPoint {
        rotation: s.rotation(),
        point: s.vector3(3.0),
        printed_sign: sign,
        printed_side: side,
    }
}

#[test]
fn a_user_derivation_gets_each_verdict() {
    let right: fn(&mut Sampler) -> RotatedPoint = |s| sample(1.0, Perturbation::Left)(s);
    assert_eq!(audit(right, 100, 1).verdict, Verdict::Correct);

    let flipped: fn(&mut Sampler) -> RotatedPoint = |s| sample(-1.0, Perturbation::Left)(s);
    let finding = audit(flipped, 100, 2);
    assert_eq!(
        finding.verdict,
        Verdict::Wrong(Some("opposite sign".into()))
    );
    assert!(finding.max_relative_error.unwrap() > 1.0);
    assert!(finding.corrected_latex.is_some());
    assert!(finding.is_unexpected());

    let other_side: fn(&mut Sampler) -> RotatedPoint = |s| sample(1.0, Perturbation::Right)(s);
    assert_eq!(
        audit(other_side, 100, 3).verdict,
        Verdict::Convention("right perturbation R ← R Exp(δ)".into())
    );
}
