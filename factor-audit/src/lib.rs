//! The derivation audit: hand-derived formulas checked against the truth.
//!
//! Each formula of a document is transcribed as printed (typos included) as a
//! [`Derivation`]: a labelled claim that a printed matrix is the Jacobian (or
//! the value) of a map written once, generic over the scalar. The truth is
//! that map differentiated by dual numbers; the correction is the same map
//! differentiated by the symbolic engine and rendered as LaTeX. [`audit`]
//! compares them at many sampled points and gives a [`Verdict`].
//!
//! A user audits a derivation of their own the same way: implement
//! [`Derivation`] for a type holding a sampled configuration, and call
//! [`verdict::audit`] (or [`Audit::of`] to add it to a report).
//!
//! Or with no transcription at all: [`from_text`] reads the formulas of a
//! Markdown/LaTeX document, gives its symbols meaning through a symbols
//! file, audits them with the same verdicts, and diagnoses errata by
//! searching small edits of the printed formula.

pub mod chain;
pub mod derivation;
pub mod doc000_line_plane;
pub mod doc000_point;
pub mod doc001;
pub mod from_text;
pub mod latex;
pub mod report;
pub mod transcription;
pub mod verdict;

pub use derivation::{Claim, Derivation, Label, Printed, truth};
pub use verdict::{Finding, Verdict, audit};

use factor_testing::samples::Sampler;

/// One formula ready to audit: a closure running [`audit`] on its sampler.
pub struct Audit {
    run: Box<dyn Fn(usize, u64) -> Finding>,
}

impl Audit {
    /// The audit of derivation type `D` sampled by `sample`.
    pub fn of<D: Derivation + 'static>(sample: fn(&mut Sampler) -> D) -> Self {
        Audit {
            run: Box::new(move |samples, seed| audit(sample, samples, seed)),
        }
    }

    /// Runs it at `samples` points drawn from `seed`.
    pub fn run(&self, samples: usize, seed: u64) -> Finding {
        (self.run)(samples, seed)
    }
}

/// Every transcribed formula of the specification documents.
pub fn document_audits() -> Vec<Audit> {
    let mut audits = doc000_point::audits();
    audits.extend(doc000_line_plane::audits());
    audits.extend(doc001::audits());
    audits
}

/// The chain rules of the documents, by equation labels.
pub fn document_chains() -> Vec<chain::Chain> {
    let mut chains = doc000_point::chains();
    chains.extend(doc000_line_plane::chains());
    chains.extend(doc001::chains());
    chains
}

/// Audits every formula of the documents at `samples` points each, and
/// localises the errors of the chain rules.
pub fn audit_documents(samples: usize) -> Vec<Finding> {
    let mut findings: Vec<Finding> = document_audits()
        .iter()
        .enumerate()
        .map(|(i, a)| a.run(samples, 1000 + i as u64))
        .collect();
    chain::localise(&mut findings, &document_chains());
    findings
}
