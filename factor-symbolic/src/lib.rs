//! The symbolic engine of `slamjac`: a scalar that records what residual
//! code does.
//!
//! [`Expr`] implements [`factor_core::Scalar`], so the residuals and all
//! geometry are traced as written, with no second definition. The stages:
//!
//! - [`graph`]: the hash-consed DAG ([`Graph`], [`Node`]) and the [`Tracer`]
//!   that records into it; [`Expr`] is a `Copy` handle to a node;
//! - [`algebra`]: the canonical constructors (n-ary sums and products with
//!   numeric coefficients), which the arithmetic operators of [`Expr`] call;
//! - [`scalar`]: `impl Scalar for Expr`;
//! - [`calculus`]: exact derivatives and substitution;
//! - [`trace`]: a factor's residual traced at a symbolic tangent;
//! - [`cut`]: minimum vertex cuts between the tangent and the residual;
//! - [`jacobian`]: the Jacobian columns at `δ = 0`, directly or by the chain
//!   rule through a cut;
//! - [`evaluate`]: a numeric evaluator, the reference in tests;
//! - [`display`]: expressions as text.
//!
//! The code generator (crate `factor-codegen`) compiles the traced
//! expressions to kernels; the derivation audit (crate `factor-audit`)
//! renders corrected formulas from them.

pub mod algebra;
pub mod calculus;
pub mod cut;
pub mod display;
pub mod evaluate;
pub mod graph;
pub mod jacobian;
pub mod scalar;
pub mod trace;

pub use graph::{Expr, Graph, Node, Tracer};

/// The optimisation level this crate was built at (`0` in a debug build
/// without a `[profile.dev.package.factor-symbolic]` entry, where tracing a
/// factor is several times slower; see `factor_codegen::build_profile`).
pub const OPT_LEVEL: &str = env!("FACTOR_SYMBOLIC_OPT_LEVEL");
