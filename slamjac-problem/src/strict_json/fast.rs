//! The common case of [`super::parse_json`] and [`super::parse_json_from`],
//! fast: a document of plain JSON (strings without escapes, finite numbers,
//! no key twice in an object, nested at most [`MAX_DEPTH`] deep) read
//! straight into its [`Document`] by recursive descent over the bytes as
//! they stream in. Anything else — an escape, any fault, a failed read — is
//! not decided here: the parse stops and hands back the bytes read so far
//! (and the read's error), for the strict parser to read from the start
//! ([`Replay`]), which gives the value or the error.

use std::io::{self, BufRead, Read};

use super::MAX_DEPTH;
use crate::document::{Builder, Document};

/// What the fast parse gives: the document, or the input to replay.
pub(super) enum Parsed<R> {
    Document(Document),
    Replay(Replay<R>),
}

/// The bytes read, then the failed read's error if one stopped the input,
/// then the rest of the source: the same input as the source gave it.
pub(super) struct Replay<R> {
    seen: io::Cursor<Vec<u8>>,
    error: Option<io::Error>,
    rest: R,
}

impl<R: Read> Read for Replay<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.seen.read(buf)?;
        if n > 0 || buf.is_empty() {
            return Ok(n);
        }
        match self.error.take() {
            Some(error) => Err(error),
            None => self.rest.read(buf),
        }
    }
}

/// Parses `reader`'s document (see the module documentation).
pub(super) fn parse<R: BufRead>(reader: R) -> Parsed<R> {
    let mut input = Input {
        reader,
        bytes: Vec::new(),
        at: 0,
        error: None,
        ended: false,
        builder: Builder::default(),
    };
    let read = input.value(0).filter(|()| {
        input.whitespace();
        input.peek().is_none() && input.error.is_none()
    });
    match read {
        Some(()) => Parsed::Document(input.builder.finish()),
        None => Parsed::Replay(Replay {
            seen: io::Cursor::new(input.bytes),
            error: input.error,
            rest: input.reader,
        }),
    }
}

/// The bytes read so far, where the parse is among them, and the document
/// read.
struct Input<R> {
    reader: R,
    bytes: Vec<u8>,
    at: usize,
    error: Option<io::Error>,
    ended: bool,
    builder: Builder,
}

impl<R: BufRead> Input<R> {
    /// Reads the source's next chunk; `false` at its end or at a failed
    /// read (kept in `error`).
    fn more(&mut self) -> bool {
        if self.ended {
            return false;
        }
        match self.reader.fill_buf() {
            Ok([]) => self.ended = true,
            Ok(chunk) => {
                let n = chunk.len();
                self.bytes.extend_from_slice(chunk);
                self.reader.consume(n);
            }
            Err(error) => {
                self.error = Some(error);
                self.ended = true;
            }
        }
        !self.ended
    }

    /// The next byte, `None` at the end of the input.
    fn peek(&mut self) -> Option<u8> {
        if self.at == self.bytes.len() && !self.more() {
            return None;
        }
        Some(self.bytes[self.at])
    }

    fn whitespace(&mut self) {
        while let Some(b' ' | b'\n' | b'\t' | b'\r') = self.peek() {
            self.at += 1;
        }
    }

    /// Steps over `byte`, `None` if another comes.
    fn expect(&mut self, byte: u8) -> Option<()> {
        self.whitespace();
        (self.peek()? == byte).then(|| self.at += 1)
    }

    /// Reads the value starting here, within `depth` arrays and objects;
    /// `None` where it is not plain JSON.
    fn value(&mut self, depth: usize) -> Option<()> {
        self.whitespace();
        match self.peek()? {
            b'{' if depth < MAX_DEPTH => self.object(depth + 1),
            b'[' if depth < MAX_DEPTH => self.array(depth + 1),
            b'"' => {
                let span = self.string()?;
                let text = std::str::from_utf8(&self.bytes[span]).ok()?;
                self.builder.string(text);
                Some(())
            }
            b't' => self.word(b"true").map(|()| self.builder.bool(true)),
            b'f' => self.word(b"false").map(|()| self.builder.bool(false)),
            b'n' => self.word(b"null").map(|()| self.builder.null()),
            b'-' | b'0'..=b'9' => self.number().map(|x| self.builder.number(x)),
            _ => None,
        }
    }

    fn word(&mut self, word: &[u8]) -> Option<()> {
        for &byte in word {
            (self.peek()? == byte).then(|| self.at += 1)?;
        }
        Some(())
    }

    fn object(&mut self, depth: usize) -> Option<()> {
        self.at += 1;
        let opened = self.builder.open();
        self.whitespace();
        if self.peek()? != b'}' {
            loop {
                self.whitespace();
                if self.peek()? != b'"' {
                    return None;
                }
                let span = self.string()?;
                let key = std::str::from_utf8(&self.bytes[span]).ok()?;
                self.builder.key(key);
                self.expect(b':')?;
                self.value(depth)?;
                self.whitespace();
                match self.peek()? {
                    b',' => self.at += 1,
                    b'}' => break,
                    _ => return None,
                }
            }
        }
        self.at += 1;
        self.builder.object(opened).then_some(())
    }

    fn array(&mut self, depth: usize) -> Option<()> {
        self.at += 1;
        let opened = self.builder.open();
        self.whitespace();
        if self.peek()? != b']' {
            loop {
                self.value(depth)?;
                self.whitespace();
                match self.peek()? {
                    b',' => self.at += 1,
                    b']' => break,
                    _ => return None,
                }
            }
        }
        self.at += 1;
        self.builder.array(opened);
        Some(())
    }

    /// A string without escapes or control characters: where its text
    /// lies among the bytes.
    fn string(&mut self) -> Option<std::ops::Range<usize>> {
        self.at += 1;
        let start = self.at;
        loop {
            let rest = &self.bytes[self.at..];
            match rest
                .iter()
                .position(|&b| b == b'"' || b == b'\\' || b < 0x20)
            {
                Some(k) if rest[k] == b'"' => {
                    let end = self.at + k;
                    self.at = end + 1;
                    return Some(start..end);
                }
                Some(_) => return None,
                None => {
                    self.at = self.bytes.len();
                    if !self.more() {
                        return None;
                    }
                }
            }
        }
    }

    /// A finite number: `-? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?`.
    fn number(&mut self) -> Option<f64> {
        let start = self.at;
        if self.peek()? == b'-' {
            self.at += 1;
        }
        match self.peek()? {
            b'0' => self.at += 1,
            b'1'..=b'9' => self.digits(),
            _ => return None,
        }
        if self.peek() == Some(b'.') {
            self.at += 1;
            self.peek()?.is_ascii_digit().then_some(())?;
            self.digits();
        }
        if let Some(b'e' | b'E') = self.peek() {
            self.at += 1;
            if let Some(b'+' | b'-') = self.peek() {
                self.at += 1;
            }
            self.peek()?.is_ascii_digit().then_some(())?;
            self.digits();
        }
        // Rust's float syntax contains JSON's (as the strict parser reads
        // it); beyond the range it reads ±∞, left to the strict parser.
        let literal = std::str::from_utf8(&self.bytes[start..self.at]).ok()?;
        literal.parse::<f64>().ok().filter(|x| x.is_finite())
    }

    fn digits(&mut self) {
        while self.peek().is_some_and(|b| b.is_ascii_digit()) {
            self.at += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{parse_json, parse_json_from};
    use super::*;
    use serde_json::Value;

    /// Documents of the fast path's subset, and documents outside it (each
    /// read by the strict parser: a value or an error).
    const PLAIN: &[&str] = &[
        r#"{"a": [1.0, -2.5e3, 0, -0, 1E-5, 7e+2, true, false, null, "xé€😀"], "b": {"c": {}}, "": []}"#,
        "  [ ]\n",
        "\"text\"",
        "-12.5",
        "[1e-999, 123456789012345678901234567890, 0.1000000000000000055511151231257827]",
    ];
    const OTHER: &[&str] = &[
        r#"{"a": "x\n\u00e9"}"#,
        r#"{"a": 1, "b": 2, "a": 3}"#,
        "[1, -1e999]",
        "[01]",
        "[1,]",
        "{\"a\" 1}",
        "[1] 2",
        "",
        "\u{feff}[]",
        "[-]",
        "[1.]",
        "[1e]",
        "[.5]",
        "[+1]",
        "[\"a\tb\"]",
        "[tru]",
        "{\"a\": 1,}",
        "{,}",
        "[1 2]",
        "\"\\ud800\"",
    ];

    /// The value or the error (its path and message).
    fn outcome(
        parsed: Result<Document, crate::error::InputError>,
    ) -> Result<Value, (String, String)> {
        parsed
            .map(|d| d.root().to_value())
            .map_err(|e| (e.path, e.message))
    }

    #[test]
    fn plain_documents_are_read_as_the_strict_parser_reads_them() {
        let nested = format!("{}{}", "[".repeat(MAX_DEPTH), "]".repeat(MAX_DEPTH));
        for text in PLAIN.iter().copied().chain([nested.as_str()]) {
            let expected = super::super::events(text, "x").unwrap();
            for chunk in [1, 3, 8192] {
                let reader = io::BufReader::with_capacity(chunk, text.as_bytes());
                match parse(reader) {
                    Parsed::Document(document) => {
                        assert_eq!(document.root().to_value(), expected, "{text}")
                    }
                    Parsed::Replay(_) => panic!("not read by the fast path: {text}"),
                }
            }
        }
    }

    #[test]
    fn other_documents_are_left_to_the_strict_parser() {
        let deep = format!("{}{}", "[".repeat(MAX_DEPTH + 1), "]".repeat(MAX_DEPTH + 1));
        for text in OTHER.iter().copied().chain([deep.as_str()]) {
            for chunk in [1, 3, 8192] {
                let reader = || io::BufReader::with_capacity(chunk, text.as_bytes());
                assert!(matches!(parse(reader()), Parsed::Replay(_)), "{text}");
                let strict = super::super::events(text, "x");
                assert_eq!(
                    outcome(parse_json_from(reader(), "x")),
                    strict.clone().map_err(|e| (e.path, e.message)),
                    "{text}"
                );
                assert_eq!(
                    outcome(parse_json(text, "x")),
                    strict.map_err(|e| (e.path, e.message)),
                    "{text}"
                );
            }
        }
    }

    /// A source that gives `bytes`, then fails.
    struct Failing<'a> {
        bytes: &'a [u8],
    }

    impl Read for Failing<'_> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            if self.bytes.is_empty() {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    "the disk is gone",
                ));
            }
            let n = self.bytes.read(buf)?;
            Ok(n)
        }
    }

    /// A read that fails midway is reported as the strict parser reports
    /// it; a fault before it, as the fault.
    #[test]
    fn a_failed_read_is_replayed_where_it_happened() {
        let error =
            parse_json_from(io::BufReader::new(Failing { bytes: b"[1, 2" }), "in").unwrap_err();
        assert_eq!(
            (error.path.as_str(), error.message.as_str()),
            ("in", "the disk is gone")
        );
        let error =
            parse_json_from(io::BufReader::new(Failing { bytes: b"[1, x" }), "in").unwrap_err();
        assert!(
            error.message.starts_with("invalid JSON at line 1 column 5"),
            "{error}"
        );
    }
}
