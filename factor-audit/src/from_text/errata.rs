//! The erratum search: small symbolic edits of the printed formula, the
//! smallest that makes it agree with the truth at every sample.
//!
//! The edit space (each edit changes the printed syntax tree, which is
//! lowered and evaluated again):
//! - the sign of a term of a sum, of a matrix entry or of the whole;
//! - an exponent `e` (of a power, or a number written as a symbol's
//!   superscript read as a power) to `e + 1`, `e − 1`, `2e`, `e/2` or `−e`
//!   (so `3/2 ↔ 3`);
//! - a factor of a product transposed (or its transpose removed), the whole
//!   transposed;
//! - two entries of a matrix's row or column swapped; an entry replaced by
//!   `0`; a matrix's row or column deleted;
//! - a term of a sum or a factor of a product deleted;
//! - a symbol replaced by a sibling in scope (the same letter with another
//!   subscript, superscript, accent, font or primes: `ω̂ → ω`, `l¹ → l²`);
//! - a term, an entry or the whole multiplied by 2 or ½;
//! - a symbol or application inverted (or its inverse undone);
//! - a misplaced parenthesis, `(a − b c)` read as `(a − b) c`;
//! - (when no single edit fits) a missing term: a term printed elsewhere in
//!   the formula's display (another side of its chain, another line, a sum
//!   inside it) added to the whole, to a sum, before a lone subtracted
//!   term, or to a matrix entry.
//!
//! An exponent corrected to 1 is dropped (`x^2` to `x`). A differential is
//! searched as its claim reads it (linear in its tangent).
//!
//! Single edits are tried first, then missing terms, then pairs (two edits at places not inside
//! one another), at most [`MAX_CANDIDATES`] edited formulas an equation (and
//! [`MAX_CANDIDATES_PER_RUN`] in a whole audit), each evaluated at up to
//! [`SEARCH_SAMPLES`] of the audit's samples (stopping at the first that
//! disagrees); formulas of more than [`MAX_SEARCHED_NODES`] nodes are not
//! searched. A formula that agrees there is confirmed at
//! every sample of the audit. The targets are the truth, then the truths
//! under the claim's conventions and with the tangent's halves swapped (a
//! fix that makes the formula right only under one of those says so). When
//! no edit within the bound fixes the whole formula, the single edit that
//! makes the most columns agree (more than as printed) is reported as a
//! partial diagnosis, with the columns still wrong.

use doc_latex::ast::Expr;
use nalgebra::DMatrix;

use super::TextAudit;
use super::claims::{TextClaim, TextDerivation};
use super::context::{Context, FrozenResolver};
use super::edits::{Edit, additions, candidates};
use super::lower::Lowering;
use super::symbols::ClaimKind;
use super::term::Term;
use super::tree::nodes;
use crate::derivation::{Derivation, Printed, truth};
use crate::verdict::TOLERANCE;
use factor_core::factor::relative_frobenius_error;
use factor_testing::samples::Sampler;

/// Most edited formulas evaluated per equation (singles and pairs).
pub const MAX_CANDIDATES: usize = 20_000;
/// Most edited formulas evaluated in one audit, all equations together.
pub const MAX_CANDIDATES_PER_RUN: usize = 100_000;
/// Largest printed formula searched, in syntax-tree nodes.
pub const MAX_SEARCHED_NODES: usize = 400;
/// Samples an edited formula is evaluated at during the search.
pub const SEARCH_SAMPLES: usize = 6;
/// Most alternative fixes reported.
pub const MAX_FIXES_SHOWN: usize = 3;

/// A target an edited formula may agree with: the truth, or an alternative.
struct Target {
    /// `None` for the truth, else what the alternative is.
    name: Option<String>,
    /// Its matrix at each search sample.
    at: Vec<DMatrix<f64>>,
}

fn agree(a: &DMatrix<f64>, b: &DMatrix<f64>) -> bool {
    a.shape() == b.shape() && relative_frobenius_error(a, b, 1e-9) <= TOLERANCE
}

/// The truth and the alternatives at the samples of `derivations`.
fn targets(claim: &TextClaim, derivations: &[TextDerivation<'_>]) -> Vec<Target> {
    let truths: Vec<DMatrix<f64>> = derivations.iter().map(truth).collect();
    let mut out = vec![Target {
        name: None,
        at: truths.clone(),
    }];
    for (k, c) in claim.conventions.iter().enumerate() {
        out.push(Target {
            name: Some(c.description.clone()),
            at: derivations
                .iter()
                .map(|d| d.conventions().swap_remove(k).1)
                .collect(),
        });
    }
    let n = truths[0].ncols();
    if claim.kind != ClaimKind::Value && n >= 2 && n.is_multiple_of(2) {
        out.push(Target {
            name: Some(
                "with the two halves of the tangent swapped (e.g. [δρ, δω] instead of [δω, δρ])"
                    .into(),
            ),
            at: truths
                .iter()
                .map(|t| DMatrix::from_fn(t.nrows(), n, |r, c| t[(r, (c + n / 2) % n)]))
                .collect(),
        });
    }
    out
}

/// The suspected erratum of a claim.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnosis {
    /// In words: the edits, what they make right, and what stays wrong.
    pub words: String,
    /// The printed formula with the edits, as LaTeX (`lhs = rhs'`).
    pub corrected: String,
    /// Whether the edited formula agrees everywhere (else it is partial).
    pub complete: bool,
    /// How many edits it makes.
    pub edits: usize,
}

/// What a search found, and how many edited formulas it evaluated.
#[derive(Debug, Clone, PartialEq)]
pub struct Searched {
    /// The diagnosis, if an edit within the bound fixes (part of) it.
    pub diagnosis: Option<Diagnosis>,
    /// Edited formulas evaluated (at most the budget given).
    pub evaluated: usize,
}

/// One search: the formula, its samples and its targets.
struct Search<'a> {
    claim: &'a TextClaim,
    ctx: &'a Context,
    root: Expr,
    derivations: Vec<TextDerivation<'a>>,
    targets: Vec<Target>,
    evaluated: usize,
    budget: usize,
}

/// What an edited formula does.
enum Outcome {
    /// It cannot be evaluated (or the edit does not apply).
    Invalid,
    /// It agrees with these targets (indices) at every search sample.
    Agrees(Vec<usize>),
    /// It agrees with no target; these columns of the truth (when counted)
    /// agree at every search sample.
    Columns(Vec<usize>),
}

/// Whether column `c` of `p` is right: within the tolerance of the whole
/// truth's norm, as the verdict engine measures columns.
fn column_agrees(p: &DMatrix<f64>, t: &DMatrix<f64>, c: usize) -> bool {
    p.shape() == t.shape() && (p.column(c) - t.column(c)).norm() <= TOLERANCE * t.norm().max(1e-9)
}

/// `e`, an edit or another reading of `claim`'s printed right side,
/// lowered as the printed one was (a differential linear in its tangent).
pub fn lower_variant(claim: &TextClaim, ctx: &Context, e: &Expr) -> Option<Term> {
    let mut resolver = FrozenResolver {
        ctx,
        scope: claim.scope(),
    };
    let term = Lowering::new(&mut resolver, claim.stacked_fractions)
        .expr(e)
        .ok()?;
    Some(match claim.differential_in {
        Some(tangent) => Term::Quotient {
            numerator: Box::new(term),
            tangent,
            limit: false,
        },
        None => term,
    })
}

/// Whether `term`, a variant of `claim`'s printed right side, agrees with
/// target `target` (0 the truth, then the claim's conventions, then the
/// tangent's halves swapped) at every one of the audit's `samples` samples.
pub fn confirmed(
    claim: &TextClaim,
    ctx: &Context,
    term: &Term,
    target: usize,
    samples: usize,
) -> bool {
    let mut sampler = Sampler::new(TextAudit::seed(claim.index));
    (0..samples).all(|_| {
        let d = TextDerivation::new(claim, ctx, ctx.sample(&mut sampler));
        let Printed::Evaluated(p) = d.printed_term(term) else {
            return false;
        };
        if d.gap_at_point(term).is_some() {
            return false;
        }
        let t = truth(&d);
        let conventions = claim.conventions.len();
        let t = match target {
            0 => t,
            k if k <= conventions => d.conventions().swap_remove(k - 1).1,
            _ => {
                let n = t.ncols();
                DMatrix::from_fn(t.nrows(), n, |r, c| t[(r, (c + n / 2) % n)])
            }
        };
        agree(&p, &t)
    })
}

impl Search<'_> {
    fn lower(&self, e: &Expr) -> Option<Term> {
        lower_variant(self.claim, self.ctx, e)
    }

    /// Applies `edits` (the later places first, so earlier ones keep their
    /// paths) and scores the result.
    fn try_edits(&mut self, edits: &[&Edit], columns: bool) -> (Outcome, Option<Expr>) {
        let mut e = self.root.clone();
        let mut ordered: Vec<&&Edit> = edits.iter().collect();
        ordered.sort_by_key(|edit| std::cmp::Reverse(edit.site()));
        if !ordered.iter().all(|edit| edit.apply(&mut e)) {
            return (Outcome::Invalid, None);
        }
        self.evaluated += 1;
        let Some(term) = self.lower(&e) else {
            return (Outcome::Invalid, None);
        };
        (self.score(&term, columns), Some(e))
    }

    /// How `term` fares against the targets at the search samples.
    fn score(&self, term: &Term, columns: bool) -> Outcome {
        let mut alive: Vec<usize> = (0..self.targets.len()).collect();
        let mut good: Vec<usize> = if columns {
            (0..self.targets[0].at[0].ncols()).collect()
        } else {
            Vec::new()
        };
        for (k, d) in self.derivations.iter().enumerate() {
            let Printed::Evaluated(p) = d.printed_term(term) else {
                return Outcome::Invalid;
            };
            alive.retain(|t| agree(&p, &self.targets[*t].at[k]));
            good.retain(|c| column_agrees(&p, &self.targets[0].at[k], *c));
            if alive.is_empty() && good.is_empty() {
                return Outcome::Columns(Vec::new());
            }
        }
        if alive.is_empty() {
            Outcome::Columns(good)
        } else {
            Outcome::Agrees(alive)
        }
    }

    /// Whether `edited` agrees with target `target` at every one of the
    /// audit's `samples` samples.
    fn confirm(&self, edited: &Expr, target: usize, samples: usize) -> bool {
        self.lower(edited)
            .is_some_and(|term| confirmed(self.claim, self.ctx, &term, target, samples))
    }
}

/// `1, 2 and 3` for column indices (0-based in, 1-based out).
fn list(columns: &[usize]) -> String {
    let names: Vec<String> = columns.iter().map(|c| (c + 1).to_string()).collect();
    match names.as_slice() {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// Searches the edits of `claim`'s printed formula (see the module
/// documentation), evaluating at most `budget` edited formulas; `samples`
/// is the audit's sample count, at which a fix is confirmed.
pub fn search(audit: &TextAudit, claim: &TextClaim, samples: usize, budget: usize) -> Searched {
    if nodes(&claim.printed_ast).len() > MAX_SEARCHED_NODES {
        return Searched {
            diagnosis: None,
            evaluated: 0,
        };
    }
    let ctx = &audit.contexts[claim.context];
    let mut sampler = Sampler::new(TextAudit::seed(claim.index));
    let derivations: Vec<TextDerivation<'_>> = (0..samples.clamp(1, SEARCH_SAMPLES))
        .map(|_| TextDerivation::new(claim, ctx, ctx.sample(&mut sampler)))
        .collect();
    let targets = targets(claim, &derivations);
    let mut s = Search {
        claim,
        ctx,
        root: claim.printed_ast.clone(),
        derivations,
        targets,
        evaluated: 0,
        budget: budget.min(MAX_CANDIDATES),
    };
    let printed_good = match s.score(&claim.printed, true) {
        Outcome::Columns(good) => good.len(),
        _ => 0,
    };
    let singles = candidates(&s.root, ctx, claim);
    let diagnosis = diagnose(&mut s, &singles, printed_good, samples);
    Searched {
        diagnosis,
        evaluated: s.evaluated,
    }
}

/// Singles, then pairs, then the best partial fix.
fn diagnose(
    s: &mut Search<'_>,
    singles: &[Edit],
    printed_good: usize,
    samples: usize,
) -> Option<Diagnosis> {
    let claim = s.claim;
    let mut fixes: Vec<(Vec<&Edit>, usize, Expr)> = Vec::new();
    let mut best: Option<(Vec<usize>, &Edit, Expr)> = None;
    for edit in singles {
        if s.evaluated >= s.budget {
            break;
        }
        match s.try_edits(&[edit], true) {
            (Outcome::Agrees(t), Some(e)) => fixes.push((vec![edit], t[0], e)),
            (Outcome::Columns(good), Some(e))
                if good.len() > printed_good
                    && best.as_ref().is_none_or(|(b, ..)| good.len() > b.len()) =>
            {
                best = Some((good, edit, e));
            }
            _ => {}
        }
    }
    // A term missing: one printed elsewhere on the line, added.
    let added = if fixes.is_empty() {
        additions(&s.root, &claim.nearby_terms)
    } else {
        Vec::new()
    };
    if fixes.is_empty() {
        for edit in &added {
            if s.evaluated >= s.budget {
                break;
            }
            if let (Outcome::Agrees(t), Some(e)) = s.try_edits(&[edit], false) {
                fixes.push((vec![edit], t[0], e));
            }
        }
    }
    if fixes.is_empty() {
        'pairs: for (i, a) in singles.iter().enumerate() {
            for b in &singles[i + 1..] {
                if s.evaluated >= s.budget {
                    break 'pairs;
                }
                let (sa, sb) = (a.site(), b.site());
                if sa.starts_with(&sb) || sb.starts_with(&sa) {
                    continue;
                }
                if let (Outcome::Agrees(t), Some(e)) = s.try_edits(&[a, b], false) {
                    fixes.push((vec![a, b], t[0], e));
                    if fixes.len() >= MAX_FIXES_SHOWN {
                        break 'pairs;
                    }
                }
            }
        }
    }
    // The fewest edits, the truth before the alternatives; confirmed at
    // every sample of the audit.
    fixes.sort_by_key(|(edits, target, _)| (edits.len(), *target));
    // Edits that print the same formula (deleting one of two equal rows)
    // are one fix.
    let mut seen: Vec<&Expr> = Vec::new();
    let confirmed: Vec<&(Vec<&Edit>, usize, Expr)> = fixes
        .iter()
        .filter(|(_, _, e)| {
            let new = !seen.contains(&e);
            seen.push(e);
            new
        })
        .filter(|(_, target, e)| s.confirm(e, *target, samples))
        .take(MAX_FIXES_SHOWN)
        .collect();
    let root = &s.root;
    if let Some((edits, _, edited)) = confirmed.first() {
        let said: Vec<String> = confirmed
            .iter()
            .map(|(edits, target, _)| {
                let mut words: Vec<String> = edits.iter().map(|e| e.describe(root)).collect();
                if let Some(name) = &s.targets[*target].name {
                    words.push(format!("then it is right {name}"));
                }
                words.join(", and ")
            })
            .collect();
        return Some(Diagnosis {
            words: said.join("; or "),
            corrected: claim.with_rhs(edited),
            complete: true,
            edits: edits.len(),
        });
    }
    let (good, edit, edited) = best?;
    let columns = s.targets[0].at[0].ncols();
    let wrong: Vec<usize> = (0..columns).filter(|c| !good.contains(c)).collect();
    let plural = |v: &[usize]| if v.len() > 1 { "s" } else { "" };
    Some(Diagnosis {
        words: format!(
            "{} (then column{} {} agree{}; column{} {} {} still wrong)",
            edit.describe(root),
            plural(&good),
            list(&good),
            if good.len() > 1 { "" } else { "s" },
            plural(&wrong),
            list(&wrong),
            if wrong.len() > 1 { "are" } else { "is" }
        ),
        corrected: claim.with_rhs(&edited),
        complete: false,
        edits: 1,
    })
}
