//! Reading text input safely: the size caps, UTF-8 checking, line numbers,
//! and tokens parsed into numbers with errors at their line.
//!
//! Two ways through a file: [`Tokens`] walks whitespace-separated tokens
//! across lines (BAL and Bundler, which C++ readers scan with `>>`), and
//! [`Lines`] hands out one line at a time whose [`Fields`] must all be used
//! (g2o, EDGE3, KITTI VO: one record per line).

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use crate::error::{Error, quoted};

/// Largest input file read, in bytes (4 GiB): larger files are rejected
/// before anything is read.
pub const MAX_FILE_BYTES: u64 = 4 << 30;

/// Longest line read, in bytes (64 MiB, without its line end).
pub const MAX_LINE_BYTES: usize = 64 << 20;

/// Largest magnitude of a number read or written (1e100), so that squares
/// and products of a few of them stay finite.
pub const MAX_MAGNITUDE: f64 = 1e100;

/// At most this many items are reserved ahead from a count a file claims;
/// longer vectors grow as the items are actually read.
pub(crate) const MAX_RESERVED: usize = 1 << 16;

/// Opens `path` for reading, after checking it against [`MAX_FILE_BYTES`].
pub(crate) fn open(path: &Path) -> Result<(BufReader<File>, String), Error> {
    let name = path.display().to_string();
    let file = File::open(path).map_err(|e| Error::file(&name, format!("cannot open: {e}")))?;
    let size = file
        .metadata()
        .map_err(|e| Error::file(&name, format!("cannot read its size: {e}")))?
        .len();
    if size > MAX_FILE_BYTES {
        return Err(Error::file(
            &name,
            format!("{size} bytes is over the cap of {MAX_FILE_BYTES} bytes (4 GiB)"),
        ));
    }
    Ok((BufReader::with_capacity(1 << 16, file), name))
}

/// The lines of an input, with their numbers.
pub(crate) struct Lines<R> {
    reader: R,
    file: String,
    /// Number of the line in `text` (0 before the first).
    number: usize,
    text: String,
    bytes_read: u64,
}

impl<R: BufRead> Lines<R> {
    pub(crate) fn new(reader: R, file: &str) -> Self {
        Lines {
            reader,
            file: file.to_owned(),
            number: 0,
            text: String::new(),
            bytes_read: 0,
        }
    }

    pub(crate) fn file(&self) -> &str {
        &self.file
    }

    /// Number of the current line; 1 before any line is read, so that an
    /// empty input is reported at line 1.
    pub(crate) fn number(&self) -> usize {
        self.number.max(1)
    }

    /// The current line's text (empty before the first).
    pub(crate) fn current_text(&self) -> &str {
        &self.text
    }

    /// An error at the current line.
    pub(crate) fn error(&self, what: impl Into<String>) -> Error {
        Error::at_line(&self.file, self.number(), what)
    }

    /// Reads the next line into `text` (without its `\n` or `\r\n`); false
    /// at the end of the input.
    fn advance(&mut self) -> Result<bool, Error> {
        let mut bytes = std::mem::take(&mut self.text).into_bytes();
        bytes.clear();
        let cap = MAX_LINE_BYTES as u64 + 2; // the line, `\r\n`, one more to see it overflow
        let read = (&mut self.reader)
            .take(cap)
            .read_until(b'\n', &mut bytes)
            .map_err(|e| {
                Error::at_line(&self.file, self.number + 1, format!("cannot read: {e}"))
            })?;
        if read == 0 {
            return Ok(false);
        }
        self.number += 1;
        self.bytes_read += read as u64;
        if self.bytes_read > MAX_FILE_BYTES {
            return Err(self.error(format!(
                "the input is over the cap of {MAX_FILE_BYTES} bytes (4 GiB)"
            )));
        }
        if bytes.last() == Some(&b'\n') {
            bytes.pop();
            if bytes.last() == Some(&b'\r') {
                bytes.pop();
            }
        }
        if bytes.len() > MAX_LINE_BYTES {
            return Err(self.error(format!(
                "line longer than the cap of {MAX_LINE_BYTES} bytes (64 MiB)"
            )));
        }
        match String::from_utf8(bytes) {
            Ok(text) => {
                self.text = text;
                Ok(true)
            }
            Err(e) => {
                let column = e.utf8_error().valid_up_to() + 1;
                Err(self.error(format!("not UTF-8 text (invalid byte at column {column})")))
            }
        }
    }

    /// The next line, or `None` at the end of the input.
    pub(crate) fn next_line(&mut self) -> Result<Option<Line<'_>>, Error> {
        Ok(self.advance()?.then(|| Line {
            text: &self.text,
            number: self.number,
            file: &self.file,
        }))
    }

    /// The next line that has a token and is not a `#` comment, or `None`
    /// at the end of the input.
    pub(crate) fn next_record(&mut self) -> Result<Option<Line<'_>>, Error> {
        while self.advance()? {
            let first = self.text.split_ascii_whitespace().next();
            if first.is_some_and(|t| !t.starts_with('#')) {
                return Ok(Some(Line {
                    text: &self.text,
                    number: self.number,
                    file: &self.file,
                }));
            }
        }
        Ok(None)
    }
}

/// One line of the input.
pub(crate) struct Line<'a> {
    pub(crate) text: &'a str,
    pub(crate) number: usize,
    file: &'a str,
}

impl<'a> Line<'a> {
    /// The whitespace-separated fields of the line.
    pub(crate) fn fields(&self) -> Fields<'a> {
        Fields {
            tokens: self.text.split_ascii_whitespace(),
            number: self.number,
            file: self.file,
        }
    }

    /// An error at this line.
    pub(crate) fn error(&self, what: impl Into<String>) -> Error {
        Error::at_line(self.file, self.number, what)
    }
}

/// The fields of one line, taken in order; [`Fields::finish`] checks none is
/// left over.
pub(crate) struct Fields<'a> {
    tokens: std::str::SplitAsciiWhitespace<'a>,
    number: usize,
    file: &'a str,
}

impl Fields<'_> {
    /// The next field, or `None` at the end of the line.
    pub(crate) fn next_token(&mut self) -> Option<&str> {
        self.tokens.next()
    }

    /// Fails if the line has a field left.
    pub(crate) fn finish(mut self) -> Result<(), Error> {
        match self.tokens.next() {
            None => Ok(()),
            Some(extra) => Err(self.error(format!("unexpected extra field {}", quoted(extra)))),
        }
    }
}

impl Cursor for Fields<'_> {
    fn token(&mut self, what: &str) -> Result<&str, Error> {
        self.tokens.next().ok_or_else(|| {
            Error::at_line(self.file, self.number, format!("line ends before {what}"))
        })
    }

    fn error(&self, what: String) -> Error {
        Error::at_line(self.file, self.number, what)
    }
}

/// Whitespace-separated tokens across the lines of an input.
pub(crate) struct Tokens<R> {
    lines: Lines<R>,
    /// Byte offset of the rest of the current line.
    position: usize,
}

impl<R: BufRead> Tokens<R> {
    /// Tokens from the line after the current one of `lines`.
    pub(crate) fn new(lines: Lines<R>) -> Self {
        let position = lines.text.len();
        Tokens { lines, position }
    }

    /// Byte range in the current line of the next token, or `None` at the
    /// end of the input.
    fn next_span(&mut self) -> Result<Option<(usize, usize)>, Error> {
        loop {
            let rest = &self.lines.text[self.position..];
            let start = rest.len() - rest.trim_ascii_start().len();
            if start < rest.len() {
                let token_len = rest[start..]
                    .find(|c: char| c.is_ascii_whitespace())
                    .unwrap_or(rest.len() - start);
                let begin = self.position + start;
                self.position = begin + token_len;
                return Ok(Some((begin, self.position)));
            }
            if !self.lines.advance()? {
                self.position = self.lines.text.len();
                return Ok(None);
            }
            self.position = 0;
        }
    }

    /// Fails if any token is left.
    pub(crate) fn finish(&mut self, after: &str) -> Result<(), Error> {
        match self.next_span()? {
            None => Ok(()),
            Some((begin, end)) => {
                let extra = quoted(&self.lines.text[begin..end]);
                Err(self
                    .lines
                    .error(format!("unexpected {extra} after {after}")))
            }
        }
    }
}

impl<R: BufRead> Cursor for Tokens<R> {
    fn token(&mut self, what: &str) -> Result<&str, Error> {
        match self.next_span()? {
            Some((begin, end)) => Ok(&self.lines.text[begin..end]),
            None => Err(self.lines.error(format!("the file ends before {what}"))),
        }
    }

    fn error(&self, what: String) -> Error {
        self.lines.error(what)
    }
}

/// Numbers from a stream of tokens, with errors at the token's line. `what`
/// names the expected value in the error (`"the focal length"`).
pub(crate) trait Cursor {
    /// The next token.
    fn token(&mut self, what: &str) -> Result<&str, Error>;

    /// An error at the line of the last token.
    fn error(&self, what: String) -> Error;

    /// A finite double of magnitude at most [`MAX_MAGNITUDE`].
    fn real(&mut self, what: &str) -> Result<f64, Error> {
        let token = self.token(what)?;
        parse_real(token).map_err(|message| self.error(format!("{what}: {message}")))
    }

    /// Three finite doubles.
    fn vector3(&mut self, what: &str) -> Result<nalgebra::Vector3<f64>, Error> {
        Ok(nalgebra::Vector3::new(
            self.real(what)?,
            self.real(what)?,
            self.real(what)?,
        ))
    }

    /// A non-negative integer.
    fn integer(&mut self, what: &str) -> Result<usize, Error> {
        let token = self.token(what)?;
        parse_integer(token).map_err(|message| self.error(format!("{what}: {message}")))
    }

    /// An integer below `count`, the number of `items` there are.
    fn index(&mut self, what: &str, count: usize, items: &str) -> Result<usize, Error> {
        let value = self.integer(what)?;
        if value < count {
            Ok(value)
        } else {
            Err(self.error(format!(
                "{what} {value} is out of range (there are {count} {items})"
            )))
        }
    }
}

/// `token` as a finite double.
pub(crate) fn parse_real(token: &str) -> Result<f64, String> {
    let value: f64 = token
        .parse()
        .map_err(|_| format!("expected a number, found {}", quoted(token)))?;
    if in_range(value) {
        Ok(value)
    } else if token.bytes().any(|b| b.is_ascii_digit()) {
        Err(format!(
            "{} is out of range (magnitude over 1e100)",
            quoted(token)
        ))
    } else {
        Err(format!("expected a finite number, found {}", quoted(token)))
    }
}

/// Whether `value` is finite and at most [`MAX_MAGNITUDE`] in magnitude.
pub(crate) fn in_range(value: f64) -> bool {
    value.abs() <= MAX_MAGNITUDE
}

/// Whether every value is [in range](in_range).
pub(crate) fn all_in_range<'a>(values: impl IntoIterator<Item = &'a f64>) -> bool {
    values.into_iter().all(|v| in_range(*v))
}

/// `token` as a non-negative integer.
pub(crate) fn parse_integer(token: &str) -> Result<usize, String> {
    if token.bytes().all(|b| b.is_ascii_digit()) && !token.is_empty() {
        token
            .parse()
            .map_err(|_| format!("{} is too large", quoted(token)))
    } else {
        Err(format!(
            "expected a non-negative integer, found {}",
            quoted(token)
        ))
    }
}
