//! The one error type of the readers and writers.

/// What went wrong reading or writing a data file, as one line.
///
/// `Display` gives `FILE:LINE: what` for a problem at a line of the input
/// (1-based line, the file name as given) and `FILE: what` for a problem with
/// the file as a whole (it cannot be opened, it is over the size cap, or the
/// problem to be written is invalid). A command line prints it after its own
/// `error: ` prefix.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A problem at a line of the input.
    #[error("{file}:{line}: {what}")]
    AtLine {
        /// The file name as given (control characters escaped).
        file: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong, one line.
        what: String,
    },
    /// A problem with a file as a whole.
    #[error("{file}: {what}")]
    File {
        /// The file name as given (control characters escaped).
        file: String,
        /// What is wrong, one line.
        what: String,
    },
}

impl Error {
    /// An error at `line` of `file`.
    pub(crate) fn at_line(file: &str, line: usize, what: impl Into<String>) -> Self {
        Error::AtLine {
            file: one_line(file),
            line,
            what: one_line(&what.into()),
        }
    }

    /// An error about `file` as a whole.
    pub(crate) fn file(file: &str, what: impl Into<String>) -> Self {
        Error::File {
            file: one_line(file),
            what: one_line(&what.into()),
        }
    }

    /// The same error with `context: ` put before what is wrong.
    pub(crate) fn context(self, context: impl std::fmt::Display) -> Self {
        match self {
            Error::AtLine { file, line, what } => Error::AtLine {
                file,
                line,
                what: format!("{context}: {what}"),
            },
            Error::File { file, what } => Error::File {
                file,
                what: format!("{context}: {what}"),
            },
        }
    }
}

/// `text` with every unprintable character escaped
/// (`slamjac_io::printable`: controls, separators, format characters such
/// as a byte-order mark), so that an error stays one printable line
/// whatever the input holds.
pub(crate) fn one_line(text: &str) -> String {
    slamjac_io::printable::escape(text).into_owned()
}

/// Item `index` (from 0) of `count` in words, counted from 1 as every
/// message of the readers counts: `ordinal("camera", 0, 3)` is
/// `camera 1 of 3`. Indices and ids written in a file are shown as written.
pub fn ordinal(item: &str, index: usize, count: usize) -> String {
    format!("{item} {} of {count}", index + 1)
}

/// A token of the input, quoted for an error message: control characters
/// escaped and anything past 40 characters cut.
pub(crate) fn quoted(token: &str) -> String {
    const SHOWN: usize = 40;
    let mut shown: String = token.chars().take(SHOWN).collect();
    if shown.len() < token.len() {
        shown.push('…');
    }
    format!("`{}`", one_line(&shown))
}
