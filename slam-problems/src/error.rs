//! [`ProblemError`]: why a data set cannot make a problem, whichever solver
//! takes it (each solver's build error wraps it in one variant).

use factor_core::FactorError;

/// Why a data set's factors cannot be built.
///
/// Non-exhaustive: the solvers' build errors wrap it whole (their
/// `Problem` variant) rather than mirror its variants, so a new reason a
/// data set fails can be added without breaking them; a match on it needs
/// a catch-all arm.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ProblemError {
    /// A factor is degenerate at the initial values.
    #[error("{which}: {error}")]
    Degenerate {
        /// The observation or edge, in words.
        which: String,
        /// The factor's error.
        error: FactorError,
    },
    /// The data cannot make a problem (an information matrix that is not
    /// positive definite, no odometry to initialise from, an edge on a
    /// vertex not defined, ...).
    #[error("{0}")]
    Data(String),
    /// Not a problem these factors can model (the documents' plane factor
    /// on a free sensor offset).
    #[error("{0}")]
    Unavailable(String),
}

impl ProblemError {
    /// [`ProblemError::Degenerate`]: `which` (the observation or edge, in
    /// words) is degenerate at the initial values.
    pub fn at_initial_values(which: impl std::fmt::Display, error: FactorError) -> Self {
        ProblemError::Degenerate {
            which: format!("{which} at the initial values"),
            error,
        }
    }
}
