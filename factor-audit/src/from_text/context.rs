//! A context of a symbols file, built: its symbol table (the context's
//! symbols and each claim's own readings, in scopes), what samples it, and
//! the lowering of definitions on demand (in dependency order, cycles and
//! over-deep nesting reported).

use std::collections::HashMap;

use doc_latex::ast::Expr;

use super::TextError;
use super::factors::FactorKind;
use super::functions::Builtin;
use super::lower::{Found, LowerError, Lowering, Resolver, symbol_key};
use super::stored::{FreeSample, Kind, part};
use super::symbols::{ContextSpec, MAX_SYMBOLS, Side, SymbolSpec};
use super::term::{Meaning, SymbolId, Table, Term, Variable};
use crate::transcription::stored_names;
use factor_core::manifold::Perturbation;
use factor_core::storage::Layout;
use factor_testing::samples::Sampler;

/// Deepest chain of definitions (a definition using one using one …).
pub const MAX_DEFINITION_DEPTH: usize = 16;

/// Where a symbol is looked up: a claim's own readings first, then the
/// context's.
pub type Scope = Option<usize>;

/// How a definition waits to be lowered.
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
}

/// The canonical LaTeX of a symbol written in the symbols file.
pub fn canonical_symbol(written: &str) -> Result<String, String> {
    match doc_latex::parse_expr(written) {
        Ok(Expr::Symbol(s)) => Ok(symbol_key(&s)),
        Ok(other) => Err(format!("`{other}` is not one symbol")),
        Err(e) => Err(format!("cannot read it: {}", e.kind)),
    }
}

/// The canonical LaTeX of any expression written in the symbols file.
pub fn canonical(written: &str) -> Result<String, String> {
    doc_latex::parse_expr(written)
        .map(|e| e.to_string())
        .map_err(|e| format!("cannot read `{written}`: {} at `{}`", e.kind, e.fragment))
}

impl Context {
    /// The context `name` as `spec` writes it (its claims' readings are
    /// added with [`Context::add_claim_symbols`]).
    pub fn build(name: &str, spec: &ContextSpec) -> Result<Self, TextError> {
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
        let mut names: Vec<String> = factor
            .map(|f| stored_names_of(&f.layout(), spec, f))
            .unwrap_or_default();
        let mut ctx = Context {
            name: name.to_string(),
            factor,
            free: Vec::new(),
            names: Vec::new(),
            table: Table::default(),
            scopes: HashMap::from([(None, HashMap::new())]),
            states: Vec::new(),
            depths: Vec::new(),
            building: 0,
            links: HashMap::new(),
            printed: Vec::new(),
        };
        let mut tangents = Vec::new();
        for (written, value) in &spec.symbols {
            let meaning = SymbolSpec::read(written, value)?;
            let id = ctx.declare(None, written, None)?;
            match meaning {
                SymbolSpec::Sample(s) => {
                    let sample = FreeSample::named(&s).ok_or_else(|| {
                        symbol_error(
                            written,
                            None,
                            format!(
                                "no sampler `{s}` (samplers: {})",
                                FreeSample::ALL.map(|(n, _)| n).join(", ")
                            ),
                        )
                    })?;
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
                }
                other => {
                    if let Some(t) = ctx.meaning(id, written, other, None)? {
                        tangents.push(t);
                    }
                }
            }
        }
        ctx.names = names;
        for (id, written, spec) in tangents {
            ctx.tangent(id, &written, spec, None)?;
        }
        Ok(ctx)
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
            if matches!(meaning, SymbolSpec::Sample(_)) {
                return Err(symbol_error(
                    written,
                    Some(equation),
                    "a claim cannot sample: declare it in its context".into(),
                ));
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
        let key = canonical_symbol(written).map_err(|m| symbol_error(written, equation, m))?;
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
                let e = doc_latex::parse_expr(&latex).map_err(|e| {
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
            SymbolSpec::Field { path, components } => {
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
            SymbolSpec::Sample(_) => unreachable!("sampled symbols are set by the caller"),
            spec @ SymbolSpec::Tangent { .. } => {
                return Ok(Some((id, written.to_string(), spec)));
            }
        }
        Ok(None)
    }

    /// Resolves a tangent: what it perturbs, on which side, which
    /// coordinates, and its parts.
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
            parts,
            coordinates,
        } = spec
        else {
            return Ok(());
        };
        let bad = |m: String| symbol_error(written, equation, m);
        let key = canonical_symbol(&perturbs).map_err(&bad)?;
        let scope = claim.map(|(c, _)| c);
        let target = self
            .lookup(scope, &key)
            .ok_or_else(|| bad(format!("it perturbs `{key}`, which is not defined")))?;
        let variable = self
            .variable(target, side, coordinates.as_deref(), false)
            .map_err(bad)?;
        let mut part_ids = Vec::new();
        for p in &parts {
            let pid = self.declare(scope, p, equation)?;
            self.set(pid, Meaning::Bound);
            part_ids.push(pid);
        }
        if !parts.is_empty() && variable.dim() % parts.len() != 0 {
            return Err(bad(format!(
                "{} coordinates cannot be cut in {} equal parts",
                variable.dim(),
                parts.len()
            )));
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

    /// What a derivative by symbol `target` perturbs: a stored value on a
    /// side (or additively), or a definition additively (its shape is set
    /// by [`Context::shape_defined`] once it can be evaluated).
    pub fn variable(
        &mut self,
        target: SymbolId,
        side: Option<Side>,
        coordinates: Option<&[usize]>,
        at_zero: bool,
    ) -> Result<Variable, String> {
        let target = self.alias_of(target);
        let key = self.table.key(target).to_string();
        match self.table.entries[target].meaning.clone() {
            Meaning::Stored { offset, kind } => {
                let additive = kind.is_additive();
                let side = match (side, additive) {
                    (Some(Side::Left), false) => Perturbation::Left,
                    (Some(Side::Right), false) => Perturbation::Right,
                    (None, false) => {
                        return Err(format!(
                            "`{key}` is perturbed on a side: say `side = \"left\"` or `\"right\"`"
                        ));
                    }
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
    fn lower_pending(&mut self, id: SymbolId) -> Result<(), LowerError> {
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

    /// How deep symbol `id`'s definitions nest.
    fn depth_of(&self, id: SymbolId) -> usize {
        match &self.table.entries[id].meaning {
            Meaning::Component { of, .. } => 1 + self.depths[*of],
            _ => self.depths[id],
        }
    }

    /// Lowers every definition, reporting the first that cannot be.
    pub fn lower_all(
        &mut self,
        equation_of: impl Fn(Scope) -> Option<String>,
    ) -> Result<(), TextError> {
        for id in 0..self.table.entries.len() {
            if let Err(e) = self.lower_pending(id) {
                let scope = self.scope_of(id);
                return Err(TextError::Symbol {
                    symbol: self.table.key(id).to_string(),
                    equation: equation_of(scope),
                    message: e.to_string(),
                });
            }
        }
        Ok(())
    }

    /// Sets the shape of every [`Variable::Defined`] tangent from a sample.
    pub fn shape_defined(
        &mut self,
        shape_of: impl Fn(&Self, SymbolId) -> Result<(usize, usize), String>,
    ) -> Result<(), TextError> {
        for id in 0..self.table.entries.len() {
            if let Meaning::Tangent {
                variable: Variable::Defined { symbol, .. },
                ..
            } = &self.table.entries[id].meaning
            {
                let symbol = *symbol;
                let s = shape_of(self, symbol)
                    .map_err(|m| symbol_error(self.table.key(id), None, m))?;
                if let Meaning::Tangent {
                    variable: Variable::Defined { shape, .. },
                    ..
                } = &mut self.table.entries[id].meaning
                {
                    *shape = s;
                }
            }
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
        self.ctx.lower_pending(id)?;
        Ok(Some((id, found(&self.ctx.table.entries[id].meaning))))
    }

    fn link(&self, key: &str) -> Option<usize> {
        self.ctx.links.get(key).copied()
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
        Ok(self
            .ctx
            .lookup(self.scope, key)
            .map(|id| (id, found(&self.ctx.table.entries[id].meaning))))
    }

    fn link(&self, key: &str) -> Option<usize> {
        self.ctx.links.get(key).copied()
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
        Meaning::Tangent { parts, .. } => Found::Tangent(parts.clone()),
        Meaning::Stored { .. } => Found::Stored,
        _ => Found::Value,
    }
}
