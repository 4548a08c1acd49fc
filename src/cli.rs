//! The command line as a library: `list`, `eval`, `generate` and `check`
//! for the factors of a [`Registry`], the user's own as well as the ones
//! `slamjac` ships.
//!
//! A crate of factors gets its command line from a few lines of `main`
//! (`slamjac init` writes such a crate; docs/guide/kernels.md walks through
//! it):
//!
//! ```no_run
//! use std::process::ExitCode;
//!
//! use slam_factors::PointReprojection; // your factors instead
//! use slamjac::cli::{KernelCrate, Provenance, Registry};
//!
//! /// The crate `generate` writes and `check` compares.
//! const KERNELS: KernelCrate = KernelCrate {
//!     package: "my-kernels",
//!     dir: concat!(env!("CARGO_MANIFEST_DIR"), "/../my-kernels"),
//!     provenance: Provenance::new(
//!         "Residual-and-Jacobian kernels of the factors of `my-factors`.",
//!         "cargo run -p my-cli --no-default-features -- generate",
//!         "cargo run -p my-cli --no-default-features -- check",
//!     ),
//! };
//!
//! fn main() -> ExitCode {
//!     Registry::new()
//!         .with_kernel::<PointReprojection>()
//!         .with_kernel_crate(KERNELS)
//!         .run("my-cli")
//! }
//! ```
//!
//! `my-cli list`, `my-cli eval FILE`, `my-cli generate` and `my-cli check`
//! then behave as `slamjac`'s own (the README's "Command line"): one JSON
//! input `{"factor", "variables", "constants"}` per `eval`, the input's
//! shape printed by `list`, errors on one line, exit codes 0, 1 and 2
//! ([`crate::error`]).
//!
//! A binary with subcommands of its own flattens [`FactorCommand`] into its
//! clap command and hands it to [`Registry::execute`]; `slamjac`'s `main`
//! does so beside `audit`, `synth-bal` and `solve`. A subcommand that works
//! on a registry's factors (solving a problem file whose factors are named
//! as in `eval`) is one more variant of [`FactorCommand`], resolving names
//! with [`Registry::find`].

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{FromArgMatches, Subcommand};

pub use factor_codegen::{KernelSpec, Provenance};

pub use crate::registry::{KernelCrate, Registry};

use crate::error::CliError;
use crate::method::Method;
use crate::{eval, generate, list, pretty, usage};

/// The subcommands every registry's command line has.
#[derive(Debug, Clone, Subcommand)]
pub enum FactorCommand {
    /// Evaluate a factor's residual and Jacobians at a point given as JSON:
    /// {"factor": NAME, "variables": {...}, "constants": {...}} (see `list`).
    /// Quaternions are [x, y, z, w].
    Eval {
        /// The JSON input file, or `-` for standard input: UTF-8, at most
        /// 16 MiB, no key given twice.
        file: String,
        /// How the Jacobians are computed.
        #[arg(long, value_enum, default_value_t)]
        method: Method,
    },
    /// List the registered factors: residual dimension, variables, tangents,
    /// input fields, kernels and their operation counts.
    List {
        /// Machine-readable JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Rewrite the kernel crate's sources (`src/*.rs`) from the current
    /// factor definitions, printing each kernel's operation counts and the
    /// generation time.
    Generate {
        /// The kernel crate's directory [default: the one this binary was
        /// built for]. DIR must be that crate (its Cargo.toml names the
        /// package), or new or empty: then a standalone Cargo.toml is written
        /// first. Any other directory is refused untouched.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// Exit 1, naming the files, when the kernel crate's sources differ from
    /// what `generate` would write (exit 2 when the crate is not found or a
    /// file cannot be read).
    Check {
        /// The kernel crate's directory [default: the one this binary was
        /// built for].
        #[arg(long, value_name = "DIR")]
        dir: Option<PathBuf>,
    },
}

/// What `--help` says after the subcommands: exit codes and the error line.
pub const AFTER_HELP: &str = "Exit codes: 0 success; 1 degenerate geometry or non-finite \
    result, stale generated files, or a solve that cannot start or stops on a failure; 2 \
    invalid input, data file or usage. Errors are one line on stderr: `error: <field path>: \
    <what>`; keys that are not plain identifiers are quoted and JSON-escaped \
    (`variables[\"a\\nb\"]`), names and values from the input cut after 64 characters (`…`).";

impl Registry {
    /// Runs `command` on this registry's factors: the text to print, or
    /// the error to report ([`report`]).
    pub fn execute(&self, command: &FactorCommand) -> Result<String, CliError> {
        match command {
            FactorCommand::Eval { file, method } => eval::run(self, file, *method),
            FactorCommand::List { json: true } => Ok(pretty::to_string(&list::json(self))),
            FactorCommand::List { json: false } => Ok(list::table(self).trim_end().to_owned()),
            FactorCommand::Generate { out } => generate::run_generate(self, out.as_deref()),
            FactorCommand::Check { dir } => generate::run_check(self, dir.as_deref()),
        }
    }

    /// The whole command line of a binary called `name`: parses the
    /// process's arguments (a usage error exits 2), runs the subcommand and
    /// reports its result.
    pub fn run(&self, name: &'static str) -> ExitCode {
        let command = FactorCommand::augment_subcommands(
            clap::Command::new(name)
                .about("Residuals and exact Jacobians of the factors registered in this binary")
                .after_help(AFTER_HELP)
                .subcommand_required(true)
                .arg_required_else_help(true),
        );
        slamjac_io::atomic::fail_writes_past_the_file_size_limit();
        match command
            .try_get_matches()
            .and_then(|matches| FactorCommand::from_arg_matches(&matches))
        {
            Ok(command) => report(self.execute(&command)),
            Err(error) => usage::print(&error, name),
        }
    }
}

/// Prints a subcommand's result: the text on stdout (exit 0), or the error
/// as one line on stderr with its exit code ([`CliError::exit_code`]).
pub fn report(result: Result<String, CliError>) -> ExitCode {
    match result {
        Ok(text) => match writeln!(std::io::stdout().lock(), "{text}") {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: <stdout>: {e}");
                ExitCode::FAILURE
            }
        },
        Err(error) => {
            eprintln!("{}", error.one_line());
            ExitCode::from(error.exit_code())
        }
    }
}

#[cfg(test)]
mod tests {
    use slam_factors::{BetweenFactor, PointReprojection};

    use super::*;

    #[test]
    fn a_registry_lists_and_evaluates_its_own_factors_only() {
        let registry = Registry::new().with::<BetweenFactor>();
        let table = registry
            .execute(&FactorCommand::List { json: false })
            .unwrap();
        assert!(
            table.starts_with("between  (residual dimension 6)"),
            "{table}"
        );
        assert!(!table.contains("point_reprojection"), "{table}");
        let input = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/examples/inputs/point_reprojection.json"
        );
        let eval = |registry: &Registry| {
            registry.execute(&FactorCommand::Eval {
                file: input.to_owned(),
                method: Method::Dual,
            })
        };
        let error = eval(&registry).unwrap_err().to_string();
        assert!(error.ends_with("known factors: between"), "{error}");
        let output = eval(&registry.with::<PointReprojection>()).unwrap();
        assert!(output.contains("\"method\": \"dual\""), "{output}");
    }
}
