//! How a problem is built: which factors ([`FactorChoice`]), the robust
//! loss on every block ([`Robust`]), the options of a build
//! ([`BuildOptions`]) and why a build fails ([`BuildError`]). Shared by the
//! typed builder ([`crate::builder`]) and the data-set problems
//! ([`crate::problems`], which re-exports them).

use std::fmt;
use std::str::FromStr;

use apex_solver::core::loss_functions::{HuberLoss, LossFunction};
use factor_core::FactorError;

use crate::adapter::Kernels;
use crate::losses::Cauchy;

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

/// A robust loss on every block: `½ ρ(‖r‖²)` instead of `½ ‖r‖²`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Robust {
    /// Huber: quadratic up to `‖r‖ = δ`, linear beyond.
    Huber(f64),
    /// Cauchy: `δ² log(1 + ‖r‖²/δ²)`.
    Cauchy(f64),
}

impl Robust {
    /// The loss served to apex-solver: apex's Huber, this crate's Cauchy
    /// (apex's rounds its cost to 0 for a large δ: see [`crate::losses`]).
    pub(crate) fn loss(self) -> Result<Box<dyn LossFunction + Send + Sync>, BuildError> {
        match self {
            Robust::Huber(delta) => HuberLoss::new(delta)
                .map(|l| Box::new(l) as _)
                .map_err(|e| BuildError::Solver(e.to_string())),
            Robust::Cauchy(delta) => Cauchy::new(delta)
                .map(|l| Box::new(l) as _)
                .map_err(BuildError::Solver),
        }
    }
}

/// The range of a robust loss's δ: the readers' range of magnitudes
/// (`slam_data::MAX_MAGNITUDE`), so that `δ²` stays within `f64`.
pub const ROBUST_SCALES: (f64, f64) = (1e-100, 1e100);

/// `huber:δ` or `cauchy:δ`.
impl fmt::Display for Robust {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Robust::Huber(delta) => write!(f, "huber:{delta}"),
            Robust::Cauchy(delta) => write!(f, "cauchy:{delta}"),
        }
    }
}

/// Reads `huber:δ` or `cauchy:δ` with `δ` in [`ROBUST_SCALES`].
impl FromStr for Robust {
    type Err = String;
    fn from_str(text: &str) -> Result<Self, String> {
        let (name, delta) = text
            .split_once(':')
            .ok_or_else(|| format!("`{text}`: expected huber:δ or cauchy:δ"))?;
        let (low, high) = ROBUST_SCALES;
        let delta: f64 = delta
            .parse()
            .ok()
            .filter(|d: &f64| (low..=high).contains(d))
            .ok_or_else(|| {
                format!("`{text}`: δ must be a number above 0, from {low:e} to {high:e}")
            })?;
        match name {
            "huber" => Ok(Robust::Huber(delta)),
            "cauchy" => Ok(Robust::Cauchy(delta)),
            _ => Err(format!("`{text}`: unknown loss `{name}` (huber or cauchy)")),
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
