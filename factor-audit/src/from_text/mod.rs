//! Auditing straight from a document's text: the formulas are read from
//! the Markdown/LaTeX (crate `doc-latex`), given meaning by a symbols file,
//! and checked by the same verdict engine as the transcribed catalogues;
//! an erratum is diagnosed by searching small edits of the printed formula.
//!
//! ```sh
//! slamjac audit notes.md --symbols notes.symbols.toml
//! ```
//!
//! - [`symbols`]: the symbols file (TOML). A `[context.NAME]` names a
//!   shipped factor (`factor = "point_reprojection"`) whose seeded samples
//!   give the fields, and `[context.NAME.symbols]` says what each symbol of
//!   the document means: `{ field = "pose.rotation" }` (a field or a part of
//!   one, by its layout names), `{ sample = "rotation_vector" | "unit_quaternion"
//!   | "vector3" | "rotation" | "pose" }` (a free variable), a LaTeX
//!   definition `"R X + t"` (with `{ latex = …, components = ["P_x", …] }`
//!   to name its entries), `{ function = "left_jacobian" }` (see
//!   [`functions`]), `{ perturbs = "T", side = "left", parts = ["\\delta\\phi",
//!   "\\delta\\rho"], coordinates = [1, 2, 3] }` (a tangent: what a derivative
//!   by it perturbs), `{ residual = [1] }` (the factor's own residual).
//!   Each `[[claim]]` names an equation: `id` (its name in reports),
//!   `context`, `label = "(5)"` or `anchor = "…"` (with `line`, `chain =
//!   true` to audit where a chain of equalities arrives, `case` for a row
//!   of `cases`), what it claims (`kind = "jacobian" | "value" |
//!   "first_order"`, `of`, `wrt`, `side`, `at_zero`; by default read from
//!   its printed left side), `lhs` (how chain rules elsewhere write it),
//!   `expected` (the verdict the gate accepts), `erratum` (a reader's
//!   note, kept apart from the engine's diagnosis), `claim` and
//!   `convention` (words), `stacked_fractions`, its own `[claim.symbols]`
//!   and `[[claim.conventions]]` (`description` with `side`, `update`,
//!   `of` or `wrt`).
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
pub mod lower;
pub mod report;
pub mod stored;
pub mod symbols;
pub mod term;
pub mod tree;
pub mod value;

use doc_latex::{Document, ParseError};
use factor_testing::samples::Sampler;

use crate::chain::{Chain, localise};
use crate::verdict::{Finding, Verdict, audit};
use claims::{TextClaim, TextDerivation, compile, links, locate};
use context::Context;
use eval::{Env, Space};
use lower::LowerError;
use report::TextFinding;
use symbols::{SymbolsFile, one_line};
use term::{Meaning, Variable};

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
    /// The claims, in the file's order.
    pub claims: Vec<TextClaim>,
}

impl TextAudit {
    /// Reads `document` (named `name` in reports) and its symbols file.
    pub fn load(name: &str, document: &str, symbols: &str) -> Result<Self, TextError> {
        on_large_stack(|| Self::load_here(name, document, symbols))
    }

    fn load_here(name: &str, document: &str, symbols: &str) -> Result<Self, TextError> {
        if document.len() > MAX_DOCUMENT_BYTES {
            return Err(TextError::TooLarge {
                what: "document",
                limit: MAX_DOCUMENT_BYTES,
            });
        }
        let file = SymbolsFile::parse(symbols)?;
        let doc = Document::parse(document).map_err(TextError::Parse)?;
        let names: Vec<&String> = file.context.keys().collect();
        let mut contexts = file
            .context
            .iter()
            .map(|(name, spec)| Context::build(name, spec))
            .collect::<Result<Vec<_>, _>>()?;
        // First pass: locate every claim, its own readings and how chain
        // rules write it, so that links resolve whatever their order.
        let mut located = Vec::with_capacity(file.claims.len());
        let mut context_of = Vec::with_capacity(file.claims.len());
        for (i, spec) in file.claims.iter().enumerate() {
            let c = names
                .iter()
                .position(|n| **n == spec.context)
                .ok_or_else(|| TextError::Claim {
                    claim: spec.id.clone(),
                    message: format!("no context `{}`", spec.context),
                })?;
            contexts[c].add_claim_symbols(i, &spec.id, &spec.symbols)?;
            let place = locate(&doc, spec)?;
            if let Some(key) = claims::lhs_key(spec, &place)? {
                contexts[c].links.entry(key).or_insert(i);
            }
            located.push(place);
            context_of.push(c);
        }
        for ctx in &mut contexts {
            let ids: Vec<String> = file.claims.iter().map(|c| c.id.clone()).collect();
            ctx.lower_all(|scope| scope.map(|s| ids[s].clone()))?;
            ctx.printed = vec![None; file.claims.len()];
        }
        let mut claims = Vec::with_capacity(file.claims.len());
        for (i, (spec, place)) in file.claims.iter().zip(located).enumerate() {
            let ctx = &mut contexts[context_of[i]];
            let mut claim = compile(ctx, context_of[i], i, spec, place.clone(), name)?;
            claim.links = links(&place, ctx, i);
            for k in claim.printed.links() {
                if !claim.links.contains(&k) {
                    claim.links.push(k);
                }
            }
            ctx.printed[i] = Some(claim.printed.clone());
            claims.push(claim);
        }
        let mut audit = TextAudit {
            document: name.to_string(),
            contexts,
            claims,
        };
        audit.check_links()?;
        audit.fix_shapes()?;
        Ok(audit)
    }

    /// A chain rule's links must be claims whose printed formulas are not
    /// chain rules themselves (one level is followed).
    fn check_links(&self) -> Result<(), TextError> {
        for c in &self.claims {
            for k in c.printed.links() {
                if !self.claims[k].printed.links().is_empty() {
                    return Err(TextError::Claim {
                        claim: c.label.equation.clone(),
                        message: format!(
                            "its link {} is itself a chain rule (one level is followed)",
                            self.claims[k].label.equation
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// Sizes what a sample tells: defined variables and each map's value.
    fn fix_shapes(&mut self) -> Result<(), TextError> {
        let samples: Vec<Vec<f64>> = self
            .contexts
            .iter()
            .map(|c| c.sample(&mut Sampler::new(0)))
            .collect();
        for (ctx, stored) in self.contexts.iter_mut().zip(&samples) {
            ctx.shape_defined(|ctx, symbol| shape_of(ctx, stored, symbol).map_err(|e| e.0))?;
        }
        for claim in &mut self.claims {
            let ctx = &self.contexts[claim.context];
            let stored = &samples[claim.context];
            let id = claim.label.equation.clone();
            let error = |m: String| TextError::Claim {
                claim: id.clone(),
                message: m,
            };
            let fix = |v: &mut Option<Variable>| -> Result<(), TextError> {
                match v {
                    Some(Variable::Defined { symbol, shape, .. }) => {
                        *shape = shape_of(ctx, stored, *symbol).map_err(|e| error(e.0))?;
                    }
                    Some(Variable::Update { symbol, dim, .. }) => {
                        let (r, c) = shape_of(ctx, stored, *symbol).map_err(|e| error(e.0))?;
                        *dim = r * c;
                    }
                    _ => {}
                }
                Ok(())
            };
            fix(&mut claim.variable)?;
            for c in &mut claim.conventions {
                fix(&mut c.variable)?;
            }
            let value = TextDerivation::new(claim, ctx, stored.clone())
                .map_value()
                .map_err(|e| error(format!("its map cannot be evaluated: {e}")))?;
            if value.iter().any(|x| !x.is_finite()) {
                return Err(error("its map is not finite at a sample".into()));
            }
            claim.value_shape = value.shape();
        }
        Ok(())
    }

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
                    .map(|k| self.claims[*k].label.equation.clone())
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
        let mut findings: Vec<Finding> = self
            .claims
            .iter()
            .map(|c| {
                let ctx = &self.contexts[c.context];
                audit(
                    |s: &mut Sampler| TextDerivation::new(c, ctx, ctx.sample(s)),
                    samples,
                    Self::seed(c.index),
                )
            })
            .collect();
        localise(&mut findings, &self.chains());
        let mut budget = errata::MAX_CANDIDATES_PER_RUN;
        findings
            .into_iter()
            .zip(&self.claims)
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
                TextFinding {
                    finding,
                    line: claim.line,
                    quote: claim.quote.clone(),
                    understood: claim.understood(),
                    expected: claim.expected.clone(),
                    diagnosis,
                    searched: searched.map(|s| s.evaluated),
                }
            })
            .collect()
    }
}

/// The shape of symbol `symbol`'s value at the sample `stored`.
fn shape_of(
    ctx: &Context,
    stored: &[f64],
    symbol: usize,
) -> Result<(usize, usize), value::ShapeError> {
    if matches!(ctx.table.entries[symbol].meaning, Meaning::Tangent { .. }) {
        return Err(value::ShapeError("a tangent has no value".into()));
    }
    let space = Space {
        table: &ctx.table,
        printed: &ctx.printed,
        factor: ctx.factor,
    };
    let mut env = Env::new(space, stored.to_vec());
    Ok(env.symbol(symbol)?.matrix()?.shape())
}
