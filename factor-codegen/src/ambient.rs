//! The ambient kernel: the residual and its Jacobian w.r.t. every
//! variable's stored scalars, each perturbed additively (`x + δ`), what a
//! solver that applies a manifold's `PlusJacobian` itself wants from a cost
//! function (Ceres: `residuals × ambient size`, row-major).
//!
//! A variable's stored scalars may then leave its manifold (a quaternion of
//! norm `1 + δ`); the residual is evaluated there as written, and any
//! smooth extension gives the same Jacobian in every tangent direction: the
//! ambient block times the manifold's `PlusJacobian` is the block in that
//! manifold's chart. Traced, formed in the cheapest exact form and compiled
//! as the factor's own kernel ([`crate::kernel`]).

use std::collections::HashMap;

use factor_core::{Factor, VariableInfo};
use factor_symbolic::trace::Traced;
use factor_symbolic::{Expr, Tracer};

use crate::kernel::{BlockOrder, SymbolicKernel, assemble};

/// What an ambient block's columns are, for reports.
const AMBIENT_TANGENT: &str =
    "ambient: the stored scalars, additively (x ← x + δ), columns in storage order";

/// Traces factor `F`'s ambient kernel: inputs are its stored scalars as for
/// its own kernel; one block per variable, `residual rows × stored scalars`,
/// row-major.
pub fn trace_ambient<F: Factor>() -> SymbolicKernel {
    let tracer = Tracer::new();
    let fields = F::fields();
    let input_len = u32::try_from(F::SCALARS).expect("fewer than 2³² inputs");
    let mut stored: Vec<Expr> = (0..input_len).map(Expr::input).collect();
    let mut delta = Vec::new();
    let mut variables: Vec<VariableInfo> = F::variables();
    let mut offset = 0;
    for field in &fields {
        if let Some(variable) = field.variable {
            for scalar in &mut stored[offset..offset + field.scalars] {
                let d = Expr::input(input_len + delta.len() as u32);
                delta.push(d);
                *scalar += d;
            }
            let info = &mut variables[variable];
            info.tangent_dim = field.scalars;
            info.tangent = AMBIENT_TANGENT;
        }
        offset += field.scalars;
    }
    let residual = F::residual_over(&stored);
    let at_zero: HashMap<Expr, Expr> = delta.iter().map(|d| (*d, Expr::constant(0.0))).collect();
    let traced = Traced {
        residual,
        delta,
        input_len,
        at_zero,
    };
    assemble(
        tracer,
        F::NAME,
        fields,
        variables,
        traced,
        BlockOrder::RowMajor,
    )
}
