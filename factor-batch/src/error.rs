//! What a batch refuses: columns that do not fit the factor or each other.

/// Why a batch cannot be evaluated as given.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BatchError {
    /// A set of columns has the wrong number of columns.
    #[error("{factor}: {what} has {found} columns, expected {expected}")]
    Width {
        /// The factor's name.
        factor: &'static str,
        /// Which columns (`inputs`, `residual`, `Jacobian w.r.t. \`pose\``, …).
        what: String,
        /// The number of columns found.
        found: usize,
        /// The number the factor needs.
        expected: usize,
    },
    /// A set of columns has another number of rows than the inputs.
    #[error("{factor}: {what} has {found} rows, the inputs {expected}")]
    Length {
        /// The factor's name.
        factor: &'static str,
        /// Which columns.
        what: String,
        /// The number of rows found.
        found: usize,
        /// The inputs' number of rows.
        expected: usize,
    },
    /// The outputs have another number of blocks than the factor has
    /// variables (or pairs of variables).
    #[error("{factor}: {what} has {found} blocks, expected {expected}")]
    Blocks {
        /// The factor's name.
        factor: &'static str,
        /// Which outputs.
        what: &'static str,
        /// The number of blocks found.
        found: usize,
        /// The number the factor has.
        expected: usize,
    },
    /// A Hessian block is present for a pair with a fixed variable, or
    /// missing for a pair of free ones.
    #[error(
        "{factor}: the Hessian block of `{first}` and `{second}` is {state}, but the gradient \
         blocks say the variables are {free}"
    )]
    Pairing {
        /// The factor's name.
        factor: &'static str,
        /// The pair's first variable.
        first: &'static str,
        /// The pair's second variable.
        second: &'static str,
        /// `present` or `absent`.
        state: &'static str,
        /// What the gradient blocks say.
        free: &'static str,
    },
}
