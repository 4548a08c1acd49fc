//! Auditing a derivation of your own: a hand-derived Jacobian, labelled, is
//! checked against the truth with the same verdicts and report as the
//! documents' formulas.
//!
//! The claim audited here is from a user's notes: "under the right
//! perturbation `R ← R Exp(δ)`, `∂(R p)/∂δ = −R ⌊p⌋×`". The map is written
//! once, generic over the scalar; the printed formula is evaluated in `f64`.
//!
//! `cargo run --example audit_own_derivation` prints the verdict table and
//! the Markdown report; `cargo test` runs the same audit.

use factor_audit::report::{markdown, table};
use factor_audit::transcription::Parameters;
use factor_audit::verdict::audit;
use factor_audit::{Derivation, Finding, Label, Printed};
use factor_core::Scalar;
use factor_core::lie::So3;
use factor_core::lie::so3::hat;
use factor_core::manifold::{Manifold, Perturbation};
use factor_core::storage::{ScalarReader, Storage};
use factor_testing::samples::Sampler;
use nalgebra::{DMatrix, Vector3};

/// One sampled configuration of the claim.
struct RotatedPoint {
    rotation: So3<f64>,
    point: Vector3<f64>,
}

impl Derivation for RotatedPoint {
    fn label(&self) -> Label {
        Label::new(
            "my-notes.md",
            "(7)",
            "∂(R p)/∂δ = −R ⌊p⌋× under R ← R Exp(δ)",
            "right perturbation of R, p fixed",
            None,
        )
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; 3]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        // The stored scalars of R and p, named from their layouts (R_{qx}, …).
        Parameters::new()
            .with("R", &self.rotation)
            .with("p", &self.point)
            .into()
    }
    fn input_names(&self) -> Vec<String> {
        ["\\delta_1", "\\delta_2", "\\delta_3"]
            .map(String::from)
            .to_vec()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        // Read back in the order written: R, then p.
        let mut r = ScalarReader::new(p);
        let rotation: So3<S> = r.read();
        let point: Vector3<S> = r.read();
        rotation
            .retract(x, Perturbation::Right)
            .rotate(&point)
            .to_scalars()
    }
    fn printed(&self) -> Printed {
        let m = -self.rotation.matrix() * hat(&self.point);
        Printed::Evaluated(DMatrix::from_column_slice(3, 3, m.as_slice()))
    }
}

fn sample(s: &mut Sampler) -> RotatedPoint {
    RotatedPoint {
        rotation: s.rotation(),
        point: s.vector3(3.0),
    }
}

fn audit_my_notes() -> Vec<Finding> {
    vec![audit(sample, 100, 7)]
}

fn main() {
    let findings = audit_my_notes();
    print!("{}", table(&findings));
    println!("\n{}", markdown(&findings));
    if findings.iter().any(Finding::is_unexpected) {
        std::process::exit(1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use factor_audit::Verdict;

    #[test]
    fn the_notes_are_right() {
        assert_eq!(audit_my_notes()[0].verdict, Verdict::Correct);
    }
}
