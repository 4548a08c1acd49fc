//! How a problem is built: which factors ([`FactorChoice`]), the robust
//! loss on every block ([`Robust`], from crate `slam-problems`), the
//! options of a build ([`BuildOptions`]) and why a build fails ([`BuildError`]). Shared by the
//! typed builder ([`crate::builder`]) and the data-set problems
//! ([`crate::problems`], which re-exports them).

use factor_core::FactorError;
use slam_problems::ProblemError;
pub use slam_problems::{ROBUST_SCALES, Robust};

use crate::adapter::Kernels;

/// The factors a problem is built with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FactorChoice {
    /// This project's factors, linearized as given.
    Ours(Kernels),
    /// apex-solver's own hand-written factors.
    Apex,
}

impl FactorChoice {
    /// `generated`, `dual` or `apex`.
    pub fn name(self) -> &'static str {
        match self {
            FactorChoice::Ours(kernels) => kernels.name(),
            FactorChoice::Apex => "apex",
        }
    }
}

/// How to build a problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuildOptions {
    /// Which factors.
    pub factors: FactorChoice,
    /// A robust loss on every block, or plain least squares.
    pub robust: Option<Robust>,
    /// Keep a handle on every block ([`Built::kept`](crate::built::Built::kept))
    /// to call it directly.
    pub keep_blocks: bool,
}

/// Why a problem cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BuildError {
    /// A block is degenerate at the initial values.
    #[error("{which}: {error}")]
    Degenerate {
        /// The observation or edge, in words.
        which: String,
        /// The factor's error.
        error: FactorError,
    },
    /// A block's generated kernel is stale: a debug build compared it with
    /// dual numbers at the initial values ([`factor_core::kernel`]).
    #[error("{which}: {error}")]
    StaleKernel {
        /// The factor, in words.
        which: String,
        /// [`FactorError::StaleKernel`].
        error: FactorError,
    },
    /// The data cannot make a problem (an information matrix that is not
    /// positive definite, no odometry to initialise from, ...).
    #[error("{0}")]
    Data(String),
    /// The factors asked for do not exist for this problem.
    #[error("{0}")]
    Unavailable(String),
    /// apex-solver refused the problem.
    #[error("apex-solver: {0}")]
    Solver(String),
    /// The adapter cannot serve a factor.
    #[error(transparent)]
    Adapter(#[from] crate::error::AdapterError),
}

/// The data sets' errors, variant for variant.
impl From<ProblemError> for BuildError {
    fn from(error: ProblemError) -> Self {
        match error {
            ProblemError::Degenerate { which, error } => BuildError::Degenerate { which, error },
            ProblemError::Data(what) => BuildError::Data(what),
            ProblemError::Unavailable(why) => BuildError::Unavailable(why),
        }
    }
}
