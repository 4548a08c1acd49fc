//! Loading a document and its symbols file: every claim located, its
//! readings added, compiled and sized, each on its own. A claim that cannot
//! be read (notation without meaning, an anchor that misses, a symbol the
//! file does not define) is an [`Unread`] claim with its error; the others
//! are audited ([`TextAudit::read`]). [`TextAudit::load`] is the strict
//! form: the first error fails it.

use doc_latex::{Document, Options, Syntax};
use factor_testing::samples::Sampler;

use super::claims::{self, TextClaim, TextDerivation, compile, links, locate};
use super::context::Context;
use super::eval::{Env, Space};
use super::symbols::{Quaternions, SymbolsFile};
use super::term::{Meaning, Variable};
use super::value::ShapeError;
use super::{MAX_DOCUMENT_BYTES, TextAudit, TextError, on_large_stack};
use crate::derivation::{Derivation, Printed, truth};

/// A claim of the symbols file that could not be read.
#[derive(Debug, Clone, PartialEq)]
pub struct Unread {
    /// Its index among the file's claims.
    pub index: usize,
    /// Its id.
    pub id: String,
    /// The document line it was found on, if it was.
    pub line: Option<usize>,
    /// Its line as printed, if it was found.
    pub quote: Option<String>,
    /// Why it cannot be read: the notation, symbol or anchor at fault.
    pub error: TextError,
    /// The verdict the symbols file expects (`unread` when it knows).
    pub expected: String,
}

impl Unread {
    /// Whether it should fail a run that gates on unread claims: the file
    /// does not expect it unread.
    pub fn is_unexpected(&self) -> bool {
        self.expected != "unread"
    }

    /// What the printed formula may have wrong, when the reading stopped on
    /// something missing from it (an erratum found while reading: an empty
    /// matrix entry, an operand or a closing delimiter missing); `None` when
    /// the reading stopped on notation the audit does not read.
    pub fn suspected_erratum(&self) -> Option<String> {
        use doc_latex::ErrorKind;
        let TextError::Parse(e) = &self.error else {
            return None;
        };
        Some(match &e.kind {
            ErrorKind::Empty("matrix entry") => {
                "an entry of the printed matrix is empty (a value is missing, or a block is meant \
                 to span the empty cells)"
                    .to_string()
            }
            ErrorKind::MissingOperand(op) if !op.is_empty() => {
                format!("the operand after `{op}` is missing")
            }
            ErrorKind::Unclosed { open, expected } => {
                format!("`{open}` is never closed by `{expected}`")
            }
            ErrorKind::UnbalancedBraces => "its braces do not balance".to_string(),
            _ => return None,
        })
    }
}

/// How a build treats an error: stop at the first, or record it against
/// the claim and go on.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Mode {
    Strict,
    Each,
}

/// Records (or, strict, returns) the error of claim `i`.
struct Failures {
    mode: Mode,
    errors: Vec<Option<TextError>>,
}

impl Failures {
    fn fail(&mut self, i: usize, e: TextError) -> Result<(), TextError> {
        if self.mode == Mode::Strict {
            return Err(e);
        }
        if self.errors[i].is_none() {
            self.errors[i] = Some(e);
        }
        Ok(())
    }

    fn failed(&self, i: usize) -> bool {
        self.errors[i].is_some()
    }
}

/// The document's syntax: the file's `syntax`, else its extension.
fn syntax_of(name: &str, file: &SymbolsFile) -> Syntax {
    match file.syntax.as_deref() {
        Some("latex") => Syntax::Latex,
        Some(_) => Syntax::Markdown,
        None if [".tex", ".ltx", ".lyx"].iter().any(|e| name.ends_with(e)) => Syntax::Latex,
        None => Syntax::Markdown,
    }
}

impl TextAudit {
    /// Reads `document` (named `name` in reports) and its symbols file;
    /// the first claim that cannot be read fails it.
    pub fn load(name: &str, document: &str, symbols: &str) -> Result<Self, TextError> {
        on_large_stack(|| Self::build(name, document, symbols, Mode::Strict))
    }

    /// Reads `document` and its symbols file claim by claim: the claims
    /// that cannot be read are [`TextAudit::unread`] with their errors, the
    /// others are audited. Fails only when the files as a whole cannot be
    /// read (too large, the TOML not valid, a display never closed).
    pub fn read(name: &str, document: &str, symbols: &str) -> Result<Self, TextError> {
        on_large_stack(|| Self::build(name, document, symbols, Mode::Each))
    }

    fn build(name: &str, document: &str, symbols: &str, mode: Mode) -> Result<Self, TextError> {
        if document.len() > MAX_DOCUMENT_BYTES {
            return Err(TextError::TooLarge {
                what: "document",
                limit: MAX_DOCUMENT_BYTES,
            });
        }
        let file = SymbolsFile::parse(symbols)?;
        let words: Vec<&str> = file.words.iter().map(String::as_str).collect();
        let doc = Document::parse_with(
            document,
            Options {
                syntax: syntax_of(name, &file),
                words: &words,
            },
        )
        .map_err(TextError::Parse)?;
        let vocabulary = doc.vocabulary().clone();
        let n = file.claims.len();
        let mut failures = Failures {
            mode,
            errors: vec![None; n],
        };
        let mut contexts: Vec<Context> = Vec::new();
        let mut built: Vec<(String, Result<usize, TextError>)> = Vec::new();
        for (name, spec) in &file.context {
            match Context::build(name, spec, &vocabulary) {
                Ok(mut c) => {
                    c.jpl_quaternions = file.quaternions == Some(Quaternions::Jpl);
                    built.push((name.clone(), Ok(contexts.len())));
                    contexts.push(c);
                }
                Err(e) if mode == Mode::Strict => return Err(e),
                Err(e) => built.push((name.clone(), Err(e))),
            }
        }
        // First pass: locate every claim, its own readings and how chain
        // rules write it, so that links resolve whatever their order.
        let mut located = vec![None; n];
        let mut context_of = vec![usize::MAX; n];
        for (i, spec) in file.claims.iter().enumerate() {
            let c = match built.iter().find(|(name, _)| *name == spec.context) {
                Some((_, Ok(c))) => *c,
                Some((_, Err(e))) => {
                    failures.fail(i, e.clone())?;
                    continue;
                }
                None => {
                    failures.fail(
                        i,
                        TextError::Claim {
                            claim: spec.id.clone(),
                            message: format!("no context `{}`", spec.context),
                        },
                    )?;
                    continue;
                }
            };
            context_of[i] = c;
            if let Err(e) = contexts[c].add_claim_symbols(i, &spec.id, &spec.symbols) {
                failures.fail(i, e)?;
                continue;
            }
            let place = match locate(&doc, spec) {
                Ok(p) => p,
                Err(e) => {
                    failures.fail(i, e)?;
                    continue;
                }
            };
            // A name an evaluation bar binds that the file does not define
            // (`\left. \frac{∂ A ⊕ p}{∂ A} \right|_{A = D}`) is defined by
            // the bar, in this formula.
            let bound = bar_definitions(&place, &contexts[c], i);
            if let Err(e) = contexts[c].add_claim_symbols(i, &spec.id, &bound) {
                failures.fail(i, e)?;
                continue;
            }
            match claims::lhs_key(spec, &place, &vocabulary) {
                Ok(Some(key)) => {
                    contexts[c].links.entry(key).or_insert(i);
                }
                Ok(None) => {}
                Err(e) => {
                    failures.fail(i, e)?;
                    continue;
                }
            }
            located[i] = Some(place);
        }
        let ids: Vec<String> = file.claims.iter().map(|c| c.id.clone()).collect();
        for ctx in &mut contexts {
            // A definition that cannot be read fails the claims that use
            // it, naming it; strict, it fails the load.
            let lowered = ctx.lower_all(|scope| scope.map(|s| ids[s].clone()));
            if mode == Mode::Strict {
                lowered?;
            }
            ctx.printed = vec![None; n];
        }
        let mut compiled: Vec<Option<TextClaim>> = vec![None; n];
        for (i, spec) in file.claims.iter().enumerate() {
            let Some(place) = located[i].clone() else {
                continue;
            };
            let ctx = &mut contexts[context_of[i]];
            match compile(ctx, context_of[i], i, spec, place.clone(), name) {
                Ok(mut claim) => {
                    claim.links = links(&place, ctx, i);
                    for k in claim.printed.links() {
                        if !claim.links.contains(&k) {
                            claim.links.push(k);
                        }
                    }
                    ctx.printed[i] = Some(claim.printed.clone());
                    compiled[i] = Some(claim);
                }
                Err(e) => failures.fail(i, e)?,
            }
        }
        check_links(&compiled, &mut failures)?;
        let samples: Vec<Vec<f64>> = contexts
            .iter()
            .map(|c| c.sample(&mut Sampler::new(0)))
            .collect();
        for (k, (ctx, stored)) in contexts.iter_mut().zip(&samples).enumerate() {
            if let Err(e) =
                ctx.shape_defined(|ctx, symbol| dims_of(ctx, stored, symbol).map_err(|e| e.0))
            {
                for i in (0..n).filter(|i| context_of[*i] == k && compiled[*i].is_some()) {
                    failures.fail(i, e.clone())?;
                }
            }
        }
        for (i, slot) in compiled.iter_mut().enumerate() {
            if failures.failed(i) {
                continue;
            }
            let Some(claim) = slot.as_mut() else {
                continue;
            };
            let ctx = &contexts[claim.context];
            if let Some(why) = broken_link(&claim.printed, ctx) {
                failures.fail(
                    i,
                    TextError::Claim {
                        claim: claim.label.equation.clone(),
                        message: why,
                    },
                )?;
                continue;
            }
            if let Err(e) = fix_shapes(claim, ctx, &samples[claim.context]) {
                failures.fail(i, e)?;
            }
        }
        let mut claims = Vec::new();
        let mut unread = Vec::new();
        for (i, spec) in file.claims.iter().enumerate() {
            match (failures.errors[i].take(), compiled[i].take()) {
                (None, Some(claim)) => claims.push(claim),
                (error, _) => unread.push(Unread {
                    index: i,
                    id: spec.id.clone(),
                    line: located[i].as_ref().map(|p| p.line),
                    quote: located[i].as_ref().map(|p| p.quote.clone()),
                    error: error.unwrap_or_else(|| TextError::Claim {
                        claim: spec.id.clone(),
                        message: "it could not be read".into(),
                    }),
                    expected: spec.expected.clone().unwrap_or_else(|| "correct".into()),
                }),
            }
        }
        // A claim expected unread that was read is reported as read: its
        // verdict is then unexpected.
        Ok(TextAudit {
            document: name.to_string(),
            contexts,
            claims,
            unread,
        })
    }

    /// The claims that could not be read, with why.
    pub fn unread(&self) -> &[Unread] {
        &self.unread
    }
}

/// The names the evaluation bars of a located claim bind that its scope
/// does not define, with the last value each is given (`A = e^0 D = D`
/// defines `A` as `D`); bindings to zero are the bar's point, not a
/// definition.
fn bar_definitions(
    place: &claims::Located,
    ctx: &Context,
    claim: usize,
) -> std::collections::BTreeMap<String, toml::Value> {
    let mut out = std::collections::BTreeMap::new();
    for side in place.lhs.iter().chain(std::iter::once(&place.rhs)) {
        for (_, node) in super::tree::nodes(side) {
            let doc_latex::ast::Expr::At { at, .. } = node else {
                continue;
            };
            for (name, values) in super::lower::evaluation_bindings(at).unwrap_or_default() {
                let key = name.to_string();
                let value = values.last().expect("a binding has a value");
                if ctx.lookup(Some(claim), &key).is_none()
                    && super::lower::number(value) != Some(0.0)
                {
                    out.entry(key)
                        .or_insert_with(|| toml::Value::String(value.to_string()));
                }
            }
        }
    }
    out
}

/// A chain rule's links must be claims that were read and whose printed
/// formulas are not chain rules themselves (one level is followed).
fn check_links(compiled: &[Option<TextClaim>], failures: &mut Failures) -> Result<(), TextError> {
    for (i, c) in compiled.iter().enumerate() {
        let Some(c) = c else { continue };
        for k in c.printed.links() {
            let message = match &compiled[k] {
                Some(link) if !link.printed.links().is_empty() => format!(
                    "its link {} is itself a chain rule (one level is followed)",
                    link.label.equation
                ),
                Some(_) if !failures.failed(k) => continue,
                _ => "one of its chain-rule links could not be read".to_string(),
            };
            failures.fail(
                i,
                TextError::Claim {
                    claim: c.label.equation.clone(),
                    message,
                },
            )?;
        }
    }
    Ok(())
}

/// Why a link stated in words that `printed` uses cannot be evaluated.
fn broken_link(printed: &super::term::Term, ctx: &Context) -> Option<String> {
    let mut stack = vec![printed];
    while let Some(t) = stack.pop() {
        if let super::term::Term::TruthLink(k) = t
            && let Some(why) = &ctx.truth_links[*k].broken
        {
            return Some(format!(
                "its link `{}` (stated in words) cannot be evaluated: {why}",
                ctx.truth_links[*k].key
            ));
        }
        stack.extend(t.children());
    }
    None
}

/// Sizes what a sample tells about a claim (its defined variables and its
/// map's value), and checks its map depends on its variable.
fn fix_shapes(claim: &mut TextClaim, ctx: &Context, stored: &[f64]) -> Result<(), TextError> {
    let id = claim.label.equation.clone();
    let error = |m: String| TextError::Claim {
        claim: id.clone(),
        message: m,
    };
    fn fix(
        v: &mut Variable,
        ctx: &Context,
        stored: &[f64],
        error: &dyn Fn(String) -> TextError,
    ) -> Result<(), TextError> {
        match v {
            Variable::Defined { symbol, shape, .. } => {
                *shape = shape_of(ctx, stored, *symbol).map_err(|e| error(e.0))?;
            }
            Variable::Update { symbol, dim, .. } => {
                *dim = dims_of(ctx, stored, *symbol).map_err(|e| error(e.0))?.1;
            }
            Variable::Joint(parts) => {
                for part in parts {
                    fix(part, ctx, stored, error)?;
                }
            }
            Variable::Stored { .. } => {}
        }
        Ok(())
    }
    for v in std::iter::once(&mut claim.variable)
        .chain(claim.conventions.iter_mut().map(|c| &mut c.variable))
        .flatten()
    {
        fix(v, ctx, stored, &error)?;
    }
    let mut value = TextDerivation::new(claim, ctx, stored.to_vec())
        .map_value()
        .map_err(|e| error(format!("its map cannot be evaluated: {e}")))?;
    if value.iter().any(|x| !x.is_finite())
        && claim.variable.as_ref().is_some_and(Variable::at_zero)
    {
        // A removable singularity at zero (`k̂ sin(θ/2)`): next to it.
        claim.near_zero = true;
        value = TextDerivation::new(claim, ctx, stored.to_vec())
            .map_value()
            .map_err(|e| error(format!("its map cannot be evaluated: {e}")))?;
        claim.notes.push(format!(
            "the map is not finite at zero (a removable singularity): compared at {:e} from it",
            super::eval::NEAR_ZERO
        ));
    }
    if value.iter().any(|x| !x.is_finite()) {
        return Err(error("its map is not finite at a sample".into()));
    }
    // A Jacobian of a homogeneous transformation moves its top 3 × 4 (a
    // differential is printed as the whole matrix).
    claim.value_shape = match claim.kind {
        super::symbols::ClaimKind::Jacobian => super::value::moving_entries(&value).1,
        _ => value.shape(),
    };
    if claim.variable.is_some() && claim.kind != super::symbols::ClaimKind::Value {
        independent_of_variable(claim, ctx).map_err(error)?;
    }
    Ok(())
}

/// An error when the claim's map does not depend on its variable (its
/// Jacobian is zero at every one of a few samples) while the printed
/// formula is not zero: a modelling mistake of the symbols file, not a
/// verdict on the document.
fn independent_of_variable(claim: &TextClaim, ctx: &Context) -> Result<(), String> {
    let mut sampler = Sampler::new(super::TextAudit::seed(claim.index));
    for _ in 0..3 {
        let d = TextDerivation::new(claim, ctx, ctx.sample(&mut sampler));
        if truth(&d).iter().any(|x| *x != 0.0) {
            return Ok(());
        }
        match d.printed() {
            Printed::Evaluated(p) if p.iter().any(|x| *x != 0.0) => {}
            _ => return Ok(()),
        }
    }
    Err(format!(
        "its map does not depend on `{}` (the Jacobian is zero at every sample): the symbols \
         file defines the map without the variable, or the variable as something the map does \
         not use",
        claim.wrt_text
    ))
}

/// The shape of symbol `symbol`'s value at the sample `stored`, and the
/// dimension of its tangent (a rotation's is 3, a matrix's its size).
fn dims_of(
    ctx: &Context,
    stored: &[f64],
    symbol: usize,
) -> Result<((usize, usize), usize), ShapeError> {
    let value = value_of(ctx, stored, symbol)?;
    let dim = match &value {
        super::value::Value::Rotation(_) => Some(3),
        super::value::Value::Pose(_) => Some(6),
        super::value::Value::Similarity(_) => Some(7),
        _ => None,
    };
    let shape = perturbed_shape(value)?;
    Ok((shape, dim.unwrap_or(shape.0 * shape.1)))
}

/// The shape of what perturbs symbol `symbol`'s value additively at the
/// sample `stored`.
fn shape_of(ctx: &Context, stored: &[f64], symbol: usize) -> Result<(usize, usize), ShapeError> {
    perturbed_shape(value_of(ctx, stored, symbol)?)
}

/// The entries of a value a derivative by it moves: all of a matrix's, but
/// the fixed last row `[0 0 0 1]` of a homogeneous transformation (its top
/// 3 × 4, column by column, as `vec` of a pose's matrix is taken).
fn perturbed_shape(value: super::value::Value<f64>) -> Result<(usize, usize), ShapeError> {
    let m = value.matrix()?;
    let homogeneous =
        m.shape() == (4, 4) && (0..4).all(|c| m[(3, c)] == if c == 3 { 1.0 } else { 0.0 });
    Ok(if homogeneous { (3, 4) } else { m.shape() })
}

/// Symbol `symbol`'s value at the sample `stored`.
fn value_of(
    ctx: &Context,
    stored: &[f64],
    symbol: usize,
) -> Result<super::value::Value<f64>, ShapeError> {
    if matches!(ctx.table.entries[symbol].meaning, Meaning::Tangent { .. }) {
        return Err(ShapeError("a tangent has no value".into()));
    }
    let space = Space {
        table: &ctx.table,
        printed: &ctx.printed,
        factor: ctx.factor,
        templates: &ctx.templates,
    };
    let mut env = Env::new(space, stored.to_vec());
    env.symbol(symbol)
}
