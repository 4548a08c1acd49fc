//! Why a pose cannot be tracked.

use factor_core::FactorError;

/// Why [`crate::PoseProblem`] refuses an observation or cannot solve.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PoseError {
    /// The factor type has no `Se3` variable, or more than one.
    #[error(
        "{factor}: a tracked factor needs exactly one `Se3` variable (the pose), found {found}"
    )]
    NoPose {
        /// The factor's name.
        factor: &'static str,
        /// How many `Se3` variables it has.
        found: usize,
    },
    /// The factor type perturbs its pose on the other side than the
    /// problem's other factors: their Jacobian blocks cannot be summed.
    #[error("{factor}: its pose is perturbed on the other side than the other observations'")]
    MixedSides {
        /// The factor's name.
        factor: &'static str,
    },
    /// A noise model that does not fit the factor's residual
    /// ([`factor_core::noise::Noise::check`]).
    #[error("{factor}: noise model: {reason}")]
    Noise {
        /// The factor's name.
        factor: &'static str,
        /// What does not fit.
        reason: String,
    },
    /// Nothing to solve.
    #[error("no observations")]
    NoObservations,
    /// An observation cannot be evaluated at the initial pose.
    #[error("observation {observation}: {error}")]
    Observation {
        /// Its index, in the order the observations were added.
        observation: usize,
        /// The factor's error.
        error: FactorError,
    },
    /// The observations do not determine the pose at the initial value:
    /// the Gauss–Newton matrix is singular (fewer than six independent
    /// residual directions, e.g. two points).
    #[error(
        "the {observations} observations ({rows} residuals) do not determine the 6-dof pose: \
         with every Jacobian row scaled to unit norm, the Gauss–Newton matrix's smallest \
         eigenvalue is {ratio:.1e} of its largest"
    )]
    Underdetermined {
        /// The observations (those defined at the initial pose, when some
        /// were deferred).
        observations: usize,
        /// Their residual rows.
        rows: usize,
        /// The smallest over the largest eigenvalue (below [`crate::Options::min_eigenvalue_ratio`]).
        ratio: f64,
    },
}
