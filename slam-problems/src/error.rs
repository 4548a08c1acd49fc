//! [`ProblemError`]: why a data set cannot make a problem, whichever solver
//! takes it (each solver's build error converts from it).

use factor_core::FactorError;

/// Why a data set's factors cannot be built.
// Exhaustive: each solver's build error converts from it variant for
// variant.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
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
