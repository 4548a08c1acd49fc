//! `slamjac`, the command line of the factor toolchain: list the registered
//! factors and evaluate any of them, residual and tangent-space Jacobians, at
//! a point given as JSON (SPEC.md, "The `eval` JSON interface").
//!
//! - [`input`]: JSON → typed values, errors naming the field path;
//! - [`decode`]: each factor's `variables` and `constants` → the factor;
//! - [`registry`]: the table of factors;
//! - [`eval`]: evaluation and the output JSON;
//! - [`list`]: the factor table, text or JSON;
//! - [`generate`]: `generate` and `check` of the generated kernels;
//! - [`pretty`]: indented JSON with arrays of numbers on one line;
//! - [`error`]: errors and the exit-code policy (0 ok, 1 degenerate
//!   geometry or non-finite result, 2 rejected input).

pub mod audit;
pub mod decode;
pub mod error;
pub mod eval;
pub mod generate;
pub mod input;
pub mod kernels;
pub mod list;
pub mod pretty;
pub mod registry;

pub use error::{CliError, InputError};
pub use eval::{Evaluation, Method};
