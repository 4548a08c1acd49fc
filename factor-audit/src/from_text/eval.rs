//! Evaluating lowered terms at one sample, over any scalar: `f64` for the
//! printed formula, dual numbers for the truth (and for a printed
//! first-order claim), the symbolic engine for the corrected expression.

use nalgebra::DMatrix;

use super::factors::FactorKind;
use super::term::{Meaning, Op, SymbolId, Table, Template, Term, Variable};
use super::value::{Blocks, ShapeError, Value, shape_text};
use factor_core::scalar::Scalar;

/// Deepest nesting of terms and definitions evaluated (hostile nesting is
/// an error, not a stack overflow).
pub const MAX_EVAL_DEPTH: usize = 400;

/// What a context's terms are evaluated in: its symbol table, the printed
/// formulas of its claims (for chain-rule links) and its factor.
#[derive(Debug, Clone, Copy)]
pub struct Space<'a> {
    /// The symbols.
    pub table: &'a Table,
    /// The printed formula of each claim of the file (by claim index), for
    /// the ones in this context.
    pub printed: &'a [Option<Term>],
    /// The factor whose residual `residual` symbols are.
    pub factor: Option<FactorKind>,
    /// The operators and functions the context defines.
    pub templates: &'a [Template],
}

/// Sizes the block matrices of a product that their own blocks leave
/// unsized (`[𝒦 0]`) from the matrices next to them (scalars skipped).
fn size_by_neighbours<S: Scalar>(values: &mut [Value<S>], factors: &[(Op, Term)]) {
    let matrix_shape = |v: &Value<S>| v.shape().filter(|s| *s != (1, 1));
    for i in 0..values.len() {
        if !matches!(values[i], Value::Blocks(_)) {
            continue;
        }
        let multiplies = |k: usize| {
            factors
                .get(k)
                .is_some_and(|(op, _)| matches!(op, Op::Mul | Op::Dot))
        };
        let left = (0..i)
            .rev()
            .take_while(|k| multiplies(k + 1))
            .find_map(|k| matrix_shape(&values[k]).map(|s| s.1));
        let right = (i + 1..values.len())
            .take_while(|k| multiplies(*k))
            .find_map(|k| matrix_shape(&values[k]).map(|s| s.0));
        if let Value::Blocks(b) = &values[i]
            && let Ok(m) = b.clone().resolve((left, right))
        {
            values[i] = Value::Matrix(m);
        }
    }
}

/// One sample's values, over scalar `S`.
pub struct Env<'a, S: Scalar> {
    space: Space<'a>,
    stored: Vec<S>,
    bound: Vec<Option<Value<S>>>,
    memo: Vec<Option<Value<S>>>,
    depth: usize,
    /// The values at this sample of the links stated in words, when the
    /// caller computed them (by context link index).
    truths: Vec<Option<DMatrix<S>>>,
    /// Where a variable expanded about zero is: `0`, or [`NEAR_ZERO`] in
    /// each entry when the map is not finite at zero itself.
    zero: S,
}

/// Where a variable expanded about zero is put when a map has a removable
/// singularity there (`k̂ sin(θ/2)` with `k̂ = θ/|θ|`): close enough that
/// values and derivatives there agree with their limits at zero to far
/// below the audit's tolerance.
pub const NEAR_ZERO: f64 = 1e-9;

fn fail<T>(message: impl Into<String>) -> Result<T, ShapeError> {
    Err(ShapeError(message.into()))
}

/// The step of the central differences a limit of a difference quotient
/// is evaluated with.
pub const LIMIT_STEP: f64 = 1e-3;

impl<'a, S: Scalar> Env<'a, S> {
    /// The sample whose stored scalars are `stored`.
    pub fn new(space: Space<'a>, stored: Vec<S>) -> Self {
        let n = space.table.entries.len();
        Env {
            space,
            stored,
            bound: vec![None; n],
            memo: vec![None; n],
            depth: 0,
            truths: Vec::new(),
            zero: S::zero(),
        }
    }

    /// The sample with variables expanded about zero put at [`NEAR_ZERO`].
    pub fn near_zero(mut self, near: bool) -> Self {
        if near {
            self.zero = S::from_f64(NEAR_ZERO);
        }
        self
    }

    /// The sample with the values of the links stated in words.
    pub fn with_truths(mut self, truths: Vec<Option<DMatrix<S>>>) -> Self {
        self.truths = truths;
        self
    }

    /// Binds a symbol to a value (every derived value is recomputed).
    pub fn bind(&mut self, id: SymbolId, value: Value<S>) {
        self.bound[id] = Some(value);
        self.memo.iter_mut().for_each(|m| *m = None);
    }

    /// Perturbs the variable by the input `x` (see [`Variable`]).
    pub fn perturb(&mut self, v: &Variable, x: &[S]) -> Result<(), ShapeError> {
        match v {
            Variable::Stored {
                offset,
                kind,
                side,
                coordinates,
                at_zero,
            } => {
                let mut delta = vec![S::zero(); kind.tangent_dim()];
                for (c, xi) in coordinates.iter().zip(x) {
                    delta[*c] = *xi;
                }
                let range = *offset..offset + kind.scalars();
                let base: Vec<S> = if *at_zero {
                    vec![self.zero; kind.scalars()]
                } else {
                    self.stored[range.clone()].to_vec()
                };
                let moved = kind.retract(&base, &delta, *side);
                self.stored[range].copy_from_slice(&moved);
                self.memo.iter_mut().for_each(|m| *m = None);
            }
            Variable::Defined {
                symbol,
                shape,
                at_zero,
            } => {
                let increment = DMatrix::from_column_slice(shape.0, shape.1, x);
                let mut base = if *at_zero {
                    DMatrix::from_element(shape.0, shape.1, self.zero)
                } else {
                    self.symbol(*symbol)?.sized((None, Some(shape.1)))?
                };
                // A homogeneous transformation moves in its top rows only.
                if base.ncols() != shape.1 || base.nrows() < shape.0 {
                    return fail(format!(
                        "a {} value perturbed by a {} increment",
                        shape_text(base.shape()),
                        shape_text(*shape)
                    ));
                }
                let mut top = base.rows_mut(0, shape.0);
                top += increment;
                self.bind(*symbol, Value::Matrix(base));
            }
            Variable::Update {
                symbol,
                update,
                delta,
                ..
            } => {
                self.bind(*delta, Value::column(x));
                let value = self.eval(update)?;
                self.bind(*symbol, value);
            }
            Variable::Joint(parts) => {
                // Independent arguments: each defined one keeps its value
                // while the others move (`θ` beside `ω` though `θ = ‖ω‖`).
                for part in parts {
                    if let Variable::Defined { symbol, .. } = part {
                        let value = self.symbol(*symbol)?;
                        self.bind(*symbol, value);
                    }
                }
                let mut at = 0;
                for part in parts {
                    let n = part.dim();
                    let piece = x.get(at..at + n).ok_or_else(|| {
                        ShapeError("the input is shorter than the variables".into())
                    })?;
                    self.perturb(part, piece)?;
                    at += n;
                }
            }
        }
        Ok(())
    }

    /// The value of `t`.
    pub fn eval(&mut self, t: &Term) -> Result<Value<S>, ShapeError> {
        self.depth += 1;
        let result = if self.depth > MAX_EVAL_DEPTH {
            fail(format!(
                "terms and definitions nest deeper than {MAX_EVAL_DEPTH} levels"
            ))
        } else {
            self.eval_inner(t)
        };
        self.depth -= 1;
        result
    }

    fn eval_inner(&mut self, t: &Term) -> Result<Value<S>, ShapeError> {
        match t {
            Term::Number(x) => Ok(Value::scalar(S::from_f64(*x))),
            Term::Symbol(id) => self.symbol(*id),
            Term::Neg(x) => self.eval(x)?.negated(),
            Term::Sum(terms) => {
                let mut acc = Value::Zero;
                for (minus, x) in terms {
                    acc = acc.add(self.eval(x)?, *minus)?;
                }
                Ok(acc)
            }
            Term::Product(factors) => {
                let mut values = Vec::with_capacity(factors.len());
                for (_, x) in factors {
                    values.push(self.eval(x)?);
                }
                size_by_neighbours(&mut values, factors);
                let mut acc: Option<Value<S>> = None;
                for ((op, _), v) in factors.iter().zip(values) {
                    acc = Some(match acc {
                        None => v,
                        Some(a) => match op {
                            Op::Mul => a.times(v)?,
                            Op::Dot => a.dot(v)?,
                            Op::Cross => a.cross(v)?,
                            Op::Oplus { jpl } => a.oplus(v, *jpl)?,
                            Op::Otimes { jpl } => a.otimes(v, *jpl)?,
                            Op::Div => a.divided_by(v)?,
                        },
                    });
                }
                acc.ok_or_else(|| ShapeError("an empty product".into()))
            }
            Term::Fraction { num, den, stack } => {
                let (n, d) = (self.eval(num)?, self.eval(den)?);
                if *stack {
                    Blocks::build(vec![vec![n], vec![d]])
                } else {
                    n.divided_by(d)
                }
            }
            Term::Power(x, p) => self.eval(x)?.power(*p),
            Term::Norm(x) => self.eval(x)?.norm(),
            Term::Hat(x) => self.eval(x)?.hat(),
            Term::Vee(x) => self.eval(x)?.vee(),
            Term::Transpose(x) => self.eval(x)?.transpose(),
            Term::Call(b, args) => {
                let values = args
                    .iter()
                    .map(|a| self.eval(a))
                    .collect::<Result<Vec<_>, _>>()?;
                b.apply(values)
            }
            Term::Blocks(rows) => {
                let mut values = Vec::with_capacity(rows.len());
                for row in rows {
                    values.push(
                        row.iter()
                            .map(|x| self.eval(x))
                            .collect::<Result<Vec<_>, _>>()?,
                    );
                }
                Blocks::build(values)
            }
            Term::Zero => Ok(Value::Zero),
            Term::BlockZero(rows, cols) => Ok(Value::BlockZero(*rows, *cols)),
            Term::Identity(None) => Ok(Value::Identity(S::one())),
            Term::Identity(Some(n)) => Value::Identity(S::one())
                .sized((Some(*n), Some(*n)))
                .map(Value::Matrix),
            Term::Shaped(x, (r, c)) => {
                let m = self.eval(x)?.sized((Some(*r), Some(*c)))?;
                if m.shape() != (*r, *c) {
                    return fail(format!(
                        "printed as {} but it is {}",
                        shape_text((*r, *c)),
                        shape_text(m.shape())
                    ));
                }
                Ok(Value::Matrix(m))
            }
            Term::Stack(items) => {
                let mut values = Vec::with_capacity(items.len());
                for x in items {
                    values.push(self.eval(x)?);
                }
                // `[I, -P^]`: items with several columns are a block row;
                // vectors and scalars stack in a column.
                if values.iter().any(|v| v.shape().is_some_and(|(_, c)| c > 1)) {
                    Blocks::build(vec![values])
                } else {
                    Blocks::build(values.into_iter().map(|v| vec![v]).collect())
                }
            }
            Term::Quotient {
                numerator,
                tangent,
                limit,
            } => self.quotient(numerator, *tangent, *limit),
            Term::Link(k) => {
                let printed = self.space.printed;
                match printed.get(*k).and_then(Option::as_ref) {
                    // A differential linked inside a differential by the
                    // same tangent (`D_2 g(ξ)` in `D_1 f(ξ) = …`): its value
                    // at the direction being taken, not its matrix.
                    Some(Term::Quotient {
                        numerator, tangent, ..
                    }) if self.bound.get(*tangent).is_some_and(Option::is_some) => {
                        self.eval(numerator)
                    }
                    Some(term) => self.eval(term),
                    None => fail("a chain rule's link has no printed formula"),
                }
            }
            Term::TruthLink(k) => match self.truths.get(*k).and_then(Option::as_ref) {
                Some(m) => Ok(Value::Matrix(m.clone())),
                None => fail(
                    "a link stated in words is evaluated only in a printed formula's own claim",
                ),
            },
            Term::Template(t, args) => self.template(*t, args),
            Term::At { body, bindings } => {
                let mut values = Vec::with_capacity(bindings.len());
                for (id, t) in bindings {
                    values.push((*id, self.eval(t)?));
                }
                let saved = (self.bound.clone(), self.memo.clone());
                for (id, v) in values {
                    self.bind(id, v);
                }
                let result = self.eval(body);
                (self.bound, self.memo) = saved;
                result
            }
        }
    }

    /// A template applied: its arguments bound, its body evaluated.
    fn template(&mut self, t: usize, args: &[Term]) -> Result<Value<S>, ShapeError> {
        let templates = self.space.templates;
        let template = &templates[t];
        if args.len() != template.params.len() {
            return fail(format!(
                "`{}` takes {} argument(s)",
                template.key,
                template.params.len()
            ));
        }
        let mut values = Vec::with_capacity(args.len());
        for a in args {
            values.push(self.eval(a)?);
        }
        let saved = (self.bound.clone(), self.memo.clone());
        for (p, v) in template.params.iter().zip(values) {
            self.bind(*p, v);
        }
        let result = self.eval(&template.body);
        (self.bound, self.memo) = saved;
        result
    }

    /// `X / δξ`: columns `X(e_j) − X(0)` over the unit tangents `e_j`; under
    /// a limit, the derivative of `X` at zero, column by column (central
    /// differences at `h` and `h/2`, Richardson-extrapolated: the error is
    /// `O(h⁴)`).
    fn quotient(
        &mut self,
        numerator: &Term,
        tangent: SymbolId,
        limit: bool,
    ) -> Result<Value<S>, ShapeError> {
        let table = self.space.table;
        let Meaning::Tangent { variable, parts } = &table.entries[tangent].meaning else {
            return fail("a difference quotient over something that is not a tangent");
        };
        let n = variable.dim();
        let slots: Vec<SymbolId> = if parts.is_empty() {
            vec![tangent]
        } else {
            parts.clone()
        };
        if n % slots.len() != 0 {
            return fail(format!(
                "a tangent of {n} coordinates cannot be cut in {} equal parts",
                slots.len()
            ));
        }
        let width = n / slots.len();
        let saved = (self.bound.clone(), self.memo.clone());
        let at =
            |env: &mut Self, unit: Option<usize>, step: f64| -> Result<DMatrix<S>, ShapeError> {
                for (k, slot) in slots.iter().enumerate() {
                    let part: Vec<S> = (0..width)
                        .map(|i| {
                            if unit == Some(k * width + i) {
                                S::from_f64(step)
                            } else {
                                S::zero()
                            }
                        })
                        .collect();
                    env.bind(*slot, Value::column(&part));
                }
                // A matrix numerator (a differential printed in the algebra)
                // is read column by column, as a map's matrix value is.
                let v = env.eval(numerator)?.matrix()?;
                Ok(DMatrix::from_column_slice(v.len(), 1, v.as_slice()))
            };
        let result = (|| {
            if limit {
                let mut columns = Vec::with_capacity(n);
                for j in 0..n {
                    let central = |env: &mut Self, h: f64| -> Result<DMatrix<S>, ShapeError> {
                        let d = at(env, Some(j), h)? - at(env, Some(j), -h)?;
                        Ok(d.map(|v| v / S::from_f64(2.0 * h)))
                    };
                    let (coarse, fine) =
                        (central(self, LIMIT_STEP)?, central(self, LIMIT_STEP / 2.0)?);
                    let rows = coarse.nrows();
                    if fine.nrows() != rows {
                        return fail("the numerator changes its size with the tangent");
                    }
                    columns.push(
                        (fine.map(|v| v * S::from_f64(4.0)) - coarse).map(|v| v / S::from_f64(3.0)),
                    );
                }
                let rows = columns.first().map_or(0, |c| c.nrows());
                let mut out = DMatrix::zeros(rows, n);
                for (j, c) in columns.iter().enumerate() {
                    if c.nrows() != rows {
                        return fail("the numerator changes its size with the tangent");
                    }
                    out.set_column(j, &c.column(0));
                }
                return Ok(Value::Matrix(out));
            }
            let zero = at(self, None, 1.0)?;
            let mut out = DMatrix::zeros(zero.nrows(), n);
            for j in 0..n {
                let column = at(self, Some(j), 1.0)? - &zero;
                out.set_column(j, &column.column(0));
            }
            Ok(Value::Matrix(out))
        })();
        (self.bound, self.memo) = saved;
        result
    }

    /// The value of symbol `id`.
    pub fn symbol(&mut self, id: SymbolId) -> Result<Value<S>, ShapeError> {
        if let Some(v) = &self.bound[id] {
            return Ok(v.clone());
        }
        if let Some(v) = &self.memo[id] {
            return Ok(v.clone());
        }
        let table = self.space.table;
        let entry = &table.entries[id];
        let value = match &entry.meaning {
            Meaning::Stored { offset, kind } => {
                kind.value(&self.stored[*offset..offset + kind.scalars()])?
            }
            Meaning::Definition(t) => self.eval(t)?,
            Meaning::Component { of, index } => {
                let v = self.symbol(*of)?.matrix()?;
                if v.ncols() != 1 || *index >= v.nrows() {
                    return fail(format!(
                        "`{}` is entry {} of `{}`, which is {}",
                        entry.key,
                        index + 1,
                        table.key(*of),
                        Value::Matrix(v).describe()
                    ));
                }
                Value::scalar(v[(*index, 0)])
            }
            Meaning::Residual(components) => {
                let Some(factor) = self.space.factor else {
                    return fail(format!(
                        "`{}` is a residual, but the context has no factor",
                        entry.key
                    ));
                };
                let r = factor.residual(&self.stored);
                let picked: Vec<S> = components.iter().map(|c| r[*c]).collect();
                Value::column(&picked)
            }
            Meaning::Function(_) | Meaning::Template(_) => {
                return fail(format!(
                    "`{}` is a function: apply it to an argument",
                    entry.key
                ));
            }
            Meaning::Tangent { .. } => {
                return fail(format!(
                    "`{}` is a perturbation: it has a value only in a difference quotient over it",
                    entry.key
                ));
            }
            Meaning::Bound | Meaning::Pending => {
                return fail(format!("`{}` has no value here", entry.key));
            }
            Meaning::Broken(why) => {
                return fail(format!("`{}` cannot be read: {why}", entry.key));
            }
        };
        self.memo[id] = Some(value.clone());
        Ok(value)
    }
}
