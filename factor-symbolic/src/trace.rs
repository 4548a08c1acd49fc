//! A factor's residual traced over symbols at a symbolic tangent.
//!
//! Each stored scalar of the factor becomes an input symbol, in field order,
//! and the stacked tangent `δ` the inputs after them; the residual is the
//! factor's own generic residual at the first-order retraction of every
//! variable by `δ` ([`factor_core::Manifold::retract_first_order`]). Its
//! derivative at `δ = 0` is the Jacobian ([`crate::jacobian`]). Only the
//! first-order part of a retraction reaches that derivative, so no
//! retraction branch is traced; the residual's own branches are kept.

use std::collections::HashMap;

use factor_core::Factor;

use crate::graph::Expr;

/// A residual traced at the first-order retraction by a symbolic tangent.
pub struct Traced {
    /// The residual over the inputs and `δ`.
    pub residual: Vec<Expr>,
    /// The tangent symbols, inputs after the factor's own scalars.
    pub delta: Vec<Expr>,
    /// Number of the factor's own input scalars.
    pub input_len: u32,
    /// `δ ↦ 0`.
    pub at_zero: HashMap<Expr, Expr>,
}

/// Traces factor type `F`'s residual (inside an active [`crate::Tracer`]):
/// each stored scalar is an input symbol, in storage order, the tangent the
/// inputs after them. No value of the factor is needed, only its type.
pub fn trace_at_tangent<F: Factor>() -> Traced {
    let input_len = u32::try_from(F::SCALARS).expect("fewer than 2³² inputs");
    let inputs: Vec<Expr> = (0..input_len).map(Expr::input).collect();
    let delta: Vec<Expr> = (0..F::TANGENT_DIM as u32)
        .map(|j| Expr::input(input_len + j))
        .collect();
    let residual = F::perturbed_residual_over(&inputs, &delta);
    let at_zero = delta.iter().map(|d| (*d, Expr::constant(0.0))).collect();
    Traced {
        residual,
        delta,
        input_len,
        at_zero,
    }
}
