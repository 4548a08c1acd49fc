//! Chain rules: a composed formula and the links it multiplies together.
//!
//! When a composed formula disagrees with the truth, the audit names the
//! links that disagree too: the place in the derivation where it went wrong.

use crate::verdict::{Finding, Verdict};

/// A chain rule of a document: `composed` (an equation label) is the
/// product of `links` (equation labels of the same document, audited on
/// their own).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Chain {
    /// The document's file name.
    pub document: String,
    /// The composed formula's equation label.
    pub composed: String,
    /// The links' equation labels, in the order they are multiplied.
    pub links: Vec<String>,
}

/// Sets [`Finding::localisation`] on every composed formula of `chains` that
/// is not correct: which of its links are wrong, malformed or right only
/// under another convention, and which are right.
pub fn localise(findings: &mut [Finding], chains: &[Chain]) {
    for chain in chains {
        let verdict_of = |equation: &str| {
            findings
                .iter()
                .find(|f| f.label.document == chain.document && f.label.equation == equation)
                .map(|f| f.verdict.clone())
        };
        let (mut bad, mut good) = (Vec::new(), Vec::new());
        for link in &chain.links {
            match verdict_of(link) {
                Some(Verdict::Correct) => good.push(link.to_string()),
                Some(v) => bad.push(format!("{link} ({})", v.keyword())),
                None => {}
            }
        }
        let Some(composed) = findings
            .iter_mut()
            .find(|f| f.label.document == chain.document && f.label.equation == chain.composed)
        else {
            continue;
        };
        if composed.verdict == Verdict::Correct {
            continue;
        }
        composed.localisation = Some(if bad.is_empty() {
            format!(
                "every link ({}) is right on its own: the error is in how they are combined",
                good.join(", ")
            )
        } else {
            format!(
                "wrong link(s): {}; right: {}",
                bad.join(", "),
                if good.is_empty() {
                    "none".to_string()
                } else {
                    good.join(", ")
                }
            )
        });
    }
}
