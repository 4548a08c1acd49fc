//! [`BuildError`]: why a data set cannot make a problem for this solver.

use slam_problems::ProblemError;

use crate::error::SchurError;

/// Why a problem cannot be built for this solver.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BuildError {
    /// The data cannot make a problem (crate `slam-problems`): a factor
    /// degenerate at the initial values, data that refer to something they
    /// do not hold, or a problem these factors cannot model.
    #[error(transparent)]
    Problem(#[from] ProblemError),
    /// The problem is not in the solver's shape.
    #[error(transparent)]
    Shape(#[from] SchurError),
}
