//! Auditing straight from a document's text: the formulas are read from
//! the Markdown/LaTeX (crate `doc-latex`, with the document's own macros),
//! given meaning by a symbols file, and checked by the verdict engine; an
//! erratum is diagnosed by searching small edits of the printed formula.
//! Each claim is read on its own: one that cannot be read is reported with
//! the notation or symbol at fault ([`Unread`]) and the others are
//! audited. `docs/guide/auditing.md` is the guide to writing a symbols file.
//!
//! ```sh
//! slamjac audit notes.md --symbols notes.symbols.toml
//! ```
//!
//! - [`symbols`]: the symbols file (TOML). At the top, `document`, `syntax
//!   = "latex" | "markdown"` (by default from the extension) and `words`
//!   (words the document uses as function names). A `[context.NAME]` may
//!   name a shipped factor (`factor = "point_reprojection"`) whose seeded
//!   samples give the fields, and `[context.NAME.symbols]` says what each
//!   symbol of the document means (keys are LaTeX, read with the
//!   document's macros; a key may be a whole expression, `"q(\omega)"`):
//!   `{ field = "pose.rotation" }` (a field or a part of one, by its layout
//!   names), `{ sample = "rotation_vector" | "unit_quaternion" | "vector3" |
//!   "rotation" | "pose" | "vector" | "scalar", size, range }` (a free
//!   variable; a field or sample may carry its default perturbation,
//!   `side = "left" | "right"` or `update = "…"` in it and `\delta`), a
//!   LaTeX definition `"R X + t"` (with `{ latex = …, components = ["P_x",
//!   …] }` to name its entries), `{ function = "left_jacobian" }` (see
//!   [`functions`]), `{ args = ["x"], latex = "…" }` (a function the
//!   document defines), `{ perturbs = "T", side = "left", update = "…",
//!   parts = ["\delta\phi", "\delta\rho"], coordinates = [1, 2, 3] }` (a
//!   tangent: what a derivative by it perturbs), `{ residual = [1] }` (the
//!   factor's own residual). `[context.NAME.operators]` gives operators,
//!   accents and words their meaning (`"\boxminus"`, `"^\odot"`,
//!   `"\hat"`, `"between"` to `{ args, latex }`), and each
//!   `[[context.NAME.link]]` (`lhs`, `of`, `wrt`, `side`, `output`) a
//!   derivative the document states only in words, for its chain rules.
//!   Each `[[claim]]` names an equation: `id` (its name in reports),
//!   `context`, where it is (`label = "(5)"`, `anchor = "…"` (a piece of
//!   exactly one formula), or `after = "…"` (the display after a piece of
//!   prose); then `line`, `statement`, `step` (one side of a chain of
//!   equalities), `chain = true` (where a chain over several lines
//!   arrives), `case` (a row of `cases`)), what it claims (`kind =
//!   "jacobian" | "value" | "first_order" | "differential"`, `of`, `wrt`,
//!   `side`, `update`, `output`, `at_zero`; by default read from its
//!   printed left side), `lhs` (how chain rules elsewhere write it),
//!   `expected` (the verdict the gate accepts, or `"unread"`), `erratum`
//!   (a reader's note, kept apart from the engine's diagnosis), `claim`
//!   and `convention` (words), `stacked_fractions`, its own
//!   `[claim.symbols]` and `[[claim.conventions]]` (`description` with
//!   `side`, `update`, `of` or `wrt`).
//! - Loading: a document and its symbols file read claim by claim
//!   ([`TextAudit::read`]) or stopping at the first error
//!   ([`TextAudit::load`]).
//! - [`lower`]: LaTeX to [`term::Term`]s; an undefined symbol or notation
//!   without meaning is an error naming the equation and the fragment.
//! - [`eval`]: terms evaluated over any scalar ([`value`] holds the
//!   arithmetic), so the truth is the map differentiated by dual numbers,
//!   through the toolchain's own code ([`functions`], [`factors`]), never
//!   through a formula of the document.
//! - [`claims`]: each claim located, compiled and sampled as a
//!   [`crate::Derivation`].
//! - [`errata`]: the erratum search, over the edits of [`edits`].
//! - [`report`]: findings with the quote, its place, the formula as
//!   understood, and the diagnosis.
//!
//! Bounds on hostile input: documents up to [`MAX_DOCUMENT_BYTES`], symbols
//! files up to [`symbols::MAX_SYMBOLS_BYTES`] with at most
//! [`symbols::MAX_CLAIMS`] claims and [`symbols::MAX_SYMBOLS`] symbols a
//! context, definitions nested at most [`context::MAX_DEFINITION_DEPTH`]
//! deep, values at most [`value::MAX_DIMENSION`] rows and columns,
//! evaluation at most [`eval::MAX_EVAL_DEPTH`] deep, printed formulas of at
//! most [`MAX_FORMULA_NODES`] nodes, and the erratum search at most
//! [`errata::MAX_CANDIDATES`] edited formulas an equation,
//! [`errata::MAX_CANDIDATES_PER_RUN`] an audit, on formulas of at most
//! [`errata::MAX_SEARCHED_NODES`] nodes.
//! Loading and auditing run on a thread with a [`STACK_BYTES`] stack, so the
//! depth bounds are reached (and reported as errors) without overflowing the
//! stack, in a debug build too.

pub mod claims;
pub mod context;
pub mod edits;
pub mod errata;
pub mod eval;
pub mod factors;
pub mod functions;
mod load;
pub mod lower;
pub mod readings;
pub mod report;
pub mod stored;
pub mod symbols;
pub mod term;
pub mod tree;
pub mod understood;
pub mod value;

use std::borrow::Cow;

use doc_latex::ParseError;
use factor_testing::samples::Sampler;

use crate::chain::{Chain, localise};
use crate::verdict::{Finding, Verdict, audit};
use claims::{TextClaim, TextDerivation};
use context::Context;
use lower::LowerError;
use report::TextFinding;
use symbols::one_line;

pub use load::Unread;

/// Longest document read, in bytes.
pub const MAX_DOCUMENT_BYTES: usize = 1 << 20;
/// Largest printed formula audited, in syntax-tree nodes.
pub const MAX_FORMULA_NODES: usize = 2000;
/// Stack of the thread a document is loaded and audited on: lowering and
/// evaluation recurse as deep as formulas and definitions nest (bounded by
/// [`context::MAX_DEFINITION_DEPTH`], `doc_latex::MAX_DEPTH` and
/// [`eval::MAX_EVAL_DEPTH`]), and a debug build's frames are large.
pub const STACK_BYTES: usize = 64 << 20;

/// `f` on a thread with a [`STACK_BYTES`] stack (inline if none can be
/// started).
fn on_large_stack<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    let task = std::sync::Mutex::new(Some(f));
    let take = || task.lock().ok().and_then(|mut t| t.take());
    let spawned = std::thread::scope(|scope| {
        let handle = std::thread::Builder::new()
            .stack_size(STACK_BYTES)
            .spawn_scoped(scope, || take().map(|f| f()))
            .ok()?;
        match handle.join() {
            Ok(value) => value,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    });
    match spawned {
        Some(value) => value,
        None => take().map_or_else(|| unreachable!("the task runs once"), |f| f()),
    }
}

/// Why a document and its symbols file cannot be audited; one line each,
/// naming the equation, the symbol or the fragment at fault.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TextError {
    /// An input over its size bound.
    #[error("the {what} is larger than {limit} bytes")]
    TooLarge {
        /// Which input.
        what: &'static str,
        /// The bound.
        limit: usize,
    },
    /// The symbols file states more claims than an audit takes.
    #[error("the symbols file states more than {limit} claims")]
    TooManyClaims {
        /// The bound.
        limit: usize,
    },
    /// The symbols file states no claim: an audit of nothing would pass
    /// any gate.
    #[error("the symbols file states no claim ([[claim]] tables): nothing to audit")]
    NoClaims,
    /// The symbols file is not valid TOML, or not in the expected shape.
    #[error("symbols file{}: {message}", line.map(|l| format!(", line {l}")).unwrap_or_default())]
    Toml {
        /// The TOML line at fault.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// A symbol's meaning is wrong.
    #[error("{}symbol `{}`: {}", equation.as_ref().map(|e| format!("equation {}, ", one_line(e))).unwrap_or_default(), one_line(symbol), one_line(message))]
    Symbol {
        /// The symbol as written.
        symbol: String,
        /// The equation whose readings it belongs to, if any.
        equation: Option<String>,
        /// What is wrong.
        message: String,
    },
    /// A context is wrong.
    #[error("context `{}`: {}", one_line(context), one_line(message))]
    Context {
        /// The context.
        context: String,
        /// What is wrong.
        message: String,
    },
    /// A claim is wrong.
    #[error("equation {}: {}", one_line(claim), one_line(message))]
    Claim {
        /// The claim's id.
        claim: String,
        /// What is wrong.
        message: String,
    },
    /// A formula of the document means nothing to the symbols file.
    #[error("equation {}, line {line}: {}", one_line(claim), one_line(&error.to_string()))]
    Formula {
        /// The claim's id.
        claim: String,
        /// The document line.
        line: usize,
        /// The fragment and why.
        error: LowerError,
    },
    /// A formula of the document is not valid LaTeX.
    #[error("{0}")]
    Parse(ParseError),
}

/// A document's claims, ready to audit.
#[derive(Debug, Clone)]
pub struct TextAudit {
    /// The document's file name.
    pub document: String,
    /// The contexts.
    pub contexts: Vec<Context>,
    /// The claims that were read, in the file's order.
    pub claims: Vec<TextClaim>,
    /// The claims that could not be read.
    unread: Vec<Unread>,
}

impl TextAudit {
    /// The chain rules among the claims.
    pub fn chains(&self) -> Vec<Chain> {
        self.claims
            .iter()
            .filter(|c| !c.links.is_empty())
            .map(|c| Chain {
                document: self.document.clone(),
                composed: c.label.equation.clone(),
                links: c
                    .links
                    .iter()
                    .filter_map(|k| self.claims.iter().find(|l| l.index == *k))
                    .map(|l| l.label.equation.clone())
                    .collect(),
            })
            .collect()
    }

    /// The seed of claim `i`'s samples.
    pub fn seed(i: usize) -> u64 {
        2000 + i as u64
    }

    /// Audits every claim at `samples` points, localises the chain rules
    /// and diagnoses the errata.
    pub fn run(&self, samples: usize) -> Vec<TextFinding> {
        on_large_stack(|| self.run_here(samples))
    }

    fn run_here(&self, samples: usize) -> Vec<TextFinding> {
        let audit_one = |c: &TextClaim| {
            let ctx = &self.contexts[c.context];
            audit(
                |s: &mut Sampler| TextDerivation::new(c, ctx, ctx.sample(s)),
                samples,
                Self::seed(c.index),
            )
        };
        let mut claims: Vec<Cow<'_, TextClaim>> = self.claims.iter().map(Cow::Borrowed).collect();
        let mut findings: Vec<Finding> = self.claims.iter().map(audit_one).collect();
        // A formula malformed as read because of which function a name is
        // (`exp` or `Exp`) is read with the one that evaluates.
        for (finding, claim) in findings.iter_mut().zip(claims.iter_mut()) {
            if matches!(finding.verdict, Verdict::Malformed(_))
                && let Some(read) = readings::well_formed(self, claim, samples)
            {
                *finding = audit_one(&read);
                *claim = Cow::Owned(read);
            }
        }
        // A formula wrong or malformed as read may be right as its author
        // meant the notation: never reported wrong then.
        for (finding, claim) in findings.iter_mut().zip(&claims) {
            if matches!(finding.verdict, Verdict::Wrong(_) | Verdict::Malformed(_))
                && let Some(reading) = readings::settle(self, claim, samples)
            {
                finding.verdict = Verdict::Ambiguous(reading);
                finding.corrected_latex = None;
            }
        }
        localise(&mut findings, &self.chains());
        let mut budget = errata::MAX_CANDIDATES_PER_RUN;
        findings
            .into_iter()
            .zip(&claims)
            .map(|(mut finding, claim)| {
                let searched = matches!(finding.verdict, Verdict::Wrong(_) | Verdict::Malformed(_))
                    .then(|| {
                        let s = errata::search(self, claim, samples, budget);
                        budget -= s.evaluated.min(budget);
                        s
                    });
                let diagnosis = searched.as_ref().and_then(|s| s.diagnosis.clone());
                if let (Verdict::Wrong(words), Some(d)) = (&mut finding.verdict, &diagnosis) {
                    *words = Some(d.words.clone());
                }
                // The expanded truth is in the stored scalars' names: shown
                // only when short, and never beside a correction in the
                // document's own terms.
                finding.corrected_latex = finding
                    .corrected_latex
                    .filter(|l| diagnosis.is_none() && report::expansion_fits(l, &claim.quote));
                TextFinding {
                    finding,
                    line: claim.line,
                    quote: claim.quote.clone(),
                    understood: claim.understood.clone(),
                    notes: claim.notes.clone(),
                    expected: claim.expected.clone(),
                    diagnosis,
                    searched: searched.map(|s| s.evaluated),
                }
            })
            .collect()
    }
}
