//! The input layer's one error: where (a JSON field path or the input
//! source) and what, one line each.

/// Input that does not describe a point a factor can be evaluated at: where
/// (a field path such as `variables.pose.rotation`, or the input source) and what.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{path}: {message}")]
pub struct InputError {
    /// The JSON field path, or the input source for unreadable files and invalid JSON.
    pub path: String,
    /// What is wrong, one line.
    pub message: String,
}

impl InputError {
    /// An error at `path`.
    pub fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        InputError {
            path: path.into(),
            message: message.into(),
        }
    }
}
