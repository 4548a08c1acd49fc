//! Claims: each audited equation located in the document, its printed
//! right side lowered, and what it claims (the map, the variable, the
//! conventions to try); per sample, a [`Derivation`] the verdict engine
//! audits exactly as it audits a transcription.

use doc_latex::ast::{Expr, Rel, Statement};
use doc_latex::{Document, Found, Locator, Vocabulary};
use factor_core::dual::Dual;
use nalgebra::DMatrix;

use super::TextError;
use super::context::{Context, Scope, canonical};
use super::eval::{Env, Space};
use super::lower::{Lowering, short, symbol_key};
use super::symbols::{ClaimKind, ClaimSpec, Side};
use super::term::{Meaning, SymbolId, Term, TruthLink, Variable};
use super::tree::derivatives;
use super::value::{ShapeError, Value, shape_text};
use crate::derivation::{Claim, Derivation, Label, Printed, dual_jacobian};
use factor_core::manifold::Perturbation;
use factor_core::scalar::Scalar;

/// The verdict keywords a claim may expect.
pub const KEYWORDS: [&str; 6] = [
    "correct",
    "convention",
    "wrong",
    "malformed",
    "ambiguous",
    "unread",
];

/// A convention to try, lowered.
#[derive(Debug, Clone)]
pub struct Convention {
    /// What it is, in words.
    pub description: String,
    /// The map under it.
    pub of: Term,
    /// The variable under it.
    pub variable: Option<Variable>,
}

/// One audited claim, ready to sample.
#[derive(Debug, Clone)]
pub struct TextClaim {
    /// Its index among the file's claims.
    pub index: usize,
    /// Its context's index.
    pub context: usize,
    /// The report's label.
    pub label: Label,
    /// What it claims.
    pub kind: ClaimKind,
    /// The map.
    pub of: Term,
    /// The variable (none for a value claim).
    pub variable: Option<Variable>,
    /// The variable as written (for messages).
    pub wrt_text: String,
    /// The local coordinates a group-valued map is read in.
    pub output: Option<Perturbation>,
    /// The printed right side, lowered.
    pub printed: Term,
    /// The printed right side as parsed.
    pub printed_ast: Expr,
    /// The printed left side, when there is one.
    pub lhs: Option<Expr>,
    /// The relation between them.
    pub relation: Rel,
    /// The document line it starts on.
    pub line: usize,
    /// The line as printed.
    pub quote: String,
    /// Conventions to try.
    pub conventions: Vec<Convention>,
    /// The shape of the map's value.
    pub value_shape: (usize, usize),
    /// The verdict the gate expects.
    pub expected: String,
    /// The claims its chain rule combines (by index), if it is one.
    pub links: Vec<usize>,
    /// Fractions over non-scalars read as stacks.
    pub stacked_fractions: bool,
    /// The terms printed elsewhere on its line (other sides of its chain):
    /// what the erratum search may add as a missing term.
    pub nearby_terms: Vec<Expr>,
    /// For a differential, the tangent its printed right side is linear
    /// in (the printed term is the difference quotient over it).
    pub differential_in: Option<SymbolId>,
    /// The printed formula as it is evaluated, every grouping explicit
    /// ([`super::understood`]): `lhs rel rhs`.
    pub understood: String,
    /// What a reader should know of how it was read.
    pub notes: Vec<String>,
    /// The other arguments its partial derivative holds (`holding`).
    pub holding: Vec<SymbolId>,
    /// Its map is not finite where its variable is expanded about zero (a
    /// removable singularity): it is compared at [`super::eval::NEAR_ZERO`].
    pub near_zero: bool,
}

impl TextClaim {
    /// The claim's scope in its context.
    pub fn scope(&self) -> Scope {
        Some(self.index)
    }

    /// `lhs rel rhs` with another right side.
    pub fn with_rhs(&self, rhs: &Expr) -> String {
        Statement {
            implied: false,
            head: self.lhs.clone(),
            steps: vec![(self.relation, rhs.clone())],
        }
        .to_string()
    }
}

/// A claim located in the document: its line, as printed and parsed.
#[derive(Debug, Clone)]
pub struct Located {
    /// The document line.
    pub line: usize,
    /// The printed line.
    pub quote: String,
    /// The parsed statement.
    pub statement: Statement,
    /// The chain's left side.
    pub lhs: Option<Expr>,
    /// The right side audited.
    pub rhs: Expr,
    /// The relation before it.
    pub relation: Rel,
    /// Every side of every line of its display (what a missing term may
    /// be found in).
    pub display: Vec<Expr>,
}

fn claim_error(spec: &ClaimSpec, message: impl Into<String>) -> TextError {
    TextError::Claim {
        claim: spec.id.clone(),
        message: message.into(),
    }
}

/// The line of a display a `\label` at byte `at` is printed in: the line
/// it falls in, else the one after the gap it is in when a row break
/// (`separates(from, to)`: the gap's text holds `\\`) comes before it
/// there, else the one before.
fn labelled_row(
    lines: &[doc_latex::Claim],
    at: usize,
    separates: impl Fn(usize, usize) -> bool,
) -> usize {
    let after = lines.iter().position(|c| c.span.start > at);
    match after {
        None => lines.len() - 1,
        Some(0) => 0,
        Some(next) => {
            let before = &lines[next - 1].span;
            if at < before.end || !separates(before.end, at) {
                next - 1
            } else {
                next
            }
        }
    }
}

/// Finds a claim's line in the document (by label, anchor or `after`, a
/// line of a formula, a statement of the line, the end of a chain, a case
/// of a `cases`). An anchor found only in the prose is an error naming its
/// line: the display after it is audited only when the file says `after`.
pub fn locate(doc: &Document, spec: &ClaimSpec) -> Result<Located, TextError> {
    let lookup = |e: doc_latex::LookupError| claim_error(spec, e.to_string());
    let pick = |claims: Vec<doc_latex::Claim>| -> Result<doc_latex::Claim, TextError> {
        let n = claims.len();
        match spec.line {
            None if n == 1 => Ok(claims.into_iter().next().expect("one claim")),
            None => Err(claim_error(
                spec,
                format!("the formula has {n} lines: say which with `line`"),
            )),
            Some(l) => claims.into_iter().nth(l.wrapping_sub(1)).ok_or_else(|| {
                claim_error(spec, format!("the formula has {n} line(s), not a line {l}"))
            }),
        }
    };
    let given = [&spec.label, &spec.anchor, &spec.after]
        .iter()
        .filter(|x| x.is_some())
        .count();
    if given != 1 {
        return Err(claim_error(
            spec,
            "give one of `label`, `anchor` and `after`",
        ));
    }
    if spec.chain && spec.line.is_some() {
        return Err(claim_error(
            spec,
            "`chain` follows the chain from the located line to its end: it goes without `line` \
             (quote the line's own LaTeX in `anchor`)",
        ));
    }
    let region = doc
        .region(spec.section.as_deref(), spec.occurrence)
        .map_err(lookup)?;
    let claim = if let Some(after) = &spec.after {
        let formula = match doc.locate_in(&region, after).map_err(lookup)? {
            Found::Prose { after, .. } => after,
            Found::Formula(f) => {
                return Err(claim_error(
                    spec,
                    format!(
                        "`after` quotes the formula on line {} itself: use `anchor`",
                        f.line
                    ),
                ));
            }
        };
        if spec.chain {
            return Err(claim_error(
                spec,
                "`chain` goes with `label` or `anchor`, not `after`",
            ));
        }
        pick(
            doc.claims(formula)
                .map_err(|e| claim_error(spec, e.to_string()))?,
        )?
    } else {
        let locator = match (&spec.label, &spec.anchor) {
            (Some(l), None) => Locator::Label(l),
            (None, Some(a)) => Locator::Anchor(a),
            _ => unreachable!("one locator"),
        };
        if let Locator::Anchor(a) = locator {
            // An anchor must be in a formula: never another display silently.
            if let Found::Prose { line, .. } = doc.locate_in(&region, a).map_err(lookup)? {
                return Err(lookup(doc_latex::LookupError::AnchorInProse {
                    anchor: short(a),
                    line,
                }));
            }
        }
        if spec.chain {
            doc.chain_in(&region, locator)
                .map_err(lookup)?
                .pop()
                .ok_or_else(|| claim_error(spec, "the chain is empty"))?
        } else if let (Locator::Anchor(a), None) = (locator, spec.line) {
            doc.claim_in_formulas_of(&region, a).map_err(lookup)?
        } else {
            let formula = doc.find_in(&region, locator).map_err(lookup)?;
            let lines = doc
                .claims(formula)
                .map_err(|e| claim_error(spec, e.to_string()))?;
            match (&spec.label, spec.line) {
                // A `\label` printed on one line of a display names that
                // line: the row it is printed in, between the `\\`s.
                (Some(name), None) if lines.len() > 1 => {
                    let marker = format!("\\label{{{name}}}");
                    match formula.source.find(&marker) {
                        Some(at) => {
                            let base = formula.span.start;
                            let row = labelled_row(&lines, at + base, |from, to| {
                                formula.source[from - base..to - base].contains("\\\\")
                            });
                            lines[row].clone()
                        }
                        None => pick(lines)?,
                    }
                }
                _ => pick(lines)?,
            }
        }
    };
    let statement = match spec.statement {
        None | Some(1) => claim.statement.clone().map_err(TextError::Parse)?,
        Some(k) => claim
            .notes
            .get(k.wrapping_sub(2))
            .cloned()
            .ok_or_else(|| {
                claim_error(
                    spec,
                    format!(
                        "the line has {} statement(s), not a statement {k}",
                        claim.notes.len() + 1
                    ),
                )
            })?
            .map_err(TextError::Parse)?,
    };
    let mut lhs = match spec.statement {
        Some(k) if k > 1 => statement.head.clone(),
        _ => claim.lhs.clone(),
    };
    let (relation, rhs) = match spec.step {
        // A display that is only a value (`[a^{-1} I_3, -q a^{-2}]` after
        // "with derivative"), its map named by the file.
        None if spec.of.is_some()
            && statement.steps.is_empty()
            && let Some(head) = &statement.head =>
        {
            lhs = None;
            (Rel::Eq, head.clone())
        }
        None => statement
            .steps
            .iter()
            .rev()
            .find(|(r, _)| !r.is_membership())
            .cloned()
            .ok_or_else(|| claim_error(spec, "the line states no relation"))?,
        Some(k) => statement
            .steps
            .iter()
            .filter(|(r, _)| !r.is_membership())
            .nth(k.wrapping_sub(1))
            .cloned()
            .ok_or_else(|| {
                claim_error(
                    spec,
                    format!(
                        "the line has {} right side(s), not a step {k}",
                        statement
                            .steps
                            .iter()
                            .filter(|(r, _)| !r.is_membership())
                            .count()
                    ),
                )
            })?,
    };
    let rhs = match (spec.case, rhs) {
        (None, Expr::Cases(_)) => {
            return Err(claim_error(
                spec,
                "the right side is a `cases`: say which with `case`",
            ));
        }
        (None, rhs) => rhs,
        (Some(k), Expr::Cases(cases)) => cases
            .get(k.wrapping_sub(1))
            .map(|c| c.value.clone())
            .ok_or_else(|| claim_error(spec, format!("there is no case {k}")))?,
        (Some(_), _) => {
            return Err(claim_error(
                spec,
                "`case` is given but the right side has none",
            ));
        }
    };
    let display = doc
        .formulas()
        .iter()
        .find(|f| f.span.start <= claim.span.start && claim.span.end <= f.span.end)
        .and_then(|f| doc.claims(f).ok())
        .map(|lines| {
            lines
                .iter()
                .flat_map(|c| c.statement.iter().chain(c.notes.iter().flatten()))
                .flat_map(|st| {
                    st.head
                        .iter()
                        .cloned()
                        .chain(st.steps.iter().map(|(_, e)| e.clone()))
                })
                .collect()
        })
        .unwrap_or_default();
    Ok(Located {
        line: claim.line,
        quote: claim.source.trim().to_string(),
        lhs,
        statement,
        rhs,
        relation,
        display,
    })
}

/// The chain-rule links of a located claim: the derivatives written on
/// its line that are claims of the same context.
pub fn links(located: &Located, ctx: &Context, own: usize) -> Vec<usize> {
    let mut out = Vec::new();
    for (_, step) in &located.statement.steps {
        for d in derivatives(step) {
            if let Some(k) = ctx.links.get(&d.to_string())
                && *k != own
                && !out.contains(k)
            {
                out.push(*k);
            }
        }
    }
    out
}

/// Lowers LaTeX written in the symbols file for a claim.
fn lower_written(
    ctx: &mut Context,
    scope: Scope,
    spec: &ClaimSpec,
    what: &str,
    latex: &str,
) -> Result<(Expr, Term), TextError> {
    let e = doc_latex::parse_expr_with(latex, &ctx.vocabulary).map_err(|e| {
        claim_error(
            spec,
            format!(
                "cannot read `{what}` = `{latex}`: {} at `{}`",
                e.kind, e.fragment
            ),
        )
    })?;
    let t = Lowering::new(&mut ctx.resolver(scope), false)
        .expr(&e)
        .map_err(|err| claim_error(spec, format!("`{what}`: {err}")))?;
    Ok((e, t))
}

/// Compiles a located claim in its context.
pub fn compile(
    ctx: &mut Context,
    context_index: usize,
    index: usize,
    spec: &ClaimSpec,
    located: Located,
    document: &str,
) -> Result<TextClaim, TextError> {
    let scope = Some(index);
    let size = super::tree::nodes(&located.rhs).len();
    if size > super::MAX_FORMULA_NODES {
        return Err(claim_error(
            spec,
            format!(
                "the formula has {size} nodes; at most {} are audited",
                super::MAX_FORMULA_NODES
            ),
        ));
    }
    let (printed, notes) = {
        let mut resolver = ctx.resolver(scope);
        let mut lowering = Lowering::new(&mut resolver, spec.stacked_fractions);
        let printed = lowering
            .formula(&located.rhs)
            .map_err(|error| TextError::Formula {
                claim: spec.id.clone(),
                line: located.line,
                error,
            })?;
        (printed, lowering.notes)
    };
    // A derivative's printed size (`\left. \frac{∂f}{∂x} \right|_{6×12}`)
    // only annotates it.
    let lhs = match &located.lhs {
        Some(Expr::Shaped { base, .. }) if matches!(base.as_ref(), Expr::Derivative { .. }) => {
            Some(base.as_ref())
        }
        other => other.as_ref(),
    };
    // The left side's derivative, evaluated at zero when a bar says so
    // (`\left. \frac{∂f}{∂ε} \right|_{ε=0}`).
    let (derivative, bar_at_zero) = match lhs {
        Some(Expr::Derivative { of, wrt, .. }) => {
            (Some((of.as_ref().clone(), wrt.as_ref().clone())), false)
        }
        Some(Expr::At { body, at }) => match body.as_ref() {
            Expr::Derivative { of, wrt, .. } => {
                let zero = super::lower::evaluation_bindings(at)
                    .unwrap_or_default()
                    .iter()
                    .any(|(name, values)| {
                        name == wrt.as_ref()
                            && values.iter().any(|v| super::lower::number(v) == Some(0.0))
                    });
                (Some((of.as_ref().clone(), wrt.as_ref().clone())), zero)
            }
            _ => (None, false),
        },
        _ => (None, false),
    };
    // A derivative by an expression no symbol names (`∂(T⁻¹ p)/∂(T⁻¹)`):
    // by a symbol standing for it where the map prints it.
    let derivative = match derivative {
        Some((of, wrt)) if spec.of.is_none() && spec.wrt.is_none() => Some(
            ctx.by_expression(scope, &of, &wrt)
                .map_err(|m| claim_error(spec, m))?
                .unwrap_or((of, wrt)),
        ),
        other => other,
    };
    // `≈`, `≃` between values: a first-order claim (BCH for a small angle,
    // a linearised propagation), in the small quantities it prints.
    let approximate = matches!(located.relation, Rel::Approx | Rel::Simeq);
    let kind = spec.kind.unwrap_or(if derivative.is_some() {
        ClaimKind::Jacobian
    } else if approximate {
        ClaimKind::FirstOrder
    } else if spec.wrt.is_some() {
        ClaimKind::Jacobian
    } else {
        ClaimKind::Value
    });
    let vocabulary = ctx.vocabulary.clone();
    let from_lhs = |part: &str| {
        claim_error(
            spec,
            format!("the printed left side is no derivative: give `{part}`"),
        )
    };
    let of = match (&spec.of, &derivative, kind, &located.lhs) {
        (Some(latex), ..) => lower_written(ctx, scope, spec, "of", latex)?.1,
        (None, Some((of, wrt)), _, _) => {
            let mut resolver = ctx.resolver(scope);
            let mut lowering = Lowering::new(&mut resolver, false).without_claim_names();
            // Under a left side's evaluation bar, with its other bindings.
            match &located.lhs {
                Some(Expr::At { at, .. }) => lowering.map_under_bar(of, wrt, at),
                _ => lowering.expr(of),
            }
            .map_err(|e| {
                claim_error(
                    spec,
                    format!("the differentiated `{}`: {e}", short(&of.to_string())),
                )
            })?
        }
        (None, None, ClaimKind::Value | ClaimKind::FirstOrder, Some(lhs)) => {
            Lowering::new(&mut ctx.resolver(scope), false)
                .without_claim_names()
                .expr(lhs)
                .map_err(|e| claim_error(spec, format!("the left side: {e}")))?
        }
        _ => return Err(from_lhs("of")),
    };
    let wrt_ast = match (&spec.wrt, &derivative) {
        (Some(latex), _) => Some(doc_latex::parse_expr_with(latex, &vocabulary).map_err(|e| {
            claim_error(
                spec,
                format!("cannot read `wrt`: {} at `{}`", e.kind, e.fragment),
            )
        })?),
        (None, Some((_, wrt))) => Some(wrt.clone()),
        (None, None) => None,
    };
    let mut wrt_names = None;
    let variable = match (kind, &spec.update) {
        (ClaimKind::Value, _) => None,
        (_, Some(update)) => {
            let wrt = wrt_ast.as_ref().ok_or_else(|| from_lhs("wrt"))?;
            let target = match wrt {
                Expr::Symbol(s) => ctx.lookup(scope, &symbol_key(s)),
                other => ctx.lookup(scope, &other.to_string()),
            }
            .ok_or_else(|| claim_error(spec, "the updated variable is not defined"))?;
            Some(
                ctx.update_variable(scope, target, update)
                    .map_err(|m| claim_error(spec, m))?,
            )
        }
        (_, None) => match &wrt_ast {
            Some(wrt) => Some(
                ctx.variable_of(scope, wrt, spec.side, spec.at_zero || bar_at_zero)
                    .map_err(|m| claim_error(spec, m))?,
            ),
            None if kind == ClaimKind::FirstOrder => {
                let (variable, names) = small_quantities(ctx, scope, &located, spec)?;
                wrt_names = Some(names);
                Some(variable)
            }
            None => return Err(from_lhs("wrt")),
        },
    };
    // The differential `J δ` printed in the tangent `δ`: `J` is the linear
    // map it is in `δ`.
    let mut differential_in = None;
    let printed = match (kind, &wrt_ast) {
        (ClaimKind::Differential, Some(wrt)) => {
            let tangent = match wrt {
                Expr::Symbol(s) => ctx.lookup(scope, &symbol_key(s)),
                _ => None,
            }
            .filter(|id| matches!(ctx.table.entries[*id].meaning, Meaning::Tangent { .. }))
            .ok_or_else(|| {
                claim_error(
                    spec,
                    "a differential is taken by a tangent symbol (`{ perturbs = … }`) printed in it",
                )
            })?;
            differential_in = Some(tangent);
            Term::Quotient {
                numerator: Box::new(printed),
                tangent,
                limit: false,
            }
        }
        _ => printed,
    };
    let output = match spec.output {
        Some(Side::Left) => Some(Perturbation::Left),
        Some(Side::Right) => Some(Perturbation::Right),
        None => match &variable {
            Some(Variable::Stored { kind, side, .. }) if !kind.is_additive() => Some(*side),
            _ => None,
        },
    };
    let mut conventions = Vec::new();
    for c in &spec.conventions {
        let of = match &c.of {
            Some(latex) => lower_written(ctx, scope, spec, "of", latex)?.1,
            None => of.clone(),
        };
        let wrt = match &c.wrt {
            Some(latex) => Some(
                doc_latex::parse_expr_with(latex, &vocabulary)
                    .map_err(|e| claim_error(spec, format!("cannot read `wrt`: {}", e.kind)))?,
            ),
            None => wrt_ast.clone(),
        };
        let variable = match (kind, &c.update, &wrt) {
            (ClaimKind::Value, ..) => None,
            // Another map by the claim's own variable (its update too).
            (_, None, _) if c.wrt.is_none() && c.side.is_none() => variable.clone(),
            (_, Some(update), Some(Expr::Symbol(s))) => {
                let symbol = ctx
                    .lookup(scope, &symbol_key(s))
                    .ok_or_else(|| claim_error(spec, "the updated variable is not defined"))?;
                Some(
                    ctx.update_variable(scope, symbol, update)
                        .map_err(|m| claim_error(spec, m))?,
                )
            }
            (_, Some(_), _) => {
                return Err(claim_error(
                    spec,
                    "an `update` needs `wrt` to be one symbol",
                ));
            }
            (_, None, Some(wrt)) => Some(
                ctx.variable_of(scope, wrt, c.side.or(spec.side), spec.at_zero)
                    .map_err(|m| claim_error(spec, m))?,
            ),
            (_, None, None) => return Err(from_lhs("wrt")),
        };
        conventions.push(Convention {
            description: c.description.clone(),
            of,
            variable,
        });
    }
    let expected = spec.expected.clone().unwrap_or_else(|| "correct".into());
    if !KEYWORDS.contains(&expected.as_str()) {
        return Err(claim_error(
            spec,
            format!("`expected` is one of {}", KEYWORDS.join(", ")),
        ));
    }
    let lhs_text = located
        .lhs
        .as_ref()
        .map_or_else(|| "the printed value".to_string(), |l| l.to_string());
    let convention = spec.convention.clone().unwrap_or_else(|| match &variable {
        Some(Variable::Stored { kind, side, .. }) if !kind.is_additive() => {
            format!("{} perturbation", side.as_str())
        }
        Some(_) => "additive".into(),
        None => "a value".into(),
    });
    let label = Label::new(
        document.to_string(),
        spec.id.clone(),
        spec.claim.clone().unwrap_or(lhs_text),
        convention,
        spec.erratum.as_deref(),
    );
    let understood = understood_line(ctx, located.lhs.as_ref(), located.relation, &printed);
    let mut holding = Vec::with_capacity(spec.holding.len());
    for held in &spec.holding {
        let key = super::context::canonical_symbol(held, &vocabulary)
            .map_err(|m| claim_error(spec, format!("`holding`: {m}")))?;
        holding.push(
            ctx.lookup(scope, &key)
                .ok_or_else(|| claim_error(spec, format!("`holding`: `{held}` is not defined")))?,
        );
    }
    Ok(TextClaim {
        index,
        context: context_index,
        label,
        kind,
        of,
        variable,
        wrt_text: wrt_names
            .or_else(|| wrt_ast.map(|w| short(&w.to_string())))
            .unwrap_or_default(),
        output,
        printed,
        printed_ast: located.rhs.clone(),
        lhs: located.lhs.clone(),
        relation: located.relation,
        line: located.line,
        quote: located.quote.clone(),
        conventions,
        value_shape: (0, 0),
        expected,
        links: Vec::new(),
        stacked_fractions: spec.stacked_fractions,
        nearby_terms: {
            let others: Vec<&Expr> = located
                .display
                .iter()
                .filter(|e| **e != located.rhs)
                .collect();
            super::tree::nearby_terms(&others, &located.rhs)
        },
        differential_in,
        understood,
        notes,
        holding,
        near_zero: false,
    })
}

/// The small quantities a first-order claim expands in, when the file
/// names none (`wrt`): the increments it prints on either side (`\delta
/// \phi`, `\Delta t`, `\delta \tilde{x}_k`) that are values of the
/// context, each expanded about zero; several together are one variable.
fn small_quantities(
    ctx: &mut Context,
    scope: Scope,
    located: &Located,
    spec: &ClaimSpec,
) -> Result<(Variable, String), TextError> {
    let mut keys: Vec<(String, Expr)> = Vec::new();
    for side in located.lhs.iter().chain(std::iter::once(&located.rhs)) {
        for (_, node) in super::tree::nodes(side) {
            if !matches!(node, Expr::Symbol(s) if s.delta.is_some()) {
                continue;
            }
            let key = node.to_string();
            // A free increment: sampled, or a constant (`δφ = 0`); one the
            // file derives from others (`δx_{k+1}`) is what is expanded.
            let free = ctx.lookup(scope, &key).is_some_and(|id| {
                ctx.lower_pending(id).is_ok()
                    && match &ctx.table.entries[id].meaning {
                        Meaning::Stored { .. } => true,
                        Meaning::Definition(t) => !mentions_symbols(t),
                        _ => false,
                    }
            });
            if free && !keys.iter().any(|(k, _)| *k == key) {
                keys.push((key, node.clone()));
            }
        }
    }
    if keys.is_empty() {
        return Err(claim_error(
            spec,
            "a first-order claim (`≈`) expands in small quantities, but it prints no increment              (`\\delta x`, `\\Delta t`) the symbols file defines: give `wrt`",
        ));
    }
    let mut parts = Vec::with_capacity(keys.len());
    for (_, e) in &keys {
        parts.push(
            ctx.variable_of(scope, e, spec.side, true)
                .map_err(|m| claim_error(spec, m))?,
        );
    }
    let names: Vec<String> = keys.into_iter().map(|(k, _)| k).collect();
    let variable = if parts.len() == 1 {
        parts.pop().expect("one part")
    } else {
        Variable::Joint(parts)
    };
    Ok((variable, short(&names.join(", "))))
}

/// Whether a term refers to any symbol.
fn mentions_symbols(t: &Term) -> bool {
    matches!(t, Term::Symbol(_)) || t.children().into_iter().any(mentions_symbols)
}

/// `lhs rel rhs` with the right side as evaluated (a differential's
/// numerator, as printed in its tangent).
pub fn understood_line(ctx: &Context, lhs: Option<&Expr>, relation: Rel, printed: &Term) -> String {
    let rhs = match printed {
        Term::Quotient {
            numerator,
            limit: false,
            ..
        } => numerator.as_ref(),
        other => other,
    };
    let rhs = super::understood::Names::of(ctx).render(rhs);
    match lhs {
        Some(l) => format!("{l} {} {rhs}", doc_latex::render::relation_latex(relation)),
        None => rhs,
    }
}

/// The canonical LaTeX other formulas write a claim's derivative with.
pub fn lhs_key(
    spec: &ClaimSpec,
    located: &Located,
    vocabulary: &Vocabulary,
) -> Result<Option<String>, TextError> {
    match &spec.lhs {
        Some(written) => canonical(written, vocabulary)
            .map(Some)
            .map_err(|m| claim_error(spec, format!("`lhs`: {m}"))),
        None => Ok(located.lhs.as_ref().map(|l| l.to_string())),
    }
}

/// One sample of a claim: what the verdict engine audits.
pub struct TextDerivation<'a> {
    claim: &'a TextClaim,
    ctx: &'a Context,
    stored: Vec<f64>,
}

/// `x` over another scalar.
fn lift<S: Scalar>(x: &[f64]) -> Vec<S> {
    x.iter().map(|v| S::from_f64(*v)).collect()
}

impl<'a> TextDerivation<'a> {
    /// The claim at the sample stored as `stored`.
    pub fn new(claim: &'a TextClaim, ctx: &'a Context, stored: Vec<f64>) -> Self {
        TextDerivation { claim, ctx, stored }
    }

    fn space(&self) -> Space<'a> {
        Space {
            table: &self.ctx.table,
            printed: &self.ctx.printed,
            factor: self.ctx.factor,
            templates: &self.ctx.templates,
        }
    }

    /// An environment over the parameters `p` at the claim's point: its
    /// variable at zero when the claim is a derivative there (`at_zero`,
    /// `\left. … \right|_{x=0}`), so that what it prints, and the
    /// derivatives printed in it, are taken there too.
    fn env_at_point<S: Scalar>(
        &self,
        p: Vec<S>,
        near_zero: bool,
    ) -> Result<Env<'_, S>, ShapeError> {
        let mut env = Env::new(self.space(), p).near_zero(near_zero);
        if let Some(v) = &self.claim.variable
            && v.at_zero()
        {
            env.perturb(v, &vec![S::zero(); v.dim()])?;
        }
        Ok(env)
    }

    /// `term` with `variable` perturbed by `x`, over the parameters `p`; a
    /// group element read in its local coordinates on `output` about its
    /// unperturbed value.
    fn evaluate<S: Scalar>(
        &self,
        term: &Term,
        variable: Option<&Variable>,
        output: Option<Perturbation>,
        x: &[S],
        p: &[S],
        holding: &[SymbolId],
    ) -> Result<Value<S>, ShapeError> {
        let at = |x: &[S]| -> Result<Value<S>, ShapeError> {
            let mut env = self.env_at_point(p.to_vec(), self.claim.near_zero)?;
            // What a partial holds keeps its value while the variable moves.
            let held = holding
                .iter()
                .map(|id| Ok((*id, env.symbol(*id)?)))
                .collect::<Result<Vec<_>, ShapeError>>()?;
            if let Some(v) = variable {
                env.perturb(v, x)?;
            }
            for (id, value) in held {
                env.bind(id, value);
            }
            env.eval(term)
        };
        let value = at(x)?;
        // A group-valued map is read in local coordinates (on the right
        // unless said): by a variable of several coordinates a Jacobian in
        // the tangent; by one coordinate (`dR/dt`) it stays the matrix, and
        // so do both sides of a first-order claim (`Exp(−θ) R ≈ (I − ⌊θ⌋)
        // R` compares a rotation with a matrix).
        let first_order = self.claim.kind == ClaimKind::FirstOrder;
        let side = match (output, variable) {
            (Some(side), Some(_)) => Some(side),
            (None, Some(v)) if v.dim() > 1 && !first_order => Some(Perturbation::Right),
            _ => None,
        };
        match side {
            // About the value at the expansion point (the variable at zero
            // when it is expanded about zero).
            Some(side) if value.is_group() => value.minus(at(&vec![S::zero(); x.len()])?, side),
            _ => Ok(value),
        }
    }

    /// `term` with the variable perturbed by `x`, over the parameters `p`,
    /// its entries in column-major order (a homogeneous transformation's
    /// top 3 × 4 when the map's value is one and the claim its Jacobian).
    fn value<S: Scalar>(
        &self,
        term: &Term,
        variable: Option<&Variable>,
        x: &[S],
        p: &[S],
    ) -> Result<DMatrix<S>, ShapeError> {
        let top_of_homogeneous =
            self.claim.kind == ClaimKind::Jacobian && self.claim.value_shape == (3, 4);
        let hint = match self.claim.value_shape {
            (0, _) => (None, None),
            _ if top_of_homogeneous => (None, None),
            (r, c) => (Some(r), Some(c)),
        };
        let m = self
            .evaluate(term, variable, self.claim.output, x, p, &self.claim.holding)?
            .sized(hint)?;
        Ok(if top_of_homogeneous && m.shape() == (4, 4) {
            m.rows(0, 3).into_owned()
        } else {
            m
        })
    }

    /// The true derivative of a link the file states in words, at this
    /// sample.
    fn truth_link(&self, link: &TruthLink) -> Result<DMatrix<f64>, ShapeError> {
        if let Some(why) = &link.broken {
            return Err(ShapeError(format!("the link `{}`: {why}", link.key)));
        }
        let p = lift::<Dual<1>>(&self.stored);
        let failure = std::cell::RefCell::new(None);
        let shape = std::cell::Cell::new((0, 0));
        let m = dual_jacobian(&vec![0.0; link.variable.dim()], |x| {
            match self
                .evaluate(
                    &link.of,
                    Some(&link.variable),
                    link.output,
                    x,
                    &p,
                    &link.holding,
                )
                .and_then(Value::matrix)
            {
                Ok(m) => {
                    let (entries, moving) = super::value::moving_entries(&m);
                    shape.set(moving);
                    entries
                }
                Err(e) => {
                    *failure.borrow_mut() = Some(e);
                    Vec::new()
                }
            }
        });
        if let Some(e) = failure.into_inner() {
            return Err(e);
        }
        // The derivative by one coordinate (`dR/dt`) has the map's shape.
        let (rows, cols) = shape.get();
        Ok(if m.ncols() == 1 && cols > 1 && rows * cols == m.nrows() {
            DMatrix::from_column_slice(rows, cols, m.as_slice())
        } else {
            m
        })
    }

    /// The values at this sample of the links stated in words `term` uses
    /// (through the claims it links and the definitions it uses too).
    fn truths<S: Scalar>(&self, term: &Term) -> Result<Vec<Option<DMatrix<S>>>, ShapeError> {
        let mut out = vec![None; self.ctx.truth_links.len()];
        if out.is_empty() {
            return Ok(out);
        }
        let mut seen = vec![false; self.ctx.table.entries.len()];
        let mut stack = vec![term];
        while let Some(t) = stack.pop() {
            match t {
                Term::TruthLink(k) if out[*k].is_none() => {
                    let m = self.truth_link(&self.ctx.truth_links[*k])?;
                    out[*k] = Some(m.map(S::from_f64));
                }
                Term::Link(k) => {
                    if let Some(Some(linked)) = self.ctx.printed.get(*k) {
                        stack.push(linked);
                    }
                }
                Term::Template(k, _) => stack.push(&self.ctx.templates[*k].body),
                Term::Symbol(id) if !seen[*id] => {
                    seen[*id] = true;
                    match &self.ctx.table.entries[*id].meaning {
                        Meaning::Definition(d) => stack.push(d),
                        Meaning::Component { of, .. } => {
                            if let Meaning::Definition(d) = &self.ctx.table.entries[*of].meaning {
                                stack.push(d);
                            }
                        }
                        _ => {}
                    }
                }
                _ => {}
            }
            stack.extend(t.children());
        }
        Ok(out)
    }

    /// The length of the variable's input.
    pub fn input_len(&self) -> usize {
        self.claim.variable.as_ref().map_or(0, Variable::dim)
    }

    /// The map's value at the sample (its shape as computed; a group
    /// element read in local coordinates is a tangent).
    pub fn map_value(&self) -> Result<DMatrix<f64>, ShapeError> {
        let dim = self.input_len();
        self.evaluate(
            &self.claim.of,
            self.claim.variable.as_ref(),
            self.claim.output,
            &vec![0.0; dim],
            &self.stored,
            &self.claim.holding,
        )?
        .matrix()
    }

    /// A printed right side (the claim's, or an edit of it) at this
    /// sample, as the matrix it claims to be.
    pub fn printed_term(&self, term: &Term) -> Printed {
        let claim = self.claim;
        let (rows, cols) = claim.value_shape;
        let expected = match claim.kind {
            ClaimKind::Value => (rows, cols),
            _ => (rows * cols, self.input_len()),
        };
        let got = match claim.kind {
            ClaimKind::FirstOrder => {
                let p = lift::<Dual<1>>(&self.stored);
                let failure = std::cell::RefCell::new(None);
                let m = dual_jacobian(&vec![0.0; self.input_len()], |x| {
                    match self.value(term, claim.variable.as_ref(), x, &p) {
                        Ok(m) => m.as_slice().to_vec(),
                        Err(e) => {
                            *failure.borrow_mut() = Some(e);
                            Vec::new()
                        }
                    }
                });
                match failure.into_inner() {
                    Some(e) => Err(e),
                    None => Ok(m),
                }
            }
            _ => {
                let at = |near_zero: bool| {
                    self.truths::<f64>(term).and_then(|truths| {
                        self.env_at_point(self.stored.clone(), near_zero)?
                            .with_truths(truths)
                            .eval(term)
                            .and_then(|v| v.sized((Some(expected.0), Some(expected.1))))
                    })
                };
                match at(claim.near_zero) {
                    // A removable singularity of the printed formula at
                    // zero (`sin‖w‖/‖w‖`): next to it.
                    Ok(m)
                        if m.iter().any(|x| !x.is_finite())
                            && !claim.near_zero
                            && claim.variable.as_ref().is_some_and(Variable::at_zero) =>
                    {
                        at(true)
                    }
                    other => other,
                }
            }
        };
        match got {
            Err(e) => Printed::Malformed(e.0),
            // 0/0, √ of a negative: no number is what the formula prints.
            Ok(m) if m.iter().any(|x| !x.is_finite()) => Printed::Malformed(
                "the printed formula is not finite at a sample (a division by zero, a root or a \
                 logarithm of a negative)"
                    .into(),
            ),
            Ok(m) if m.shape() == expected => Printed::Evaluated(match claim.kind {
                ClaimKind::Value => DMatrix::from_column_slice(rows * cols, 1, m.as_slice()),
                _ => m,
            }),
            // The derivative by one coordinate printed as a matrix
            // (`\dot{R} = R [ω]_×`, `[\dot{R}, \dot{p}]`): its entries
            // column by column (`vec`), as the map's value is read.
            Ok(m)
                if claim.kind != ClaimKind::Value
                    && expected.1 == 1
                    && m.ncols() > 1
                    && m.len() == expected.0 =>
            {
                Printed::Evaluated(DMatrix::from_column_slice(rows * cols, 1, m.as_slice()))
            }
            // A homogeneous coordinate kept: the verdict engine names it.
            Ok(m) if m.nrows() == expected.0 + 1 && m.ncols() == expected.1 => {
                Printed::Evaluated(m)
            }
            Ok(m) => Printed::Malformed(format!(
                "the printed matrix is {}, but {} is {}",
                shape_text(m.shape()),
                match claim.kind {
                    ClaimKind::Value => "the value".to_string(),
                    _ => "the Jacobian".to_string(),
                },
                shape_text(expected)
            )),
        }
    }

    /// For a first-order claim, why `term` (its printed side, or a variant
    /// of it) is not right even at the expansion point: the two sides'
    /// values there differ (their derivatives are compared apart).
    pub fn gap_at_point(&self, term: &Term) -> Option<String> {
        if self.claim.kind != ClaimKind::FirstOrder {
            return None;
        }
        let zero = vec![0.0; self.input_len()];
        let at = |t: &Term| {
            self.evaluate(
                t,
                self.claim.variable.as_ref(),
                None,
                &zero,
                &self.stored,
                &self.claim.holding,
            )
            .and_then(Value::matrix)
        };
        let (truth, printed) = (at(&self.claim.of).ok()?, at(term).ok()?);
        let error = if truth.shape() == printed.shape() {
            factor_core::factor::relative_frobenius_error(&printed, &truth, 1e-9)
        } else {
            f64::INFINITY
        };
        (error > crate::verdict::TOLERANCE).then(|| {
            format!(
                "the two sides differ at the expansion point (relative error {error:.1e}), so \
                 they do not agree to first order"
            )
        })
    }

    /// The truths under the claim's conventions at this sample.
    fn convention_truths(&self) -> Vec<(String, DMatrix<f64>)> {
        let p = lift::<Dual<1>>(&self.stored);
        self.claim
            .conventions
            .iter()
            .filter_map(|c| {
                let m = match (&c.variable, self.claim.kind) {
                    (_, ClaimKind::Value) | (None, _) => {
                        let m = self
                            .value(&c.of, None, &[], &lift::<f64>(&self.stored))
                            .ok()?;
                        DMatrix::from_column_slice(m.len(), 1, m.as_slice())
                    }
                    (Some(v), _) => dual_jacobian(&vec![0.0; v.dim()], |x| {
                        self.value(&c.of, Some(v), x, &p)
                            .map(|m| m.as_slice().to_vec())
                            .unwrap_or_default()
                    }),
                };
                Some((c.description.clone(), m))
            })
            .collect()
    }
}

impl Derivation for TextDerivation<'_> {
    fn label(&self) -> Label {
        self.claim.label.clone()
    }
    fn point(&self) -> Vec<f64> {
        vec![0.0; self.input_len()]
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        self.ctx
            .names
            .iter()
            .cloned()
            .zip(self.stored.iter().copied())
            .collect()
    }
    fn input_names(&self) -> Vec<String> {
        (1..=self.input_len())
            .map(|k| format!("\\delta_{{{k}}}"))
            .collect()
    }
    fn map<S: Scalar>(&self, x: &[S], p: &[S]) -> Vec<S> {
        // The map evaluated at load, so its shapes fit; an error here would
        // give no entries, which no printed formula matches.
        self.value(&self.claim.of, self.claim.variable.as_ref(), x, p)
            .map(|m| m.as_slice().to_vec())
            .unwrap_or_default()
    }
    fn printed(&self) -> Printed {
        self.printed_term(&self.claim.printed)
    }
    fn claim(&self) -> Claim {
        match self.claim.kind {
            ClaimKind::Value => Claim::Value,
            _ => Claim::Jacobian,
        }
    }
    fn conventions(&self) -> Vec<(String, DMatrix<f64>)> {
        self.convention_truths()
    }
    fn gap(&self) -> Option<String> {
        self.gap_at_point(&self.claim.printed)
    }
}
