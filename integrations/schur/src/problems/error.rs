//! [`BuildError`]: why a data set cannot make a problem for this solver.

use factor_core::FactorError;
use slam_problems::ProblemError;

use crate::error::SchurError;

/// Why a problem cannot be built for this solver.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BuildError {
    /// A factor is degenerate at the initial values.
    #[error("{which}: {error}")]
    Degenerate {
        /// The observation, in words.
        which: String,
        /// The factor's error.
        error: FactorError,
    },
    /// The data refer to something they do not hold.
    #[error("{0}")]
    Data(String),
    /// Not a problem these factors can model (the documents' plane factor
    /// on a free sensor offset).
    #[error("{0}")]
    Unavailable(String),
    /// The problem is not in the solver's shape.
    #[error(transparent)]
    Shape(#[from] SchurError),
}

/// The data sets' errors (crate `slam-problems`), variant for variant.
impl From<ProblemError> for BuildError {
    fn from(error: ProblemError) -> Self {
        match error {
            ProblemError::Degenerate { which, error } => BuildError::Degenerate { which, error },
            ProblemError::Data(what) => BuildError::Data(what),
            ProblemError::Unavailable(why) => BuildError::Unavailable(why),
        }
    }
}
