//! A context of a symbols file, built: its symbol table (the context's
//! symbols and each claim's own readings, in scopes), what samples it, the
//! operators and functions it defines by LaTeX ([`Template`]s), the
//! chain-rule links it states ([`TruthLink`]s), and the lowering of
//! definitions on demand (in dependency order, cycles and over-deep nesting
//! reported).

use std::collections::HashMap;

use doc_latex::Vocabulary;
use doc_latex::ast::{Expr, Head};

use super::TextError;
use super::factors::FactorKind;
use super::functions::Builtin;
use super::lower::{
    Found, Link, LowerError, Lowering, PrintedDerivative, Resolver, short, symbol_key,
};
use super::stored::{FreeSample, Kind, part};
use super::symbols::{
    ContextSpec, LinkSpec, MAX_SYMBOLS, Perturbed, Side, SymbolSpec, TemplateSpec, one_line,
};
use super::term::{Meaning, SymbolId, Table, Template, Term, TruthLink, Variable};
use crate::transcription::stored_names;
use factor_core::manifold::Perturbation;
use factor_core::storage::Layout;
use factor_testing::samples::Sampler;

/// Deepest chain of definitions (a definition using one using one …).
pub const MAX_DEFINITION_DEPTH: usize = 16;

/// Most operators and function templates a context may define.
pub const MAX_TEMPLATES: usize = 200;

/// Where a symbol is looked up: a claim's own readings first, then the
/// context's.
pub type Scope = Option<usize>;

/// The scopes of templates' arguments come after every claim's.
const TEMPLATE_SCOPES: usize = 1 << 40;

/// How a definition or a template waits to be lowered.
#[derive(Debug, Clone)]
enum State {
    Done,
    Pending(Box<Expr>, Scope),
    InProgress,
}

/// A context, built.
#[derive(Debug, Clone)]
pub struct Context {
    /// Its name in the symbols file.
    pub name: String,
    /// The factor sampled, if any.
    pub factor: Option<FactorKind>,
    /// Free variables: sampler and offset in the stored scalars.
    pub free: Vec<(FreeSample, usize)>,
    /// LaTeX names of the stored scalars, from their layouts.
    pub names: Vec<String>,
    /// The symbols.
    pub table: Table,
    /// The document's macros and words, which LaTeX of the symbols file is
    /// read with too.
    pub vocabulary: Vocabulary,
    scopes: HashMap<Scope, HashMap<String, SymbolId>>,
    states: Vec<State>,
    /// How deep each symbol's definitions nest (0 for a symbol not defined
    /// in terms of others).
    depths: Vec<usize>,
    building: usize,
    /// Derivative (canonical LaTeX) to the claim stating it.
    pub links: HashMap<String, usize>,
    /// The printed formula of each claim of the file in this context.
    pub printed: Vec<Option<Term>>,
    /// Operators and functions defined by LaTeX.
    pub templates: Vec<Template>,
    template_states: Vec<State>,
    /// Operator keys (`\boxminus`, `^\odot`, `between`) to templates.
    template_keys: HashMap<String, usize>,
    /// How a derivative by a stored symbol perturbs it by default.
    defaults: HashMap<SymbolId, Perturbed>,
    /// Links stated in words, once lowered.
    pub truth_links: Vec<TruthLink>,
    link_specs: Vec<LinkSpec>,
    /// Why a link stated in words could not be read, by its key.
    link_errors: HashMap<String, String>,
    /// The symbols file states JPL quaternions.
    pub jpl_quaternions: bool,
    /// The symbols whose very key cannot be read, with why: a formula that
    /// finds a symbol undefined says so.
    unreadable: Vec<String>,
}

/// The canonical LaTeX of a name the symbols file defines: a symbol, or
/// any printed expression but a number (`\pi'(q)`, `u v`, `\hat{\xi}_b^*`).
pub fn canonical_symbol(written: &str, vocabulary: &Vocabulary) -> Result<String, String> {
    // A function's name alone (`\exp`, `Exp`): the document's function
    // given another meaning (`{ function = "expm" }`), keyed as written.
    let name = written.trim();
    let letters = name.strip_prefix('\\').unwrap_or(name);
    if !letters.is_empty()
        && letters.chars().all(|c| c.is_ascii_alphabetic())
        && matches!(
            doc_latex::parse_expr_with(name, vocabulary),
            Err(e) if matches!(e.kind, doc_latex::ErrorKind::MissingOperand(_))
        )
    {
        return Ok(name.to_string());
    }
    match doc_latex::parse_expr_with(written, vocabulary) {
        Ok(Expr::Symbol(s)) => Ok(symbol_key(&s)),
        Ok(e @ (Expr::Number(_) | Expr::Relation { .. } | Expr::Text(_))) => {
            Err(format!("`{e}` is not a name"))
        }
        Ok(other) => Ok(other.to_string()),
        Err(e) => Err(format!("cannot read it: {}", e.kind)),
    }
}

/// The canonical LaTeX of any expression written in the symbols file.
pub fn canonical(written: &str, vocabulary: &Vocabulary) -> Result<String, String> {
    doc_latex::parse_expr_with(written, vocabulary)
        .map(|e| e.to_string())
        .map_err(|e| format!("cannot read `{written}`: {} at `{}`", e.kind, e.fragment))
}

/// An operator's key as the symbols file writes it, normalised: no braces
/// or spaces (`^{\odot}` is `^\odot`).
pub fn operator_key(written: &str) -> String {
    written
        .chars()
        .filter(|c| !c.is_whitespace() && *c != '{' && *c != '}')
        .collect()
}

impl Context {
    /// The context `name` as `spec` writes it (its claims' readings are
    /// added with [`Context::add_claim_symbols`]); LaTeX is read with the
    /// document's `vocabulary`.
    pub fn build(
        name: &str,
        spec: &ContextSpec,
        vocabulary: &Vocabulary,
    ) -> Result<Self, TextError> {
        let error = |message: String| TextError::Context {
            context: name.to_string(),
            message,
        };
        let factor = match &spec.factor {
            None => None,
            Some(f) => Some(FactorKind::named(f).ok_or_else(|| {
                error(format!(
                    "no factor `{f}` (factors: {})",
                    FactorKind::all_names()
                ))
            })?),
        };
        if spec.symbols.len() > MAX_SYMBOLS {
            return Err(error(format!("more than {MAX_SYMBOLS} symbols")));
        }
        if spec.operators.len() > MAX_TEMPLATES {
            return Err(error(format!("more than {MAX_TEMPLATES} operators")));
        }
        let mut names: Vec<String> = factor
            .map(|f| stored_names_of(&f.layout(), spec, f))
            .unwrap_or_default();
        let mut ctx = Context {
            name: name.to_string(),
            factor,
            free: Vec::new(),
            names: Vec::new(),
            table: Table::default(),
            vocabulary: vocabulary.clone(),
            scopes: HashMap::from([(None, HashMap::new())]),
            states: Vec::new(),
            depths: Vec::new(),
            building: 0,
            links: HashMap::new(),
            printed: Vec::new(),
            templates: Vec::new(),
            template_states: Vec::new(),
            template_keys: HashMap::new(),
            defaults: HashMap::new(),
            truth_links: Vec::new(),
            link_specs: spec.links.clone(),
            link_errors: HashMap::new(),
            jpl_quaternions: false,
            unreadable: Vec::new(),
        };
        for (written, t) in &spec.operators {
            let id = ctx.template(written, t, None)?;
            ctx.template_keys.insert(operator_key(written), id);
        }
        let mut tangents = Vec::new();
        for (written, value) in &spec.symbols {
            // A symbol that cannot be read fails the claims that use it,
            // not the context.
            let meaning = match SymbolSpec::read(written, value) {
                Ok(m) => m,
                Err(e) => {
                    ctx.unreadable(written, e);
                    continue;
                }
            };
            let id = match ctx.declare(None, written, None) {
                Ok(id) => id,
                Err(e) => {
                    ctx.unreadable(written, e);
                    continue;
                }
            };
            let read = (|| -> Result<(), TextError> {
                match meaning {
                    SymbolSpec::Sample {
                        name,
                        size,
                        shape,
                        range,
                        components,
                        perturbation,
                    } => {
                        let sample = FreeSample::from_spec(&name, size, shape, range)
                            .map_err(|m| symbol_error(written, None, m))?;
                        let offset = names.len();
                        names.extend(sampled_names(sample, written));
                        ctx.free.push((sample, offset));
                        ctx.set(
                            id,
                            Meaning::Stored {
                                offset,
                                kind: sample.kind(),
                            },
                        );
                        ctx.defaults.insert(id, perturbation);
                        for (index, c) in components.iter().enumerate() {
                            let cid = ctx.declare(None, c, None)?;
                            ctx.set(cid, Meaning::Component { of: id, index });
                        }
                    }
                    SymbolSpec::Template(t) => {
                        let template = ctx.template(written, &t, None)?;
                        ctx.set(id, Meaning::Template(template));
                    }
                    other => {
                        if let Some(t) = ctx.meaning(id, written, other, None)? {
                            tangents.push(t);
                        }
                    }
                }
                Ok(())
            })();
            if let Err(e) = read {
                ctx.set(id, Meaning::Broken(one_line(&e.to_string())));
            }
        }
        ctx.names = names;
        for (id, written, spec) in tangents {
            if let Err(e) = ctx.tangent(id, &written, spec, None) {
                ctx.set(id, Meaning::Broken(one_line(&e.to_string())));
            }
        }
        Ok(ctx)
    }

    /// Records a symbol whose key cannot be read.
    fn unreadable(&mut self, written: &str, e: TextError) {
        self.unreadable.push(format!(
            "`{}` ({})",
            one_line(written),
            one_line(&e.to_string())
        ));
    }

    /// Declares a template: its arguments bound in a scope of their own.
    fn template(
        &mut self,
        written: &str,
        t: &TemplateSpec,
        equation: Option<&str>,
    ) -> Result<usize, TextError> {
        let bad = |m: String| symbol_error(written, equation, m);
        if self.templates.len() >= MAX_TEMPLATES {
            return Err(bad(format!("more than {MAX_TEMPLATES} operators")));
        }
        let id = self.templates.len();
        let scope = Some(TEMPLATE_SCOPES + id);
        let mut params = Vec::with_capacity(t.args.len() + 1);
        for a in t.sub.iter().chain(&t.args) {
            let p = self.declare(scope, a, equation)?;
            self.set(p, Meaning::Bound);
            params.push(p);
        }
        let e = doc_latex::parse_expr_with(&t.latex, &self.vocabulary).map_err(|e| {
            bad(format!(
                "cannot read `{}`: {} at `{}`",
                t.latex, e.kind, e.fragment
            ))
        })?;
        self.templates.push(Template {
            key: operator_key(written),
            written: written.trim().to_string(),
            params,
            subscripted: t.sub.is_some(),
            body: Term::Zero,
        });
        self.template_states
            .push(State::Pending(Box::new(e), scope));
        Ok(id)
    }

    /// Adds claim `claim`'s own readings (its `[claim.symbols]`).
    pub fn add_claim_symbols(
        &mut self,
        claim: usize,
        equation: &str,
        symbols: &std::collections::BTreeMap<String, toml::Value>,
    ) -> Result<(), TextError> {
        self.scopes.entry(Some(claim)).or_default();
        let mut tangents = Vec::new();
        for (written, value) in symbols {
            let meaning = SymbolSpec::read(written, value).map_err(|e| match e {
                TextError::Symbol {
                    symbol, message, ..
                } => TextError::Symbol {
                    symbol,
                    equation: Some(equation.to_string()),
                    message,
                },
                other => other,
            })?;
            if matches!(meaning, SymbolSpec::Sample { .. }) {
                return Err(symbol_error(
                    written,
                    Some(equation),
                    "a claim cannot sample: declare it in its context".into(),
                ));
            }
            if let SymbolSpec::Template(t) = &meaning {
                // A function read this way in this formula only.
                let template = self.template(written, t, Some(equation))?;
                let id = self.declare(Some(claim), written, Some(equation))?;
                self.set(id, Meaning::Template(template));
                continue;
            }
            let id = self.declare(Some(claim), written, Some(equation))?;
            if let Some(t) = self.meaning(id, written, meaning, Some(equation))? {
                tangents.push(t);
            }
        }
        for (id, written, spec) in tangents {
            self.tangent(id, &written, spec, Some((claim, equation)))?;
        }
        Ok(())
    }

    /// A new symbol `written` in `scope`.
    pub fn declare(
        &mut self,
        scope: Scope,
        written: &str,
        equation: Option<&str>,
    ) -> Result<SymbolId, TextError> {
        let key = canonical_symbol(written, &self.vocabulary)
            .map_err(|m| symbol_error(written, equation, m))?;
        if self.table.entries.len() >= MAX_SYMBOLS {
            return Err(symbol_error(
                written,
                equation,
                format!("more than {MAX_SYMBOLS} symbols in one context"),
            ));
        }
        let names = self.scopes.entry(scope).or_default();
        if names.contains_key(&key) {
            return Err(symbol_error(
                written,
                equation,
                format!("`{key}` is defined twice"),
            ));
        }
        let id = self.table.add(key.clone());
        self.states.push(State::Done);
        self.depths.push(0);
        self.scopes.entry(scope).or_default().insert(key, id);
        Ok(id)
    }

    fn set(&mut self, id: SymbolId, meaning: Meaning) {
        self.table.entries[id].meaning = meaning;
    }

    /// Sets the meaning of a declared symbol; a tangent is returned to be
    /// resolved once every symbol is declared.
    fn meaning(
        &mut self,
        id: SymbolId,
        written: &str,
        spec: SymbolSpec,
        equation: Option<&str>,
    ) -> Result<Option<(SymbolId, String, SymbolSpec)>, TextError> {
        let scope = self.scope_of(id);
        let bad = |m: String| symbol_error(written, equation, m);
        match spec {
            SymbolSpec::Latex { latex, components } => {
                let e = doc_latex::parse_expr_with(&latex, &self.vocabulary).map_err(|e| {
                    bad(format!(
                        "cannot read `{latex}`: {} at `{}`",
                        e.kind, e.fragment
                    ))
                })?;
                let size = super::tree::nodes(&e).len();
                if size > super::MAX_FORMULA_NODES {
                    return Err(bad(format!(
                        "the definition has {size} nodes; at most {} are read",
                        super::MAX_FORMULA_NODES
                    )));
                }
                self.states[id] = State::Pending(Box::new(e), scope);
                for (index, c) in components.iter().enumerate() {
                    let cid = self.declare(scope, c, equation)?;
                    self.set(cid, Meaning::Component { of: id, index });
                }
            }
            SymbolSpec::Field {
                path,
                components,
                perturbation,
            } => {
                let Some(factor) = self.factor else {
                    return Err(bad("a field needs the context's `factor`".into()));
                };
                let (offset, layout) = part(&factor.layout(), &path).ok_or_else(|| {
                    bad(format!(
                        "no field `{path}` in `{}` (its stored scalars: {})",
                        factor.name(),
                        factor.layout().names().join(", ")
                    ))
                })?;
                self.set(
                    id,
                    Meaning::Stored {
                        offset,
                        kind: Kind::of(&layout),
                    },
                );
                self.defaults.insert(id, perturbation);
                for (index, c) in components.iter().enumerate() {
                    let cid = self.declare(scope, c, equation)?;
                    self.set(cid, Meaning::Component { of: id, index });
                }
            }
            SymbolSpec::Function(name) => {
                let b = Builtin::named(&name).ok_or_else(|| {
                    bad(format!(
                        "no function `{name}` (functions: {})",
                        Builtin::all_names()
                    ))
                })?;
                self.set(id, Meaning::Function(b));
            }
            SymbolSpec::Residual(components) => {
                let Some(factor) = self.factor else {
                    return Err(bad("a residual needs the context's `factor`".into()));
                };
                let dim = factor.residual_dim();
                if components.is_empty() || components.iter().any(|c| *c == 0 || *c > dim) {
                    return Err(bad(format!(
                        "residual components are 1 to {dim} (the residual of `{}`)",
                        factor.name()
                    )));
                }
                self.set(
                    id,
                    Meaning::Residual(components.iter().map(|c| c - 1).collect()),
                );
            }
            SymbolSpec::Sample { .. } | SymbolSpec::Template(_) => {
                unreachable!("sampled symbols and templates are set by the caller")
            }
            spec @ SymbolSpec::Tangent { .. } => {
                return Ok(Some((id, written.to_string(), spec)));
            }
        }
        Ok(None)
    }

    /// Resolves a tangent: what it perturbs, on which side or by which
    /// update, which coordinates, and its parts.
    fn tangent(
        &mut self,
        id: SymbolId,
        written: &str,
        spec: SymbolSpec,
        claim: Option<(usize, &str)>,
    ) -> Result<(), TextError> {
        let equation = claim.map(|(_, e)| e);
        let SymbolSpec::Tangent {
            perturbs,
            side,
            update,
            parts,
            coordinates,
        } = spec
        else {
            return Ok(());
        };
        let bad = |m: String| symbol_error(written, equation, m);
        let key = canonical_symbol(&perturbs, &self.vocabulary).map_err(&bad)?;
        let scope = claim.map(|(c, _)| c);
        let target = self
            .lookup(scope, &key)
            .ok_or_else(|| bad(format!("it perturbs `{key}`, which is not defined")))?;
        let variable = match &update {
            Some(latex) => {
                if side.is_some() || coordinates.is_some() {
                    return Err(bad(
                        "an `update` says how it perturbs: no `side` or `coordinates`".into(),
                    ));
                }
                self.update_variable(scope, target, latex).map_err(bad)?
            }
            None => self
                .variable(target, side, coordinates.as_deref(), false)
                .map_err(bad)?,
        };
        let mut part_ids = Vec::new();
        for p in &parts {
            let pid = self.declare(scope, p, equation)?;
            self.set(pid, Meaning::Bound);
            part_ids.push(pid);
        }
        self.set(
            id,
            Meaning::Tangent {
                variable,
                parts: part_ids,
            },
        );
        Ok(())
    }

    /// A variable perturbed by an update: `symbol` replaced by `latex`, an
    /// expression in it and `\delta` (the input).
    pub fn update_variable(
        &mut self,
        scope: Scope,
        symbol: SymbolId,
        latex: &str,
    ) -> Result<Variable, String> {
        let symbol = self.alias_of(symbol);
        let delta = match self.lookup(scope, "\\delta") {
            Some(d) => d,
            None => {
                let d = self
                    .declare(scope, "\\delta", None)
                    .map_err(|e| e.to_string())?;
                self.set(d, Meaning::Bound);
                d
            }
        };
        let e = doc_latex::parse_expr_with(latex, &self.vocabulary).map_err(|e| {
            format!(
                "cannot read the update `{latex}`: {} at `{}`",
                e.kind, e.fragment
            )
        })?;
        let update = Lowering::new(&mut self.resolver(scope), false)
            .expr(&e)
            .map_err(|e| format!("the update: {e}"))?;
        Ok(Variable::Update {
            symbol,
            update,
            delta,
            dim: 0,
        })
    }

    /// What a derivative by symbol `target` perturbs: a stored value on a
    /// side (the one given, else the symbol's default), by the symbol's
    /// default update, or additively; a definition additively (its shape
    /// is set by [`Context::shape_defined`] once it can be evaluated).
    pub fn variable(
        &mut self,
        target: SymbolId,
        side: Option<Side>,
        coordinates: Option<&[usize]>,
        at_zero: bool,
    ) -> Result<Variable, String> {
        let target = self.alias_of(target);
        let key = self.table.key(target).to_string();
        let default = self.defaults.get(&target).cloned().unwrap_or_default();
        match self.table.entries[target].meaning.clone() {
            Meaning::Stored { offset, kind } => {
                let additive = kind.is_additive();
                if let (None, None, Some(update)) = (side, coordinates, &default.update) {
                    let scope = self.scope_of(target);
                    return self.update_variable(scope, target, update);
                }
                // A group element is perturbed on the right unless said.
                let side = match (side.or(default.side), additive) {
                    (Some(Side::Left), false) => Perturbation::Left,
                    (Some(Side::Right) | None, false) => Perturbation::Right,
                    (_, true) => Perturbation::Left,
                };
                if at_zero && !additive {
                    return Err(format!("`{key}` has no zero: it is not additive"));
                }
                let dim = kind.tangent_dim();
                let coordinates = match coordinates {
                    None => (0..dim).collect(),
                    Some(c) => {
                        if c.is_empty() || c.iter().any(|k| *k == 0 || *k > dim) {
                            return Err(format!("`{key}` has tangent coordinates 1 to {dim}"));
                        }
                        c.iter().map(|k| k - 1).collect()
                    }
                };
                Ok(Variable::Stored {
                    offset,
                    kind,
                    side,
                    coordinates,
                    at_zero,
                })
            }
            Meaning::Definition(_) | Meaning::Pending => {
                if side.is_some() || coordinates.is_some() {
                    return Err(format!(
                        "`{key}` is a definition: it is perturbed additively, as a whole"
                    ));
                }
                // A column of other symbols (`xy = [x; y]`): each of them.
                if let Meaning::Definition(t) = &self.table.entries[target].meaning
                    && let Some(parts) = stacked_symbols(t)
                {
                    return Ok(Variable::Joint(
                        parts
                            .into_iter()
                            .map(|id| self.variable(id, None, None, at_zero))
                            .collect::<Result<_, _>>()?,
                    ));
                }
                Ok(Variable::Defined {
                    symbol: target,
                    shape: (0, 0),
                    at_zero,
                })
            }
            Meaning::Tangent { mut variable, .. } => {
                if let (Variable::Stored { side: s, .. }, Some(new)) = (&mut variable, side) {
                    *s = match new {
                        Side::Left => Perturbation::Left,
                        Side::Right => Perturbation::Right,
                    };
                }
                if at_zero {
                    match &mut variable {
                        Variable::Stored {
                            kind, at_zero: z, ..
                        } if kind.is_additive() => *z = true,
                        Variable::Defined { at_zero: z, .. } => *z = true,
                        _ => return Err(format!("`{key}` has no zero: it is not additive")),
                    }
                }
                Ok(variable)
            }
            Meaning::Component { of, .. } => Err(format!(
                "`{key}` is an entry of `{}`: differentiate by `{}` as a whole",
                self.table.key(of),
                self.table.key(of)
            )),
            _ => Err(format!(
                "`{key}` is not a quantity a derivative can be taken by"
            )),
        }
    }

    /// The variable a derivative is taken by, written `wrt`: a symbol (or a
    /// name the file defines, `\pi'(q)`), or the entries of one vector in
    /// order (`(P_x, P_y, P_z)`).
    pub fn variable_of(
        &mut self,
        scope: Scope,
        wrt: &Expr,
        side: Option<Side>,
        at_zero: bool,
    ) -> Result<Variable, String> {
        let target = match wrt {
            Expr::Symbol(s) => self.lookup(scope, &symbol_key(s)),
            Expr::Apply {
                head: Head::Symbol(s),
                ..
            } => self
                .lookup(scope, &wrt.to_string())
                .or_else(|| self.lookup(scope, &symbol_key(s))),
            Expr::Tuple(items) => {
                let ids: Option<Vec<usize>> = items
                    .iter()
                    .map(|i| match i {
                        Expr::Symbol(s) => self.lookup(scope, &symbol_key(s)),
                        _ => None,
                    })
                    .collect();
                if let Some(ids) = ids {
                    return self.variable_of_symbols(&ids, side, at_zero);
                }
                None
            }
            other => self.lookup(scope, &other.to_string()),
        };
        let Some(target) = target else {
            return Err(format!(
                "`{}` is not a variable (a symbol, or the entries of one vector in order)",
                short(&wrt.to_string())
            ));
        };
        self.variable(target, side, None, at_zero)
    }

    /// The variable of a derivative by several symbols (`(P_x, P_y, P_z)`,
    /// `\{ω_x, ω_y, ω_z, θ\}`): each run of entries of one vector is its
    /// tangent coordinates (all of them in order: the vector); other
    /// symbols are each perturbed, holding the others (`θ` beside `ω`
    /// though `θ = ‖ω‖`: a partial by each argument).
    fn variable_of_symbols(
        &mut self,
        ids: &[SymbolId],
        side: Option<Side>,
        at_zero: bool,
    ) -> Result<Variable, String> {
        let component = |c: &Self, id: SymbolId| match c.table.entries[id].meaning {
            Meaning::Component { of, index } => Some((of, index)),
            _ => None,
        };
        let mut parts = Vec::new();
        let mut rest = ids;
        while let Some((&first, _)) = rest.split_first() {
            let Some((of, _)) = component(self, first) else {
                parts.push(self.variable(first, side, None, at_zero)?);
                rest = &rest[1..];
                continue;
            };
            let run = rest
                .iter()
                .take_while(|id| component(self, **id).is_some_and(|(o, _)| o == of))
                .count();
            let indices: Vec<usize> = rest[..run]
                .iter()
                .filter_map(|id| component(self, *id).map(|(_, k)| k))
                .collect();
            let entries = self
                .table
                .entries
                .iter()
                .filter(|e| matches!(e.meaning, Meaning::Component { of: o, .. } if o == of))
                .count();
            let whole = run == entries && indices.iter().enumerate().all(|(i, k)| *k == i);
            let coordinates: Vec<usize> = indices.iter().map(|k| k + 1).collect();
            parts.push(self.variable(
                of,
                side,
                (!whole).then_some(coordinates.as_slice()),
                at_zero,
            )?);
            rest = &rest[run..];
        }
        Ok(if parts.len() == 1 {
            parts.remove(0)
        } else {
            Variable::Joint(parts)
        })
    }

    /// Whether perturbing `v` moves symbol `id` itself (not only what
    /// depends on it).
    fn moves(&self, v: &Variable, id: SymbolId) -> bool {
        match v {
            Variable::Stored { offset, .. } => matches!(
                self.table.entries[id].meaning,
                Meaning::Stored { offset: o, .. } if o == *offset
            ),
            Variable::Defined { symbol, .. } | Variable::Update { symbol, .. } => *symbol == id,
            Variable::Joint(parts) => parts.iter().any(|p| self.moves(p, id)),
        }
    }

    /// Follows definitions that are one other symbol (`{}_w p_C = {}_W p_C`),
    /// lowered or not.
    pub fn alias_of(&self, mut id: SymbolId) -> SymbolId {
        for _ in 0..=MAX_DEFINITION_DEPTH {
            let next = match (&self.states[id], &self.table.entries[id].meaning) {
                (State::Pending(e, scope), _) => match e.as_ref() {
                    Expr::Symbol(s) => self.lookup(*scope, &symbol_key(s)),
                    _ => None,
                },
                (_, Meaning::Definition(Term::Symbol(other))) => Some(*other),
                _ => None,
            };
            match next {
                Some(n) => id = n,
                None => return id,
            }
        }
        id
    }

    /// An error when symbol `id`'s meaning could not be read.
    fn readable(&self, id: SymbolId) -> Result<(), LowerError> {
        match &self.table.entries[id].meaning {
            Meaning::Broken(why) => Err(LowerError {
                message: format!("the symbols file's meaning of it cannot be read: {why}"),
                fragment: self.table.key(id).to_string(),
            }),
            _ => Ok(()),
        }
    }

    /// The symbol `key` in `scope` (falling back to the context's).
    pub fn lookup(&self, scope: Scope, key: &str) -> Option<SymbolId> {
        scope
            .and_then(|s| self.scopes.get(&Some(s)).and_then(|m| m.get(key)))
            .or_else(|| self.scopes.get(&None).and_then(|m| m.get(key)))
            .copied()
    }

    /// The symbols visible in `scope`, by key.
    pub fn visible(&self, scope: Scope) -> Vec<(String, SymbolId)> {
        let mut out: HashMap<String, SymbolId> =
            self.scopes.get(&None).cloned().unwrap_or_default();
        if let Some(s) = scope.and_then(|s| self.scopes.get(&Some(s))) {
            out.extend(s.clone());
        }
        let mut out: Vec<(String, SymbolId)> = out.into_iter().collect();
        out.sort();
        out
    }

    fn scope_of(&self, id: SymbolId) -> Scope {
        self.scopes
            .iter()
            .find(|(_, m)| m.values().any(|v| *v == id))
            .and_then(|(s, _)| *s)
    }

    /// Lowers symbol `id`'s definition if it still waits.
    pub fn lower_pending(&mut self, id: SymbolId) -> Result<(), LowerError> {
        match std::mem::replace(&mut self.states[id], State::InProgress) {
            State::Done => {
                self.states[id] = State::Done;
                Ok(())
            }
            State::InProgress => Err(LowerError {
                message: "is defined in terms of itself".into(),
                fragment: self.table.key(id).to_string(),
            }),
            State::Pending(e, scope) => {
                if self.building >= MAX_DEFINITION_DEPTH {
                    self.states[id] = State::Pending(e, scope);
                    return Err(LowerError {
                        message: format!(
                            "definitions nest deeper than {MAX_DEFINITION_DEPTH} levels"
                        ),
                        fragment: self.table.key(id).to_string(),
                    });
                }
                self.building += 1;
                let term = Lowering::new(&mut ScopeResolver { ctx: self, scope }, false).expr(&e);
                self.building -= 1;
                match term {
                    Ok(t) => {
                        let depth = 1 + symbols_in(&t)
                            .iter()
                            .map(|k| self.depth_of(*k))
                            .max()
                            .unwrap_or(0);
                        self.set(id, Meaning::Definition(t));
                        self.states[id] = State::Done;
                        self.depths[id] = depth;
                        if depth > MAX_DEFINITION_DEPTH {
                            return Err(LowerError {
                                message: format!(
                                    "definitions nest deeper than {MAX_DEFINITION_DEPTH} levels"
                                ),
                                fragment: self.table.key(id).to_string(),
                            });
                        }
                        Ok(())
                    }
                    Err(err) => {
                        self.states[id] = State::Pending(e, scope);
                        Err(err)
                    }
                }
            }
        }
    }

    /// Lowers template `id`'s body if it still waits.
    fn lower_template(&mut self, id: usize) -> Result<(), LowerError> {
        match std::mem::replace(&mut self.template_states[id], State::InProgress) {
            State::Done => {
                self.template_states[id] = State::Done;
                Ok(())
            }
            State::InProgress => Err(LowerError {
                message: "is defined in terms of itself".into(),
                fragment: self.templates[id].key.clone(),
            }),
            State::Pending(e, scope) => {
                if self.building >= MAX_DEFINITION_DEPTH {
                    self.template_states[id] = State::Pending(e, scope);
                    return Err(LowerError {
                        message: format!(
                            "definitions nest deeper than {MAX_DEFINITION_DEPTH} levels"
                        ),
                        fragment: self.templates[id].key.clone(),
                    });
                }
                self.building += 1;
                let term = Lowering::new(&mut ScopeResolver { ctx: self, scope }, false).expr(&e);
                self.building -= 1;
                match term {
                    Ok(t) => {
                        self.templates[id].body = t;
                        self.template_states[id] = State::Done;
                        Ok(())
                    }
                    Err(err) => {
                        self.template_states[id] = State::Pending(e, scope);
                        Err(err)
                    }
                }
            }
        }
    }

    /// How deep symbol `id`'s definitions nest.
    fn depth_of(&self, id: SymbolId) -> usize {
        match &self.table.entries[id].meaning {
            Meaning::Component { of, .. } => 1 + self.depths[*of],
            _ => self.depths[id],
        }
    }

    /// Lowers every template, definition and link stated in words,
    /// reporting the first that cannot be (the others are still lowered:
    /// a claim using a broken one gets its error).
    pub fn lower_all(
        &mut self,
        equation_of: impl Fn(Scope) -> Option<String>,
    ) -> Result<(), TextError> {
        let mut first: Option<TextError> = None;
        for id in 0..self.templates.len() {
            if let Err(e) = self.lower_template(id) {
                first.get_or_insert(TextError::Symbol {
                    symbol: self.templates[id].key.clone(),
                    equation: None,
                    message: e.to_string(),
                });
            }
        }
        for id in 0..self.table.entries.len() {
            if let Err(e) = self.lower_pending(id) {
                let scope = self.scope_of(id);
                first.get_or_insert(TextError::Symbol {
                    symbol: self.table.key(id).to_string(),
                    equation: equation_of(scope),
                    message: e.to_string(),
                });
            }
        }
        for spec in std::mem::take(&mut self.link_specs) {
            if let Err(message) = self.truth_link(&spec) {
                self.link_errors.insert(
                    canonical(&spec.lhs, &self.vocabulary).unwrap_or_default(),
                    message.clone(),
                );
                first.get_or_insert(TextError::Context {
                    context: self.name.clone(),
                    message: format!("the link `{}`: {message}", short(&spec.lhs)),
                });
            }
        }
        first.map_or(Ok(()), Err)
    }

    /// Lowers a link stated in words and registers it under its printed
    /// form.
    fn truth_link(&mut self, spec: &LinkSpec) -> Result<(), String> {
        let key = canonical(&spec.lhs, &self.vocabulary)?;
        let of = doc_latex::parse_expr_with(&spec.of, &self.vocabulary)
            .map_err(|e| format!("cannot read `of`: {} at `{}`", e.kind, e.fragment))?;
        let of = Lowering::new(&mut self.resolver(None), false)
            .expr(&of)
            .map_err(|e| format!("`of`: {e}"))?;
        let wrt = doc_latex::parse_expr_with(&spec.wrt, &self.vocabulary)
            .map_err(|e| format!("cannot read `wrt`: {} at `{}`", e.kind, e.fragment))?;
        let variable = self.variable_of(None, &wrt, spec.side, false)?;
        if matches!(variable, Variable::Update { .. }) {
            return Err("a link stated in words differentiates by a symbol, not an update".into());
        }
        let output = spec.output.map(|s| match s {
            Side::Left => Perturbation::Left,
            Side::Right => Perturbation::Right,
        });
        let mut holding = Vec::with_capacity(spec.holding.len());
        for held in &spec.holding {
            let written = canonical_symbol(held, &self.vocabulary)?;
            holding.push(
                self.lookup(None, &written)
                    .ok_or_else(|| format!("`holding`: `{held}` is not defined"))?,
            );
        }
        self.truth_links.push(TruthLink {
            key: key.clone(),
            of,
            variable,
            output,
            broken: None,
            inline: None,
            holding,
        });
        Ok(())
    }

    /// A derivative printed inside a formula that no claim or stated link
    /// names (`R \frac{\partial}{\partial\omega}(e^{[\omega]_\times} p)`):
    /// the true derivative of what it prints, read in `scope`, registered
    /// as a link of its own (the same printed derivative in the same
    /// scope is one link).
    fn inline_link(&mut self, scope: Scope, d: PrintedDerivative<'_>) -> Result<Link, LowerError> {
        let PrintedDerivative {
            key,
            of,
            wrt,
            holding,
            bound,
            at_zero,
        } = d;
        // The same derivative under other bars is another link.
        let bars_of = |t: &Term| match t {
            Term::At { bindings, .. } => bindings.clone(),
            _ => Vec::new(),
        };
        if let Some(k) = self
            .truth_links
            .iter()
            .position(|l| l.inline == Some(scope) && l.key == key && bars_of(&l.of) == bound)
        {
            return Ok(Link::Truth(k));
        }
        if *of == Expr::Placeholder {
            return Err(LowerError::at(of, "a derivative of nothing"));
        }
        let by_expression = self
            .by_expression(scope, of, wrt)
            .map_err(|m| LowerError::at(wrt, m))?;
        let (of, wrt) = match &by_expression {
            Some((of, wrt)) => (of, wrt),
            None => (of, wrt),
        };
        let mut of = Lowering::new(&mut self.resolver(scope), false).expr(of)?;
        if !bound.is_empty() {
            of = Term::At {
                body: Box::new(of),
                bindings: bound.to_vec(),
            };
        }
        let variable = self
            .variable_of(scope, wrt, None, at_zero)
            .map_err(|m| LowerError::at(wrt, m))?;
        if matches!(variable, Variable::Update { .. }) {
            return Err(LowerError::at(
                wrt,
                "a derivative printed in a formula is taken by a symbol, not an update",
            ));
        }
        // What the derivative moves is never held (`ω` in `∂e(ω, θ)/∂{ω_x,
        // ω_y, ω_z, θ}`).
        let holding = holding
            .iter()
            .filter_map(|h| match h {
                Expr::Symbol(s) => self.lookup(scope, &symbol_key(s)),
                other => self.lookup(scope, &other.to_string()),
            })
            .filter(|id| !self.moves(&variable, self.alias_of(*id)))
            .collect();
        self.truth_links.push(TruthLink {
            key: key.to_string(),
            of,
            variable,
            output: None,
            broken: None,
            inline: Some(scope),
            holding,
        });
        Ok(Link::Truth(self.truth_links.len() - 1))
    }

    /// A derivative by an expression no symbol names (`∂(T⁻¹ p)/∂(T⁻¹)`,
    /// `∂(A B)/∂(A B)`): `of` with the expression replaced by a symbol of
    /// its own, defined as it in `scope`, and that symbol; `None` when
    /// `wrt` is a variable already; an error when `of` does not print it.
    pub fn by_expression(
        &mut self,
        scope: Scope,
        of: &Expr,
        wrt: &Expr,
    ) -> Result<Option<(Expr, Expr)>, String> {
        let named = match wrt {
            Expr::Symbol(s) => self.lookup(scope, &symbol_key(s)).is_some(),
            Expr::Tuple(_) => true,
            other => self.lookup(scope, &other.to_string()).is_some(),
        };
        if named {
            return Ok(None);
        }
        let mut places: Vec<super::tree::Path> = super::tree::nodes(of)
            .into_iter()
            .filter(|(_, node)| *node == wrt)
            .map(|(path, _)| path)
            .collect();
        if places.is_empty() || matches!(wrt, Expr::Symbol(_)) {
            return Ok(None);
        }
        // A symbol of its own, whose key nothing of the document uses.
        let name = (1..)
            .map(|k| format!("\\mathsf{{d}}_{{{k}}}"))
            .find(|n| {
                canonical_symbol(n, &self.vocabulary)
                    .is_ok_and(|key| self.lookup(scope, &key).is_none())
            })
            .expect("a free name");
        let id = self
            .declare(scope, &name, None)
            .map_err(|e| e.to_string())?;
        self.states[id] = State::Pending(Box::new(wrt.clone()), scope);
        let symbol = doc_latex::parse_expr(&name).map_err(|e| e.to_string())?;
        let mut substituted = of.clone();
        places.sort_by(|a, b| b.cmp(a));
        for path in places {
            if let Some(node) = super::tree::at_mut(&mut substituted, &path) {
                *node = symbol.clone();
            }
        }
        self.lower_pending(id).map_err(|e| e.to_string())?;
        Ok(Some((substituted, symbol)))
    }

    /// Sets the input size of every tangent perturbing a definition or by
    /// an update, from a sample: `dim_of` gives a symbol's value's shape
    /// and its tangent dimension.
    pub fn shape_defined(
        &mut self,
        dim_of: impl Fn(&Self, SymbolId) -> Result<((usize, usize), usize), String>,
    ) -> Result<(), TextError> {
        for id in 0..self.table.entries.len() {
            let target = match &self.table.entries[id].meaning {
                Meaning::Tangent {
                    variable: Variable::Defined { symbol, .. } | Variable::Update { symbol, .. },
                    ..
                } => *symbol,
                _ => continue,
            };
            let key = self.table.key(id).to_string();
            let (shape, dim) = dim_of(self, target).map_err(|m| symbol_error(&key, None, m))?;
            if let Meaning::Tangent {
                variable, parts, ..
            } = &mut self.table.entries[id].meaning
            {
                match variable {
                    Variable::Defined { shape: s, .. } => *s = shape,
                    Variable::Update { dim: d, .. } => *d = dim,
                    _ => {}
                }
                if !parts.is_empty() && variable.dim() % parts.len() != 0 {
                    return Err(symbol_error(
                        &key,
                        None,
                        format!(
                            "{} coordinates cannot be cut in {} equal parts",
                            variable.dim(),
                            parts.len()
                        ),
                    ));
                }
            }
        }
        // A link whose variable cannot be sized is broken: the claims
        // using it cannot be read.
        for k in 0..self.truth_links.len() {
            let mut variable = self.truth_links[k].variable.clone();
            if let Err(m) = size_defined(&mut variable, &|symbol| {
                dim_of(self, symbol).map(|(shape, _)| shape)
            }) {
                self.truth_links[k].broken = Some(m);
            }
            self.truth_links[k].variable = variable;
        }
        Ok(())
    }

    /// A lowering of formulas in `scope`.
    pub fn resolver(&mut self, scope: Scope) -> ScopeResolver<'_> {
        ScopeResolver { ctx: self, scope }
    }

    /// One sample: the factor's stored scalars, then each free variable's.
    pub fn sample(&self, s: &mut Sampler) -> Vec<f64> {
        let mut stored = self.factor.map(|f| f.sample(s)).unwrap_or_default();
        for (sample, _) in &self.free {
            stored.extend(sample.draw(s));
        }
        stored
    }

    fn link_of(&self, scope: Scope, key: &str) -> Option<Link> {
        if let Some(k) = self.links.get(key) {
            return Some(Link::Claim(*k));
        }
        if let Some(k) = self
            .truth_links
            .iter()
            .position(|l| l.key == key && l.inline.is_none_or(|s| s == scope))
        {
            return Some(Link::Truth(k));
        }
        self.link_errors.get(key).map(|m| Link::Broken(m.clone()))
    }

    fn template_of(&self, scope: Scope, key: &str) -> Option<usize> {
        self.template_keys
            .get(&operator_key(key))
            .copied()
            .or_else(|| {
                self.lookup(scope, key)
                    .and_then(|id| match self.table.entries[id].meaning {
                        Meaning::Template(t) => Some(t),
                        _ => None,
                    })
            })
    }
}

/// Sets the shape of every definition `variable` perturbs (one, or each
/// of several together) from `shape_of`.
fn size_defined(
    variable: &mut Variable,
    shape_of: &dyn Fn(SymbolId) -> Result<(usize, usize), String>,
) -> Result<(), String> {
    match variable {
        Variable::Defined { symbol, shape, .. } => *shape = shape_of(*symbol)?,
        Variable::Joint(parts) => {
            for part in parts {
                size_defined(part, shape_of)?;
            }
        }
        Variable::Stored { .. } | Variable::Update { .. } => {}
    }
    Ok(())
}

/// The symbols a definition stacks in a column (`[x; y]`, `(x, y)`), when
/// it is only that.
fn stacked_symbols(t: &Term) -> Option<Vec<SymbolId>> {
    let entries: Vec<&Term> = match t {
        Term::Blocks(rows) if rows.len() > 1 && rows.iter().all(|r| r.len() == 1) => {
            rows.iter().map(|r| &r[0]).collect()
        }
        Term::Stack(items) if items.len() > 1 => items.iter().collect(),
        _ => return None,
    };
    entries
        .into_iter()
        .map(|e| match e {
            Term::Symbol(id) => Some(*id),
            _ => None,
        })
        .collect()
}

/// The LaTeX names of a factor's stored scalars: each field named by the
/// symbol the context binds to the whole field (its layout's names as
/// subscripts), else by its layout path.
fn stored_names_of(layout: &Layout, spec: &ContextSpec, factor: FactorKind) -> Vec<String> {
    let mut names: Vec<String> = layout
        .names()
        .iter()
        .map(|n| format!("\\mathrm{{{}}}", n.replace('_', "\\_")))
        .collect();
    let mut offset = 0;
    for field in factor.fields() {
        let symbol = spec.symbols.iter().find_map(|(written, v)| {
            match SymbolSpec::read(written, v).ok()? {
                SymbolSpec::Field { path, .. } if path == field.name => Some(written),
                _ => None,
            }
        });
        if let Some(symbol) = symbol {
            let field_names = layout_names(&field.layout, symbol);
            names[offset..offset + field.scalars].clone_from_slice(&field_names);
        }
        offset += field.scalars;
    }
    names
}

/// [`stored_names`] for a layout known only at run time.
fn layout_names(layout: &Layout, symbol: &str) -> Vec<String> {
    match Kind::of(layout) {
        Kind::Pose => stored_names::<factor_core::lie::Se3<f64>>(symbol),
        Kind::Rotation => stored_names::<factor_core::lie::So3<f64>>(symbol),
        _ => {
            let n = layout.names();
            if n.len() == 1 {
                vec![symbol.to_string()]
            } else {
                n.iter()
                    .map(|n| format!("{symbol}_{{{}}}", n.replace('_', "\\_")))
                    .collect()
            }
        }
    }
}

/// The names of a free variable's stored scalars.
fn sampled_names(sample: FreeSample, symbol: &str) -> Vec<String> {
    layout_names(&sample.layout(), symbol)
}

fn symbol_error(symbol: &str, equation: Option<&str>, message: String) -> TextError {
    TextError::Symbol {
        symbol: symbol.to_string(),
        equation: equation.map(str::to_string),
        message,
    }
}

/// Lowering in one scope of a context.
pub struct ScopeResolver<'c> {
    ctx: &'c mut Context,
    scope: Scope,
}

impl Resolver for ScopeResolver<'_> {
    fn symbol(&mut self, key: &str) -> Result<Option<(SymbolId, Found)>, LowerError> {
        let Some(id) = self.ctx.lookup(self.scope, key) else {
            return Ok(None);
        };
        self.ctx.readable(id)?;
        self.ctx.lower_pending(id).map_err(|e| {
            if e.fragment == key {
                e
            } else {
                LowerError {
                    message: format!("the definition of `{key}` cannot be read: {}", e.message),
                    fragment: e.fragment,
                }
            }
        })?;
        Ok(Some((id, found(&self.ctx.table.entries[id].meaning))))
    }

    fn link(&self, key: &str) -> Option<Link> {
        self.ctx.link_of(self.scope, key)
    }

    fn inline_link(&mut self, d: PrintedDerivative<'_>) -> Result<Link, LowerError> {
        self.ctx.inline_link(self.scope, d)
    }

    fn template(&mut self, key: &str) -> Result<Option<(usize, usize)>, LowerError> {
        let Some(t) = self.ctx.template_of(self.scope, key) else {
            return Ok(None);
        };
        self.ctx.lower_template(t)?;
        Ok(Some((t, self.ctx.templates[t].params.len())))
    }

    fn jpl_quaternions(&self) -> bool {
        self.ctx.jpl_quaternions
    }

    fn unreadable_symbols(&self) -> &[String] {
        &self.ctx.unreadable
    }

    fn subscripted(&self, t: usize) -> bool {
        self.ctx.templates[t].subscripted
    }
}

/// Lowering in one scope of a context whose definitions are all lowered
/// (an edited formula, in the erratum search): nothing changes.
pub struct FrozenResolver<'c> {
    /// The context.
    pub ctx: &'c Context,
    /// The scope.
    pub scope: Scope,
}

impl Resolver for FrozenResolver<'_> {
    fn symbol(&mut self, key: &str) -> Result<Option<(SymbolId, Found)>, LowerError> {
        let Some(id) = self.ctx.lookup(self.scope, key) else {
            return Ok(None);
        };
        self.ctx.readable(id)?;
        Ok(Some((id, found(&self.ctx.table.entries[id].meaning))))
    }

    fn link(&self, key: &str) -> Option<Link> {
        self.ctx.link_of(self.scope, key)
    }

    fn template(&mut self, key: &str) -> Result<Option<(usize, usize)>, LowerError> {
        Ok(self
            .ctx
            .template_of(self.scope, key)
            .map(|t| (t, self.ctx.templates[t].params.len())))
    }

    fn jpl_quaternions(&self) -> bool {
        self.ctx.jpl_quaternions
    }

    fn subscripted(&self, t: usize) -> bool {
        self.ctx.templates[t].subscripted
    }
}

/// The symbols a term refers to.
fn symbols_in(t: &Term) -> Vec<SymbolId> {
    let mut out = Vec::new();
    let mut stack = vec![t];
    while let Some(t) = stack.pop() {
        match t {
            Term::Symbol(id) | Term::Quotient { tangent: id, .. } => out.push(*id),
            _ => {}
        }
        stack.extend(t.children());
    }
    out
}

/// What lowering needs to know of a meaning.
fn found(meaning: &Meaning) -> Found {
    match meaning {
        Meaning::Function(b) => Found::Function(*b),
        Meaning::Template(t) => Found::Template(*t),
        Meaning::Tangent { parts, .. } => Found::Tangent(parts.clone()),
        Meaning::Stored { kind, .. } => Found::Stored {
            group: !kind.is_additive(),
        },
        _ => Found::Value,
    }
}
