//! The command line's errors and their exit codes.
//!
//! | exit | meaning |
//! | --- | --- |
//! | 0 | success |
//! | 1 | the input is well formed but the factor cannot be evaluated there: degenerate geometry, or a configuration outside the factor's accuracy envelope, reported by the factor's `validate()` (with a hint when an input quaternion looks written `[w, x, y, z]`), a non-finite residual or Jacobian, or numerical differentiation that does not converge (`--method numeric`); or `check` found stale generated files |
//! | 2 | the input is rejected: unreadable file, input over 16 MiB or not UTF-8, invalid JSON (nesting deeper than 128 included), duplicate key, unknown factor, missing, unknown or mistyped field, wrong length, non-finite number, non-unit quaternion, zero-norm vector, Plücker constraint violated (and, from clap, a command-line usage error); or the generated crate is not found or a file of it cannot be read, `generate --out` names a directory that is not a generated crate, or `generate` cannot write it |
//!
//! Every error is printed as one line, `error: <where>: <what>`, where
//! `<where>` is the JSON field path (`variables.pose.rotation[3]`,
//! `variables["a b"]`: see [`slamjac_problem::field_path`] for quoting,
//! escaping and the cut of long names), the input source (a file name or `<stdin>`), a
//! directory or file of the generated crate, or the factor's name. No
//! character that ends a line or steers a terminal is printed raw.

use std::path::PathBuf;

use factor_core::FactorError;
use slamjac_problem::InputError;
use slamjac_problem::field_path::escape_unprintable;
use slamjac_registry::RegistryError;

/// Exit code of rejected input (and of clap's usage errors).
pub const EXIT_BAD_INPUT: u8 = 2;
/// Exit code of a well-formed input the factor cannot be evaluated at.
pub const EXIT_DEGENERATE: u8 = 1;

/// Anything `slamjac` reports instead of a result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CliError {
    /// Rejected input (exit 2).
    #[error(transparent)]
    Input(#[from] InputError),
    /// A degenerate configuration or a non-finite result (exit 1); the
    /// message names the factor.
    #[error(transparent)]
    Factor(#[from] FactorError),
    /// A registry's factor not evaluated or not added to a problem: exit 2
    /// for rejected input, 1 for a degenerate configuration (with a hint
    /// at its likely cause in the input, e.g. a quaternion written
    /// `[w, x, y, z]`), a non-finite result or a solver's refusal.
    #[error(transparent)]
    Registry(#[from] RegistryError),
    /// `check`: these generated files differ from what the factor
    /// definitions produce, are missing or are not generated (exit 1).
    #[error(
        "{}: stale: differs from what the factor definitions produce; run `{generate}`",
        .files.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
    )]
    Stale {
        /// The files.
        files: Vec<PathBuf>,
        /// The command that rewrites them.
        generate: String,
    },
    /// `generate`/`check`: the generator refuses a kernel (exit 1).
    #[error("generate: {0}")]
    Codegen(#[from] factor_codegen::CodegenError),
    /// `audit`: these formulas disagree with the truth and are not known
    /// errata (exit 1); the claims that could not be read either (when the
    /// files do not expect them unread) are named too.
    #[error(
        "audit: formulas disagree with the truth: {}{}",
        .disagreeing.join("; "),
        if .unread.is_empty() {
            String::new()
        } else {
            format!(
                "; and {} claim(s) could not be read: {}",
                .unread.len(),
                .unread.join("; ")
            )
        }
    )]
    Disagreement {
        /// The disagreements.
        disagreeing: Vec<String>,
        /// The claims that could not be read.
        unread: Vec<String>,
    },
    /// A data file that cannot be read or written, `FILE:LINE: what` or
    /// `FILE: what` (exit 2).
    #[error(transparent)]
    Data(#[from] slam_data::Error),
    /// An option whose value is not valid, named (exit 2).
    #[error("{0}")]
    Usage(String),
    /// `solve`: the problem cannot be solved from its initial values, or the
    /// solve stopped on a failure (exit 1).
    #[error("{0}")]
    Solve(String),
}

/// A problem file's or a graph's refusal as the command line reports it:
/// the variant of the same name, the same message.
#[cfg(feature = "solve")]
impl From<slamjac_solve::SolveError> for CliError {
    fn from(error: slamjac_solve::SolveError) -> Self {
        use slamjac_solve::SolveError;
        match error {
            SolveError::Input(error) => CliError::Input(error),
            SolveError::Usage(message) => CliError::Usage(message),
            SolveError::Solve(message) => CliError::Solve(message),
            SolveError::Registry(error) => CliError::Registry(error),
            other => CliError::Solve(other.to_string()),
        }
    }
}

/// A ground truth that cannot be read is a data error, one the solve cannot
/// use a usage error (both exit 2).
impl From<slamjac_problem::truth::TruthError> for CliError {
    fn from(error: slamjac_problem::truth::TruthError) -> Self {
        use slamjac_problem::truth::TruthError;
        match error {
            TruthError::Read(error) => CliError::Data(error),
            TruthError::NothingToCompare(message) => CliError::Usage(message),
            other => CliError::Usage(other.to_string()),
        }
    }
}

impl CliError {
    /// The process exit code for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_)
            | CliError::Registry(RegistryError::Input(_))
            | CliError::Data(_)
            | CliError::Usage(_) => EXIT_BAD_INPUT,
            CliError::Factor(_)
            | CliError::Registry(_)
            | CliError::Stale { .. }
            | CliError::Codegen(_)
            | CliError::Disagreement { .. }
            | CliError::Solve(_) => EXIT_DEGENERATE,
        }
    }

    /// The message as one line, `error: <where>: <what>`, any line break or
    /// other unprintable character in it escaped (`\n`, `\u001b`).
    pub fn one_line(&self) -> String {
        format!("error: {}", escape_unprintable(&self.to_string()))
    }
}
