//! `slamjac eval`: evaluate a factor at a point given as JSON and write the
//! residual and its tangent-space Jacobians as JSON.

use factor_core::{DynLinearization, Factor, FactorError, VariableInfo};
use serde_json::{Map, Value};

use crate::error::CliError;
use crate::input::{Object, QuaternionReading};
use crate::source::read_source;
use crate::strict_json::parse_json;
use crate::{pretty, registry, w_first};

/// How the Jacobians are computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Method {
    /// The checked-in generated kernel of `generated/` (straight-line code,
    /// exact to rounding); dual numbers for a factor without one.
    #[default]
    Generated,
    /// Dual numbers (num-dual) through the generic residual: exact.
    Dual,
    /// Numerical differentiation through each variable's exact retraction
    /// (Ridders' extrapolation of central differences, steps chosen per
    /// coordinate): an independent reference, each block within about 1e-7
    /// of the exact Jacobian; exit 1 when its error estimate does not reach
    /// that.
    Numeric,
}

impl Method {
    /// The name used on the command line and in the output.
    pub fn as_str(self) -> &'static str {
        match self {
            Method::Generated => "generated",
            Method::Dual => "dual",
            Method::Numeric => "numeric",
        }
    }
}

/// Validates `factor` and linearizes it with `method`; a degenerate
/// configuration or a non-finite output is an error. Returns the method
/// actually used: [`Method::Generated`] falls back to [`Method::Dual`] for a
/// factor without a generated kernel (or a build without the `kernels`
/// feature).
pub fn linearize<F: Factor>(
    factor: &F,
    method: Method,
) -> Result<(DynLinearization, Method), FactorError> {
    factor.validate()?;
    let (linearization, used) = match method {
        Method::Generated => match factor.linearize_generated_dyn() {
            Some(result) => (result?, Method::Generated),
            None => (factor.linearize_dual_dyn()?, Method::Dual),
        },
        Method::Dual => (factor.linearize_dual_dyn()?, Method::Dual),
        Method::Numeric => (factor.linearize_numeric_dyn()?, Method::Numeric),
    };
    let variables = F::variables();
    let names: Vec<&str> = variables.iter().map(|v| v.name).collect();
    Ok((linearization.ensure_finite(F::NAME, &names)?, used))
}

/// A factor evaluated at a point.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// The factor's name.
    pub factor: &'static str,
    /// How the Jacobians were computed (the requested method, or dual
    /// numbers when `generated` was requested for a factor without a kernel).
    pub method: Method,
    /// The factor's variables, in declaration order.
    pub variables: Vec<VariableInfo>,
    /// Residual and one Jacobian block per variable.
    pub linearization: DynLinearization,
}

/// Evaluates the request `{"factor", "variables", "constants"}`. A
/// degenerate configuration whose quaternions look written `[w, x, y, z]`
/// gets a hint naming them (see [`w_first`]).
pub fn evaluate(request: &Value, method: Method) -> Result<Evaluation, CliError> {
    let reading = QuaternionReading::default();
    match evaluate_reading(request, method, &reading) {
        Err(CliError::Factor(error @ FactorError::Degenerate { .. })) => {
            Err(w_first::with_hint(error, &reading.read(), |reading| {
                evaluate_reading(request, method, reading)
            }))
        }
        result => result,
    }
}

/// [`evaluate`] without the hint, reading quaternions as `reading` says.
fn evaluate_reading(
    request: &Value,
    method: Method,
    reading: &QuaternionReading,
) -> Result<Evaluation, CliError> {
    let top = Object::top(request, &["factor", "variables", "constants"], reading)?;
    let entry = registry::find(top.string("factor")?, &top.path_of("factor"))?;
    let names = |variables: bool| -> Vec<&'static str> {
        entry
            .json_fields(variables)
            .into_iter()
            .map(|(name, _)| name)
            .collect()
    };
    let variables = top.object("variables", &names(true))?;
    let constants = top.object("constants", &names(false))?;
    let (linearization, method) = (entry.linearize)(&variables, &constants, method)?;
    Ok(Evaluation {
        factor: entry.name,
        method,
        variables: (entry.variables)(),
        linearization,
    })
}

/// Reads the request from `source` (a path, or `-` for standard input),
/// evaluates it and returns the pretty-printed output JSON.
pub fn run(source: &str, method: Method) -> Result<String, CliError> {
    let text = read_source(source)?;
    let request = parse_json(&text, source)?;
    let evaluation = evaluate(&request, method)?;
    Ok(pretty::to_string(&evaluation.to_json()))
}

impl Evaluation {
    /// `{"factor", "method", "residual", "jacobians": {name: rows}, "tangents": {name: words}}`,
    /// variables in declaration order, each Jacobian residual rows × tangent columns.
    pub fn to_json(&self) -> Value {
        let mut jacobians = Map::new();
        let mut tangents = Map::new();
        for (variable, block) in self.variables.iter().zip(&self.linearization.jacobians) {
            let rows: Vec<Value> = block
                .row_iter()
                .map(|row| row.iter().copied().collect::<Vec<f64>>().into())
                .collect();
            jacobians.insert(variable.name.into(), rows.into());
            tangents.insert(variable.name.into(), variable.tangent.into());
        }
        let residual: Vec<f64> = self.linearization.residual.iter().copied().collect();
        let mut out = Map::new();
        out.insert("factor".into(), self.factor.into());
        out.insert("method".into(), self.method.as_str().into());
        out.insert("residual".into(), residual.into());
        out.insert("jacobians".into(), jacobians.into());
        out.insert("tangents".into(), tangents.into());
        out.into()
    }
}
