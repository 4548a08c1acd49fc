//! Snapshot tests (`insta`): the generated Jacobians of every factor at a
//! fixed configuration beside the documents' formulas where the audit finds
//! them right, the audit's verdicts, and the generated kernel sources.
//!
//! Numbers are printed with 6 significant digits and audit errors bucketed,
//! so the snapshots are stable across machines. Accept an intended change
//! with `cargo insta review` (or `INSTA_UPDATE=always cargo test`).

use std::fmt::Write;

use factor_audit::from_text::TextAudit;
use factor_audit::from_text::claims::TextDerivation;
use factor_audit::{Derivation, Printed};
use factor_core::storage::Storage;
use factor_core::{DynLinearization, Factor};
use factor_testing::samples::Sampler;
use nalgebra::DMatrix;

/// `x` with 6 significant digits; tiny values (rounding noise) print as 0.
fn number(x: f64) -> String {
    if x.abs() < 1e-12 {
        "0".into()
    } else {
        format!("{x:.5e}")
    }
}

fn matrix(m: &DMatrix<f64>) -> String {
    let mut out = String::new();
    for r in 0..m.nrows() {
        let row: Vec<String> = (0..m.ncols())
            .map(|c| format!("{:>13}", number(m[(r, c)])))
            .collect();
        let _ = writeln!(out, "  [{}]", row.join(", "));
    }
    out
}

fn linearization<F: Factor>(factor: &F) -> String {
    let lin: DynLinearization = factor
        .linearize_generated_dyn()
        .expect("a generated kernel")
        .expect("a well-conditioned configuration");
    let mut out = format!(
        "{}\nresidual: {:?}\n",
        F::NAME,
        lin.residual.iter().map(|x| number(*x)).collect::<Vec<_>>()
    );
    for (variable, block) in F::variables().iter().zip(&lin.jacobians) {
        let _ = write!(
            out,
            "d/d{} ({}):\n{}",
            variable.name,
            variable.tangent,
            matrix(block)
        );
    }
    out
}

#[test]
fn generated_jacobians_at_fixed_configurations() {
    let mut s = Sampler::new(42);
    insta::assert_snapshot!("point_reprojection", linearization(&s.point_reprojection()));
    insta::assert_snapshot!("line_reprojection", linearization(&s.line_reprojection()));
    insta::assert_snapshot!(
        "plucker_line_reprojection",
        linearization(&s.plucker_line_reprojection())
    );
    insta::assert_snapshot!("plane", linearization(&s.plane()));
    insta::assert_snapshot!("free_line", linearization(&s.free_line()));
    insta::assert_snapshot!(
        "snavely_reprojection",
        linearization(&s.snavely_reprojection())
    );
    insta::assert_snapshot!(
        "stereo_reprojection",
        linearization(&s.stereo_reprojection())
    );
    insta::assert_snapshot!("between", linearization(&s.between()));
}

/// A specification document audited from its text.
fn shipped(name: &str) -> TextAudit {
    let text = |ext: &str| {
        std::fs::read_to_string(format!(
            "{}/documents/{name}.{ext}",
            env!("CARGO_MANIFEST_DIR")
        ))
        .expect("the document is shipped")
    };
    TextAudit::load(&format!("{name}.txt"), &text("txt"), &text("symbols.toml"))
        .expect("the document loads")
}

/// The point block beside document 000 (5), first line, which the audit
/// finds correct: the two must print the same digits.
#[test]
fn point_block_beside_document_000_equation_5() {
    let factor = Sampler::new(42).point_reprojection();
    let lin = factor.linearize_generated().expect("valid");
    let audit = shipped("000_29653f4af9b68bb8");
    let claim = audit
        .claims
        .iter()
        .find(|c| c.label.equation == "(5) ∂ρ/∂^wP")
        .expect("(5) is read");
    let ctx = &audit.contexts[claim.context];
    let d = TextDerivation::new(claim, ctx, factor.to_scalars());
    let Printed::Evaluated(printed) = d.printed() else {
        panic!("(5) is well formed");
    };
    let generated = DMatrix::from_column_slice(2, 3, lin.point.as_slice());
    let text = format!(
        "generated ∂ρ/∂X:\n{}document 000 (5):\n{}",
        matrix(&generated),
        matrix(&printed)
    );
    insta::assert_snapshot!("point_block_vs_document_000_5", text);
}

#[test]
fn audit_verdicts() {
    let mut out = String::new();
    let findings = ["000_29653f4af9b68bb8", "001_85032ab900231dbd"]
        .into_iter()
        .flat_map(|name| shipped(name).run(100))
        .map(|t| t.finding);
    for f in findings {
        // Agreement is bucketed; a disagreement keeps two significant digits.
        let error = match f.max_relative_error {
            None => "—".to_string(),
            Some(e) if e <= 1e-9 => "≤ 1e-9".to_string(),
            Some(e) => format!("{e:.1e}"),
        };
        let _ = writeln!(
            out,
            "{} {}: {} ({error}){}",
            f.label.document,
            f.label.equation,
            f.verdict.keyword(),
            f.localisation.map(|l| format!("; {l}")).unwrap_or_default()
        );
    }
    insta::assert_snapshot!("audit_verdicts", out);
}

#[test]
fn generated_kernel_sources() {
    for module in slamjac::kernels::generate_all()
        .expect("the document kernels generate")
        .modules
    {
        insta::assert_snapshot!(format!("kernel_{}", module.name), module.source);
    }
}
