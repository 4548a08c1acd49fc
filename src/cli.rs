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
//! use slamjac::cli::{CommandLine, KernelCrate, Provenance, Registry};
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
//!         .solve_with_kernel::<PointReprojection>() // `my-cli solve PROBLEM.json`
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
//! With `slamjac`'s feature `solve`, `my-cli solve PROBLEM.json` solves a
//! problem file ([`SolveCommand`]; its format in `slamjac::solve::problem_file`
//! and the guide's "Solving") of the factors registered with
//! [`Registry::solve_with_kernel`] (their generated kernel in apex-solver's
//! chart) or [`Registry::solve_with_dual`] (dual numbers in that chart).
//!
//! A binary with subcommands of its own flattens [`FactorCommand`] into its
//! clap command and hands it to [`CommandLine::execute`] (and a
//! [`SolveCommand`] to [`CommandLine::solve`]); `slamjac`'s `main` does so
//! beside `audit`, `synth-bal` and its `solve` of data files.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, FromArgMatches, Subcommand, ValueEnum};

pub use factor_codegen::{HostSpec, KernelSpec, Provenance};
/// apex-solver's chart, the host of `solve` ([`HostSpec::of`], [`Registry::solve_with_kernel`]).
pub use factor_core::host::Apex;

pub use crate::generate::Lang;
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
    /// Rewrite the kernel crate's sources (`src/*.rs`, and its C++ in
    /// `cpp/`) from the current factor definitions, printing each kernel's
    /// operation counts and the generation time.
    Generate {
        /// The kernel crate's directory [default: the one this binary was
        /// built for]. DIR must be that crate (its Cargo.toml names the
        /// package), or new or empty: then a standalone Cargo.toml is written
        /// first. Any other directory is refused untouched.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// The languages to write: `rust` (the crate's `src/`) and `cpp`
        /// (a header-only C++17 library in its `cpp/`, with Ceres cost
        /// functions and manifolds for the factors generated for Ceres);
        /// repeat or separate by commas [default: rust, and cpp when the
        /// crate has a `cpp/` directory].
        #[arg(long, value_enum, value_delimiter = ',', value_name = "LANG")]
        lang: Vec<Lang>,
    },
    /// Exit 1, naming the files, when the kernel crate's sources differ from
    /// what `generate` would write (exit 2 when the crate is not found or a
    /// file cannot be read).
    Check {
        /// The kernel crate's directory [default: the one this binary was
        /// built for].
        #[arg(long, value_name = "DIR")]
        dir: Option<PathBuf>,
        /// The languages to compare [default: rust, and cpp when the crate
        /// has a `cpp/` directory].
        #[arg(long, value_enum, value_delimiter = ',', value_name = "LANG")]
        lang: Vec<Lang>,
    },
}

/// `solve PROBLEM`: a problem file of the registry's factors solved by
/// Levenberg–Marquardt (apex-solver), a line per iteration and a summary;
/// `--output` writes the file back with the solution. Needs `slamjac`'s
/// feature `solve`.
#[derive(Debug, Clone, Args)]
pub struct SolveCommand {
    /// The file to solve: a problem file (JSON: `slamjac_problem`,
    /// `variables`, `factors`, optional `truth`; see the guide's "Solving").
    /// `slamjac solve` also reads data files: BAL, Bundler, g2o, EDGE3,
    /// KITTI VO (any of its three `VO_*.txt` files).
    pub file: PathBuf,
    /// How the factors are linearized: their generated kernels where they
    /// have one, or dual numbers (for comparison).
    #[arg(long, value_enum, default_value_t)]
    pub kernels: KernelChoice,
    /// The most iterations (accepted or rejected steps): a guard, not a
    /// tolerance (g2o's own plane graphs need 106–123).
    #[arg(long, default_value_t = 500, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub max_iterations: u64,
    /// A robust loss on every factor without one of its own, `huber:δ` or
    /// `cauchy:δ` (δ in whitened units; for `slamjac solve`'s reprojection
    /// data files, pixels).
    #[arg(long, value_name = "LOSS:δ")]
    pub robust: Option<String>,
    /// Write the optimized problem here, in the input's format. Outputs are
    /// checked before any work (none may name an input or the other output)
    /// and written whole or not at all.
    #[arg(long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Write an SVG plot here: the cost per iteration and, for
    /// reprojection data files, the reprojection errors before and after.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
}

#[cfg(feature = "solve")]
impl SolveCommand {
    /// What `solve` is asked for: a problem file, apex-solver, no other
    /// data (`slamjac solve` sets the options only data files have).
    ///
    /// # Errors
    ///
    /// [`CliError::Usage`] for a `--robust` that is not a loss.
    pub fn args(&self) -> Result<crate::solve::SolveArgs, CliError> {
        use slam_problems::Kernels;
        use slam_problems::g2o_edges::LandmarkFactors;
        let robust = self
            .robust
            .as_deref()
            .map(|r| {
                r.parse()
                    .map_err(|e| CliError::Usage(format!("--robust: {e}")))
            })
            .transpose()?;
        Ok(crate::solve::SolveArgs {
            file: self.file.clone(),
            format: None,
            kernels: match self.kernels {
                KernelChoice::Generated => Kernels::Generated,
                KernelChoice::Dual => Kernels::Dual,
            },
            solver: crate::solve::SolverChoice::Auto,
            max_iterations: usize::try_from(self.max_iterations).unwrap_or(usize::MAX),
            robust,
            output: self.output.clone(),
            plot: self.plot.clone(),
            landmarks: LandmarkFactors::G2o,
            truth: None,
        })
    }
}

/// `--kernels`: how `solve` linearizes its factors.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum KernelChoice {
    /// The generated kernels (dual numbers for a factor without one).
    #[default]
    Generated,
    /// Dual numbers through the same factors.
    Dual,
}

/// A registry's whole command line: [`FactorCommand`] and `solve`.
#[derive(Debug, Clone, Subcommand)]
enum RegistryCommand {
    #[command(flatten)]
    Factors(FactorCommand),
    /// Solve a problem file of the registered factors by Levenberg–Marquardt
    /// (apex-solver): a line per iteration and a summary; errors against the
    /// file's `truth` when it has one. Needs slamjac's feature `solve`.
    #[command(allow_negative_numbers = true)]
    Solve(SolveCommand),
}

/// What a binary built without `slamjac`'s feature `solve` says to `solve`.
pub const WITHOUT_SOLVE: &str = "solve: this binary was built without slamjac's feature \
    `solve`; enable it (`slamjac = { ..., features = [\"solve\"] }`, or for slamjac itself \
    `cargo run --release --features solve -- solve FILE`)";

/// What `--help` says after the subcommands: exit codes and the error line.
pub const AFTER_HELP: &str = "Exit codes: 0 success; 1 degenerate geometry or non-finite \
    result, stale generated files, or a solve that cannot start or stops on a failure; 2 \
    invalid input, data file or usage. Errors are one line on stderr: `error: <field path>: \
    <what>`; keys that are not plain identifiers are quoted and JSON-escaped \
    (`variables[\"a\\nb\"]`), names and values from the input cut after 64 characters (`…`).";

/// The command line of a [`Registry`] (the registry itself is the crate
/// `slamjac-registry`'s, which parses no argument and prints nothing):
/// `use slamjac::cli::CommandLine` and call [`CommandLine::run`] on it.
pub trait CommandLine {
    /// Runs `command` on this registry's factors: the text to print, or
    /// the error to report ([`report`]).
    fn execute(&self, command: &FactorCommand) -> Result<String, CliError>;

    /// Solves the problem file of `command` with this registry's factors
    /// (those registered for `solve`), printing a line per iteration; the
    /// summary, or the error to report ([`report`]).
    fn solve(&self, command: &SolveCommand) -> Result<String, CliError>;

    /// The whole command line of a binary called `name`: parses the
    /// process's arguments (a usage error exits 2), runs the subcommand and
    /// reports its result.
    fn run(&self, name: &'static str) -> ExitCode;
}

impl CommandLine for Registry {
    fn execute(&self, command: &FactorCommand) -> Result<String, CliError> {
        match command {
            FactorCommand::Eval { file, method } => eval::run(self, file, *method),
            FactorCommand::List { json: true } => Ok(pretty::to_string(&list::json(self))),
            FactorCommand::List { json: false } => Ok(list::table(self).trim_end().to_owned()),
            FactorCommand::Generate { out, lang } => {
                generate::run_generate(self, out.as_deref(), lang)
            }
            FactorCommand::Check { dir, lang } => generate::run_check(self, dir.as_deref(), lang),
        }
    }

    fn solve(&self, command: &SolveCommand) -> Result<String, CliError> {
        #[cfg(feature = "solve")]
        {
            crate::solve::run_problem_file(&command.args()?, self)
        }
        #[cfg(not(feature = "solve"))]
        {
            let _ = command;
            Err(CliError::Usage(WITHOUT_SOLVE.into()))
        }
    }

    fn run(&self, name: &'static str) -> ExitCode {
        // The about after the subcommands: clap's derive gives the command
        // the doc comment of `RegistryCommand` otherwise.
        let command = RegistryCommand::augment_subcommands(clap::Command::new(name))
            .about(
                "Residuals and exact Jacobians of the factors registered in this binary; \
                 problem files of them solved",
            )
            .after_help(AFTER_HELP)
            .subcommand_required(true)
            .arg_required_else_help(true);
        slamjac_io::atomic::fail_writes_past_the_file_size_limit();
        match command
            .try_get_matches()
            .and_then(|matches| RegistryCommand::from_arg_matches(&matches))
        {
            Ok(RegistryCommand::Factors(command)) => report(self.execute(&command)),
            Ok(RegistryCommand::Solve(command)) => report(self.solve(&command)),
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
