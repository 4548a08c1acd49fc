//! `slamjac`, the command line of the factor toolchain: list the registered
//! factors and evaluate any of them, residual and tangent-space Jacobians, at
//! a point given as JSON (the README's "Command line"); generate and check
//! the document factors' kernels; audit the documents' derivations. It is a
//! user of the public APIs of `slam-factors`, `factor-codegen` and
//! `factor-audit`, like any other. Its input layer (reading a source,
//! strict JSON, typed values, decoding factors, the problem-file format's
//! version) and the observability check of a problem are the crate
//! `slamjac-problem`; the factors a command line knows, how they are
//! evaluated and added to the solvers' problems, the crate
//! `slamjac-registry` (re-exported here as [`registry`], [`method`] and
//! [`eval`]).
//!
//! - [`registry`]: the factors a command line knows ([`registry::Registry`])
//!   and the kernel crate it generates (`slamjac_registry::registry`);
//! - [`cli`]: the command line as a library, `list`, `eval`, `generate` and
//!   `check` for any registry (a user's own factors);
//! - [`init`]: `init`, a new project for factors of your own;
//! - [`method`]: how the Jacobians are computed (generated, dual, numeric;
//!   `slamjac_registry::method`);
//! - [`eval`]: evaluation and the output JSON (`slamjac_registry::eval`),
//!   and `eval`'s request read and its output printed;
//! - [`list`]: the factor table, text or JSON;
//! - [`kernels`]: the shipped factors: `slamjac`'s own registry, their
//!   kernel specs and provenance;
//! - [`generate`]: `generate` and `check` of a registry's kernel crate;
//! - [`audit`]: `audit` of the documents' derivations;
//! - [`audit_text`]: `audit DOC --symbols FILE`, a document's formulas
//!   audited from its text;
//! - [`pretty`]: indented JSON with arrays of numbers on one line;
//! - [`synth`]: `synth-bal`, seeded synthetic BAL problems;
//! - [`synth_plp`]: `synth-plp`, a seeded point-line-plane room written as
//!   a problem file;
//! - [`outputs`]: the files a command writes, checked before any work;
//! - [`usage`]: clap's usage errors as one line;
//! - `solve` (feature `solve`): real estimation problems solved by
//!   apex-solver through the factors' generated kernels, and problem files
//!   read and built by the crate `slamjac-solve` (its `problem_file`,
//!   re-exported as `solve::problem_file`, and `schur_file`) through the
//!   adders of `slamjac-registry`, solved, printed and written here;
//! - [`error`]: errors and the exit-code policy (0 ok, 1 degenerate
//!   geometry or non-finite result, 2 rejected input).

pub mod audit;
pub mod audit_text;
pub mod cli;
pub mod error;
pub mod eval;
pub mod generate;
pub mod init;
pub mod kernels;
pub mod list;
pub mod outputs;
pub mod pretty;
#[cfg(feature = "solve")]
pub mod solve;
pub mod synth;
pub mod synth_plp;
pub mod usage;

pub use error::CliError;
pub use slamjac_registry::{Evaluation, Method, method, registry};
