//! The factors a command line knows, and what it does with them that is
//! not parsing arguments or printing (issue 27: the command-line crate
//! `slamjac` parses and prints; this crate holds the logic a user's own
//! command line shares with it):
//!
//! - [`registry`]: the [`Registry`] of factors, each one's JSON form and
//!   how it is evaluated, and the kernel crate `generate` writes;
//! - [`method`]: how the Jacobians are computed ([`Method`]: generated
//!   kernel, dual numbers, numerical differentiation), the one
//!   [`linearize`](method::linearize) of any factor;
//! - [`eval`]: a request `{"factor", "variables", "constants"}` evaluated,
//!   and the output JSON ([`Evaluation`]);
//! - [`error`]: [`RegistryError`], which the command line's `CliError`
//!   converts from with the same message and exit code;
//! - `problem_assembly` (feature `solve`): a problem file's factor entries
//!   added to an apex-solver problem, the adders a registry keeps;
//! - `schur_assembly` (feature `solve`): the same entries added to a
//!   `factor-schur` problem.
//!
//! The problem file's reading, solving and reporting stay with the command
//! line (`slamjac::solve`), which drives the adders. Feature `clap` makes
//! [`Method`] a `clap::ValueEnum`; feature `solve` depends on the solvers'
//! adapters (apex-solver takes minutes to build the first time).

pub mod error;
pub mod eval;
pub mod method;
#[cfg(feature = "solve")]
pub mod problem_assembly;
pub mod registry;
#[cfg(feature = "solve")]
pub mod schur_assembly;

pub use error::RegistryError;
pub use eval::Evaluation;
pub use method::Method;
pub use registry::{FactorEntry, KernelCrate, Registry, SolvedBy};
