//! The symbolic engine: a scalar that records what residual code does.
//!
//! [`Expr`] implements [`crate::Scalar`], so the residuals and all geometry
//! are traced as written, with no second definition. Underneath is a
//! hash-consed DAG of canonical n-ary sums and products ([`algebra`]),
//! exact derivatives and substitution ([`calculus`]), and a numeric
//! evaluator ([`evaluate`]) used as the reference in tests.

pub mod algebra;
pub mod calculus;
pub mod cut;
pub mod evaluate;
pub mod graph;
mod scalar_impl;

pub use graph::{Expr, Graph, Node, Tracer};
pub use kernel::{JacobianBlock, JacobianForm, SymbolicKernel, trace};
pub mod display;
pub mod kernel;
pub mod lower;
pub mod optimize;
