//! A variable's own chart traced for a solver's manifold: what a Ceres
//! `Manifold` computes, from the variable type's [`factor_core::Manifold`]
//! alone ([`factor_core::Factor::chart_over`]).
//!
//! With `x` the stored scalars (`n`), `δ` a tangent (`d`) and `y` another
//! value's stored scalars, on the variable's perturbation side:
//!
//! - `plus(x, δ)`: the exact retraction [`factor_core::Manifold::retract`];
//! - `plus_jacobian(x)`: `∂ plus(x, δ)/∂δ` at `δ = 0`, `n × d` row-major,
//!   through the first-order retraction (rule 5 of `Manifold`: the same
//!   derivative, no small-angle branch);
//! - `minus(y, x)`: the local coordinates of `y` at `x`,
//!   [`factor_core::Manifold::local`];
//! - `minus_jacobian(x)`: `∂ minus(y, x)/∂y` at `y = x`, `d × n` row-major,
//!   with `y`'s scalars free (off the manifold too), so it is the derivative
//!   a numerical check of `minus` sees; `minus_jacobian · plus_jacobian = I`
//!   follows from `minus(plus(x, δ), x) = δ`.
//!
//! A chart whose retraction is `x + δ` on every stored scalar is
//! [`ChartTrace::euclidean`]: a solver needs no manifold for it.

use std::collections::HashMap;

use factor_core::manifold::{ChartMap, NoLocal};
use factor_core::{Factor, Layout, Perturbation, VariableInfo};
use factor_symbolic::jacobian::direct_columns;
use factor_symbolic::{Expr, Tracer};

use crate::error::CodegenError;
use crate::lower::{LoweredKernel, lower};

/// One variable's chart, each map lowered to a program whose residual
/// values are its outputs (inputs: `plus` reads `x` then `δ`,
/// `plus_jacobian` and `minus_jacobian` read `x`, `minus` reads `x` then
/// `y`).
#[derive(Debug, Clone)]
pub struct ChartTrace {
    /// The chart's name, `<type>_<side>` in snake case (`se3_left`,
    /// [`VariableInfo::chart_name`]): the prefix of its functions and of its
    /// solver manifold's file.
    pub name: String,
    /// The variable type as the factor writes it (`Se3<S>`).
    pub type_name: &'static str,
    /// The perturbation side.
    pub side: Perturbation,
    /// The retraction and the tangent's columns, in words.
    pub tangent: &'static str,
    /// The stored scalars' names.
    pub layout: Layout,
    /// The number of stored scalars `n` (the solver's ambient size).
    pub ambient: usize,
    /// The tangent dimension `d`.
    pub dim: usize,
    /// Whether the retraction is `x + δ` on every stored scalar (`n = d`).
    pub euclidean: bool,
    /// `plus(x, δ)`: `n` outputs.
    pub plus: LoweredKernel,
    /// `∂plus/∂δ` at `δ = 0`: `n × d`, row-major.
    pub plus_jacobian: LoweredKernel,
    /// `minus(y, x)`: `d` outputs.
    pub minus: LoweredKernel,
    /// `∂minus/∂y` at `y = x`: `d × n`, row-major.
    pub minus_jacobian: LoweredKernel,
}

/// Rows × columns of `columns` (one `Vec` per column) as row-major entries.
fn row_major(columns: &[Vec<Expr>], rows: usize) -> Vec<Expr> {
    (0..rows)
        .flat_map(|r| columns.iter().map(move |column| column[r]))
        .collect()
}

/// Traces variable `variable` of factor `F` (see the module
/// documentation).
///
/// # Errors
///
/// [`CodegenError::NoLocal`] when the variable's type gives no
/// [`factor_core::Manifold::local`].
///
/// # Panics
///
/// If `variable` is out of range.
pub fn trace_chart<F: Factor>(variable: usize) -> Result<ChartTrace, CodegenError> {
    let info: VariableInfo = F::variables().swap_remove(variable);
    let field = F::fields()
        .into_iter()
        .find(|f| f.variable == Some(variable))
        .expect("every variable is a field");
    let (n, d) = (field.scalars, info.tangent_dim);
    let index = |k: usize| Expr::input(u32::try_from(k).expect("fewer than 2³² inputs"));
    let tracer = Tracer::new();
    let x: Vec<Expr> = (0..n).map(index).collect();
    let delta: Vec<Expr> = (n..n + d).map(index).collect();
    let y: Vec<Expr> = (n..2 * n).map(index).collect();
    let chart = |map: ChartMap, argument: &[Expr], len: usize| {
        let mut out = vec![Expr::constant(0.0); len];
        F::chart_over::<Expr>(variable, map, &x, argument, &mut out).map(|()| out)
    };
    let no_local = |NoLocal| CodegenError::NoLocal {
        kernel: F::NAME,
        variable: info.name,
        type_name: info.type_name,
    };
    let plus = chart(ChartMap::Retract, &delta, n).expect("a retraction is always given");
    let first_order =
        chart(ChartMap::RetractFirstOrder, &delta, n).expect("a retraction is always given");
    let minus = chart(ChartMap::Local, &y, d).map_err(no_local)?;
    let at_zero: HashMap<Expr, Expr> = delta.iter().map(|e| (*e, Expr::constant(0.0))).collect();
    let plus_jacobian = row_major(
        &direct_columns(&first_order, &delta, &at_zero, &mut HashMap::new()),
        n,
    );
    let at_x: HashMap<Expr, Expr> = y.iter().zip(&x).map(|(y, x)| (*y, *x)).collect();
    let minus_jacobian = row_major(&direct_columns(&minus, &y, &at_x, &mut HashMap::new()), d);
    let euclidean = n == d && (0..n).all(|k| plus[k] == x[k] + delta[k]);
    let graph = tracer.finish();
    let lowered = |outputs: &[Expr]| lower(&graph, outputs, &[]);
    Ok(ChartTrace {
        name: info.chart_name(),
        type_name: info.type_name,
        side: info.perturbation,
        tangent: info.tangent,
        layout: field.layout,
        ambient: n,
        dim: d,
        euclidean,
        plus: lowered(&plus),
        plus_jacobian: lowered(&plus_jacobian),
        minus: lowered(&minus),
        minus_jacobian: lowered(&minus_jacobian),
    })
}

/// Every variable's chart of factor `F`, in declaration order.
///
/// # Errors
///
/// As [`trace_chart`].
pub fn trace_charts<F: Factor>() -> Result<Vec<ChartTrace>, CodegenError> {
    (0..F::variables().len()).map(trace_chart::<F>).collect()
}
