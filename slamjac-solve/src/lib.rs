//! Problem files read and built for the solvers, and the observability
//! checks of what `slamjac solve` solves (issue 27: the command line
//! `slamjac` parses and prints; this crate holds what it solves a problem
//! file with). Everything is behind feature `solve` (the solvers'
//! adapters; apex-solver takes minutes to build the first time): without
//! it the crate is empty.
//!
//! - `problem_file`: the format, a file's entries checked and added to an
//!   apex-solver problem by the adders of a registry
//!   (`slamjac_registry::problem_assembly`), the observability check, the
//!   solution written back and measured against the file's truth;
//! - `schur_file`: the same file built for the Schur-complement solver
//!   (`factor-schur`), its variables to eliminate chosen;
//! - `graph_checks`: the observability check of a g2o line, plane and
//!   point graph (a data file);
//! - `track_sequence`: a problem file read as a tracking sequence (its
//!   `Se3` variables the frames, every other variable the fixed map), for
//!   `factor-tracking`'s pose-only solver (`slamjac track`);
//! - [`error`]: [`SolveError`], which the command line's `CliError`
//!   converts from with the same message and exit code.
//!
//! The solve itself (the solver run, the progress printed, the summary,
//! `--output` and `--plot`) is the command line's (`slamjac::solve`).

pub mod error;
#[cfg(feature = "solve")]
pub mod graph_checks;
#[cfg(feature = "solve")]
pub mod problem_file;
#[cfg(feature = "solve")]
pub mod schur_file;
#[cfg(feature = "solve")]
pub mod track_sequence;

pub use error::SolveError;
