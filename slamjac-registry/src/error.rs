//! What a registry's factor reports instead of a result
//! ([`RegistryError`]). The command line (`slamjac::error::CliError`)
//! wraps it as it is (`CliError::Registry`): the same message, exit 2 for
//! [`RegistryError::Input`], exit 1 for the others.

use factor_core::FactorError;
use slamjac_problem::InputError;

/// Why a factor of a registry was not evaluated or added to a problem.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RegistryError {
    /// Rejected input, at its field path.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A degenerate configuration or a non-finite result; the message
    /// names the factor.
    #[error(transparent)]
    Factor(#[from] FactorError),
    /// A degenerate configuration with a hint at its likely cause in the
    /// input, e.g. a quaternion written `[w, x, y, z]`.
    #[error("{error} ({hint})")]
    Hinted {
        /// The factor's error.
        error: FactorError,
        /// The hint, naming the input field.
        hint: String,
    },
    /// A solver's problem refused a factor (feature `solve`).
    #[error("{0}")]
    Solve(String),
}
