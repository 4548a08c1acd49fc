//! The table of factors the command line knows.
//!
//! Registering a factor is one line in [`factors`]: its JSON form comes
//! from its fields' storage ([`crate::decode`]).

use factor_core::{DynLinearization, Factor, FieldInfo, VariableInfo};
use slam_factors::{
    BetweenFactor, FreeLineFactor, G2oLineEdge, G2oPlaneEdge, G2oSe3Edge, LineObservation,
    LineReprojection, PlaneFactor, PluckerLineReprojection, PointReprojection, SnavelyReprojection,
    StereoReprojection,
};

use crate::decode::{decode, json_shape};
use crate::error::{CliError, InputError};
use crate::field_path::quoted;
use crate::input::Object;
use crate::method::{Method, linearize};

/// One registered factor, its description and how to evaluate it from JSON.
#[derive(Debug, Clone, Copy)]
pub struct FactorEntry {
    /// The `factor` name used in the JSON input ([`factor_core::Factor::NAME`]).
    pub name: &'static str,
    /// Residual dimension (Jacobian rows).
    pub residual_dim: usize,
    /// The variables in declaration order ([`factor_core::Factor::variables`]).
    pub variables: fn() -> Vec<VariableInfo>,
    /// Every field in declaration order ([`factor_core::Factor::fields`]).
    pub fields: fn() -> Vec<FieldInfo>,
    /// The generated kernel `eval --method generated` uses
    /// ([`factor_core::Factor::KERNEL`]), if any.
    pub kernel: Option<&'static str>,
    /// Reads the factor from its checked `variables` and `constants` objects,
    /// validates it and linearizes it with the given method; returns the
    /// method used (see [`linearize`]).
    pub linearize: LinearizeFn,
}

/// How a [`FactorEntry`] evaluates: checked `variables` and `constants`
/// objects and the requested method → the linearization and the method used.
pub type LinearizeFn = fn(&Object, &Object, Method) -> Result<(DynLinearization, Method), CliError>;

impl FactorEntry {
    /// The entry of factor `F`.
    pub fn of<F: Factor>() -> Self {
        FactorEntry {
            name: F::NAME,
            residual_dim: F::RESIDUAL_DIM,
            variables: F::variables,
            fields: F::fields,
            kernel: F::KERNEL,
            linearize: |variables, constants, method| {
                let factor: F = decode(variables, constants)?;
                Ok(linearize(&factor, method)?)
            },
        }
    }
}

impl FactorEntry {
    /// The fields of `variables` (`true`) or `constants` (`false`), each
    /// with its JSON shape.
    pub fn json_fields(&self, variables: bool) -> Vec<(&'static str, String)> {
        (self.fields)()
            .into_iter()
            .filter(|field| field.variable.is_some() == variables)
            .map(|field| (field.name, json_shape(&field.input_layout)))
            .collect()
    }
}

/// Every registered factor, in the order `list` shows them.
pub fn factors() -> Vec<FactorEntry> {
    vec![
        FactorEntry::of::<PointReprojection>(),
        FactorEntry::of::<LineReprojection>(),
        FactorEntry::of::<PlaneFactor>(),
        FactorEntry::of::<FreeLineFactor>(),
        FactorEntry::of::<PluckerLineReprojection>(),
        FactorEntry::of::<LineObservation>(),
        FactorEntry::of::<SnavelyReprojection>(),
        FactorEntry::of::<StereoReprojection>(),
        FactorEntry::of::<BetweenFactor>(),
        FactorEntry::of::<G2oSe3Edge>(),
        FactorEntry::of::<G2oLineEdge>(),
        FactorEntry::of::<G2oPlaneEdge>(),
    ]
}

/// The factor called `name`; the error (at field path `path`) lists the known ones.
pub fn find(name: &str, path: &str) -> Result<FactorEntry, InputError> {
    let all = factors();
    all.iter().find(|f| f.name == name).copied().ok_or_else(|| {
        let known: Vec<&str> = all.iter().map(|f| f.name).collect();
        InputError::new(
            path,
            format!(
                "unknown factor {}; known factors: {}",
                quoted(name),
                known.join(", ")
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_fields_follow_the_declared_variables() {
        for entry in factors() {
            let declared: Vec<&str> = (entry.variables)().iter().map(|v| v.name).collect();
            let fields: Vec<&str> = entry
                .json_fields(true)
                .iter()
                .map(|(name, _)| *name)
                .collect();
            assert_eq!(declared, fields, "{}", entry.name);
        }
    }

    #[test]
    fn unknown_factors_list_the_known_ones() {
        let error = find("nope", "factor").unwrap_err();
        assert_eq!(error.path, "factor");
        assert!(
            error
                .message
                .contains("point_reprojection, line_reprojection, plane, free_line")
        );
    }
}
