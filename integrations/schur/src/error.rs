//! [`SchurError`]: a problem this solver cannot take.

/// A problem this solver cannot take.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SchurError {
    /// A factor given the wrong number of variables.
    #[error("{factor}: {given} variables given, the factor has {expected}")]
    Arity {
        factor: &'static str,
        given: usize,
        expected: usize,
    },
    /// A factor given one variable twice.
    #[error("{factor}: variable {variable} given twice")]
    Repeated {
        factor: &'static str,
        variable: usize,
    },
    /// A variable whose stored scalars do not fit the factor's field.
    #[error("{factor}: `{name}` stores {expected} scalars, variable {variable} has {found}")]
    Scalars {
        factor: &'static str,
        variable: usize,
        name: &'static str,
        expected: usize,
        found: usize,
    },
    /// Two factors that perturb one variable differently.
    #[error(
        "variable {variable}: {first}, {second}: every factor on a variable must declare the same \
         type, side and tangent"
    )]
    Chart {
        variable: usize,
        first: String,
        second: String,
    },
    /// A noise model that does not fit the factor's residual.
    #[error("{factor}: {message}")]
    Noise {
        factor: &'static str,
        message: String,
    },
    /// A variable id that is not the problem's.
    #[error("variable {0} does not exist")]
    UnknownVariable(usize),
    /// A factor on two eliminated variables: they cannot be eliminated one
    /// by one.
    #[error(
        "{factor} {index} joins two eliminated variables: a Schur complement eliminates variables \
         no factor joins"
    )]
    NotSchur { factor: &'static str, index: usize },
    /// Beyond the solver's limits (sizes, indices).
    #[error("{0}")]
    TooLarge(String),
}
