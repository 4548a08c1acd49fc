//! The command line's errors and their exit codes.
//!
//! | exit | meaning |
//! | --- | --- |
//! | 0 | success |
//! | 1 | the input is well formed but the factor cannot be evaluated there: degenerate geometry reported by the factor's `validate()`, or a non-finite residual or Jacobian; or `check` found stale generated files |
//! | 2 | the input is rejected: unreadable file, invalid JSON, unknown factor, missing, unknown or mistyped field, wrong length, non-finite number, non-unit quaternion, zero-norm vector, Plücker constraint violated (and, from clap, a command-line usage error); or `generate` cannot write its directory |
//!
//! Every error is printed as one line, `error: <where>: <what>`, where
//! `<where>` is the JSON field path (`variables.pose.rotation[3]`), the input
//! source (a file name or `<stdin>`) or the factor's name.

use std::path::PathBuf;

use factor_core::FactorError;

/// Exit code of rejected input (and of clap's usage errors).
pub const EXIT_BAD_INPUT: u8 = 2;
/// Exit code of a well-formed input the factor cannot be evaluated at.
pub const EXIT_DEGENERATE: u8 = 1;

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

/// Anything `slamjac` reports instead of a result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CliError {
    /// Rejected input (exit 2).
    #[error(transparent)]
    Input(#[from] InputError),
    /// A degenerate configuration or a non-finite result (exit 1); the
    /// message names the factor.
    #[error(transparent)]
    Factor(#[from] FactorError),
    /// `check`: these generated files differ from what the factor
    /// definitions produce, are missing or are not generated (exit 1).
    #[error(
        "{}: stale: differs from what the factor definitions produce; run `slamjac generate`",
        .0.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
    )]
    Stale(Vec<PathBuf>),
    /// `generate`/`check`: the generator refuses a kernel (exit 1).
    #[error("generate: {0}")]
    Codegen(#[from] factor_codegen::CodegenError),
    /// `audit`: these formulas disagree with the truth and are not known
    /// errata (exit 1).
    #[error("audit: formulas disagree with the truth: {}", .0.join("; "))]
    Disagreement(Vec<String>),
}

impl CliError {
    /// The process exit code for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_) => EXIT_BAD_INPUT,
            CliError::Factor(_)
            | CliError::Stale(_)
            | CliError::Codegen(_)
            | CliError::Disagreement(_) => EXIT_DEGENERATE,
        }
    }

    /// The message as one line, `error: <where>: <what>`.
    pub fn one_line(&self) -> String {
        let text = self.to_string();
        let lines: Vec<&str> = text.lines().map(str::trim).collect();
        format!("error: {}", lines.join(" "))
    }
}
