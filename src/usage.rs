//! Command-line usage errors as one line. clap renders an error as a
//! paragraph (`error: the following required arguments were not
//! provided:` and the missing argument on the next line), then a blank line,
//! a usage summary and a tip; this keeps the first paragraph, joined into
//! one line and made printable, so a usage error reads like every other
//! error (`error: …`, exit 2).

use std::process::ExitCode;

use clap::error::ErrorKind;
use slamjac_problem::field_path::escape_unprintable;

use crate::error::EXIT_BAD_INPUT;

/// What to print for clap's `error` of the command `program`, and the exit
/// code: help and version as clap renders them (exit 0); anything else one
/// line on stderr, exit 2.
pub fn report(error: &clap::Error, program: &str) -> (Output, u8) {
    match error.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            (Output::Stdout(error.render().to_string()), 0)
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => (
            Output::Stderr(format!(
                "error: a command is needed; see `{program} --help`"
            )),
            EXIT_BAD_INPUT,
        ),
        _ => (
            Output::Stderr(one_line(&error.render().to_string())),
            EXIT_BAD_INPUT,
        ),
    }
}

/// Prints [`report`]'s output where it goes and returns its exit code.
pub fn print(error: &clap::Error, program: &str) -> ExitCode {
    let (output, code) = report(error, program);
    match output {
        Output::Stdout(text) => print!("{text}"),
        Output::Stderr(line) => eprintln!("{line}"),
    }
    ExitCode::from(code)
}

/// Where a report goes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Output {
    /// Help or version text, as rendered.
    Stdout(String),
    /// One line, `error: …`.
    Stderr(String),
}

/// clap's rendered error as one printable line: its first paragraph, lines
/// trimmed and joined by spaces, `error: ` once in front.
fn one_line(rendered: &str) -> String {
    let paragraph: Vec<&str> = rendered
        .lines()
        .map(str::trim)
        .skip_while(|l| l.is_empty())
        .take_while(|l| !l.is_empty())
        .collect();
    let text = paragraph.join(" ");
    let text = text.strip_prefix("error: ").unwrap_or(&text);
    format!("error: {}", escape_unprintable(text))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_paragraph_becomes_one_line() {
        let rendered = "error: the following required arguments were not provided:\n  \
                        <DOCUMENT>\n\nUsage: slamjac audit --symbols <FILE> <DOCUMENT>\n\n\
                        For more information, try '--help'.\n";
        assert_eq!(
            one_line(rendered),
            "error: the following required arguments were not provided: <DOCUMENT>"
        );
        assert_eq!(
            one_line("error: unexpected argument '\u{feff}--x\u{1b}' found\n\n  tip: …\n"),
            "error: unexpected argument '\\ufeff--x\\u001b' found"
        );
    }
}
