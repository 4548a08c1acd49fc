//! `eval`: evaluate a registry's factor at a point given as JSON, the
//! residual and its tangent-space Jacobians as JSON (the command line
//! prints them: `slamjac::eval::run`).

use factor_core::{DynLinearization, FactorError, VariableInfo};
use serde_json::{Map, Value};
use slamjac_problem::document::Json;
use slamjac_problem::input::{Object, QuaternionReading};
use slamjac_problem::w_first;

use crate::error::RegistryError;
use crate::method::Method;
use crate::registry::Registry;

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

/// Evaluates the request `{"factor", "variables", "constants"}` for a
/// factor of `registry`. A degenerate configuration whose quaternions look
/// written `[w, x, y, z]` gets a hint naming them (see
/// [`slamjac_problem::w_first`]).
pub fn evaluate(
    registry: &Registry,
    request: Json<'_>,
    method: Method,
) -> Result<Evaluation, RegistryError> {
    let reading = QuaternionReading::default();
    match evaluate_reading(registry, request, method, &reading) {
        Err(RegistryError::Factor(error @ FactorError::Degenerate { .. })) => {
            // Validation passed when the evaluation succeeded or failed only after it.
            let validates = |reading: &QuaternionReading| {
                matches!(
                    evaluate_reading(registry, request, method, reading),
                    Ok(_) | Err(RegistryError::Factor(FactorError::NonFinite { .. }))
                )
            };
            Err(match w_first::hint(&reading.read(), validates) {
                Some(hint) => RegistryError::Hinted { error, hint },
                None => RegistryError::Factor(error),
            })
        }
        result => result,
    }
}

/// [`evaluate`] without the hint, reading quaternions as `reading` says.
fn evaluate_reading(
    registry: &Registry,
    request: Json<'_>,
    method: Method,
    reading: &QuaternionReading,
) -> Result<Evaluation, RegistryError> {
    let top = Object::top(request, &["factor", "variables", "constants"], reading)?;
    let entry = registry.find(top.string("factor")?, &top.path_of("factor"))?;
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
