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
    /// The data cannot make a problem (crate `slam-problems`): a block
    /// degenerate at the initial values, data that cannot make a problem
    /// (an information matrix that is not positive definite, no odometry
    /// to initialise from, ...), or factors that do not exist for it.
    #[error(transparent)]
    Problem(#[from] ProblemError),
    /// A block's generated kernel is stale: a debug build compared it with
    /// dual numbers at the initial values ([`factor_core::kernel`]).
    #[error("{which}: {error}")]
    StaleKernel {
        /// The factor, in words.
        which: String,
        /// [`FactorError::StaleKernel`].
        error: FactorError,
    },
    /// apex-solver refused the problem.
    #[error("apex-solver: {0}")]
    Solver(String),
    /// The adapter cannot serve a factor.
    #[error(transparent)]
    Adapter(#[from] crate::error::AdapterError),
}
