//! Why a problem file or a graph is not built or checked
//! ([`SolveError`]). The command line (`slamjac::error::CliError`)
//! converts each variant to its own: the same message, exit 2 for
//! [`SolveError::Input`] and [`SolveError::Usage`], exit 1 for
//! [`SolveError::Solve`], and a registry's error as it converts that.

use slamjac_problem::InputError;

/// Why a problem file or a graph is not built or checked.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SolveError {
    /// Rejected input, at its field path.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A file that cannot be solved as asked: nothing to solve, a graph
    /// whose vertices or edges cannot be built, an entry a solver's
    /// problem refuses.
    #[error("{0}")]
    Usage(String),
    /// The problem cannot be solved from its initial values: a factor
    /// degenerate there, directions no factor determines, a solver that
    /// cannot start.
    #[error("{0}")]
    Solve(String),
    /// A registry's factor refused, as the registry words it (feature
    /// `solve`).
    #[cfg(feature = "solve")]
    #[error(transparent)]
    Registry(#[from] slamjac_registry::RegistryError),
}
