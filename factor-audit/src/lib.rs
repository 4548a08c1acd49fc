//! The derivation audit: hand-derived formulas checked against the truth.
//!
//! A formula is a [`Derivation`]: a labelled claim that a printed matrix is
//! the Jacobian (or the value) of a map written once, generic over the
//! scalar. The truth is that map differentiated by dual numbers; the
//! correction is the same map differentiated by the symbolic engine and
//! rendered as LaTeX. [`audit`] compares them at many sampled points and
//! gives a [`Verdict`].
//!
//! Documents are audited from their text ([`from_text`]): it reads the
//! formulas of a Markdown/LaTeX document, gives its symbols meaning through
//! a symbols file, makes each claim a [`Derivation`], audits them with the
//! same verdicts, and diagnoses errata by searching small edits of the
//! printed formula. The specification documents and the corpus of public
//! derivations in `documents/` are audited that way; a notation fix is made
//! once, in `doc-latex` or [`from_text`].
//!
//! A formula written as code (a derivation of your own, outside any
//! document) is audited the same way: implement [`Derivation`] for a type
//! holding a sampled configuration, and call [`verdict::audit`] (or
//! [`Audit::of`] to add it to a report).

pub mod chain;
pub mod derivation;
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
