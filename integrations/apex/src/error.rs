//! [`AdapterError`]: a factor the adapter cannot serve.

/// A factor that [`ApexFactor`](crate::adapter::ApexFactor) cannot serve. (A variable type with no
/// mapping onto apex's manifolds is refused at compile time: the factor is
/// then not a `HostFactor<Apex>`.)
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum AdapterError {
    /// The factor is larger than the adapter's stack buffers.
    #[error(
        "{factor}: more than {} stored scalars, or a variable of more than {} apex parameters",
        factor_core::host::MAX_STORED,
        factor_core::host::MAX_VARIABLE_PARAMETERS
    )]
    TooLarge {
        /// The factor's name.
        factor: &'static str,
    },
}
