//! `slamjac`: evaluate SLAM factors and their exact tangent-space Jacobians.
//!
//! ```text
//! slamjac eval FILE [--method dual|numeric]   # FILE may be `-` for stdin
//! slamjac list [--json]
//! ```
//!
//! Exit codes: 0 success; 1 degenerate geometry or a non-finite result;
//! 2 rejected input or a usage error. Errors are one line on stderr,
//! `error: <field path>: <what>`.

use std::io::Write;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use slamjac::{Method, eval, list, pretty};

#[derive(Debug, Parser)]
#[command(
    name = "slamjac",
    version,
    about = "Exact tangent-space Jacobians of SLAM factors",
    after_help = "Exit codes: 0 success; 1 degenerate geometry or non-finite result; \
                  2 invalid input or usage. Errors are one line on stderr: \
                  `error: <field path>: <what>`."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Evaluate a factor's residual and Jacobians at a point given as JSON:
    /// {"factor": NAME, "variables": {...}, "constants": {...}} (see `slamjac list`).
    Eval {
        /// The JSON input file, or `-` for standard input.
        file: String,
        /// How the Jacobians are computed.
        #[arg(long, value_enum, default_value_t)]
        method: Method,
    },
    /// List the registered factors: residual dimension, variables, tangents.
    List {
        /// Machine-readable JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let output = match cli.command {
        Command::Eval { file, method } => eval::run(&file, method),
        Command::List { json: true } => Ok(pretty::to_string(&list::json())),
        Command::List { json: false } => Ok(list::table().trim_end().to_owned()),
    };
    match output {
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
