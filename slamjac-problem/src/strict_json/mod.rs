//! JSON text → [`Document`], in one pass over the text, stricter than the
//! JSON grammar where a lenient reading would let a wrong number through:
//!
//! - a key given twice in one object is an error at its path (the last one
//!   would silently win);
//! - a number literal beyond the `f64` range (`1e999`) is an error at its
//!   path, found as the literal is read (so no marked value is left for
//!   later code to confuse with input text);
//! - arrays and objects nested deeper than [`MAX_DEPTH`] are invalid JSON.
//!
//! The events come from `json-event-parser`, which validates the grammar and
//! hands each number over as its literal text: from text in memory
//! ([`parse_json`]) or as a reader streams it in ([`parse_json_from`], so
//! that a source that is not JSON is refused at its first bytes, not once
//! it has been read whole). A problem file of some ten megabytes is mostly
//! plain JSON, which [`parse_json_from`] reads by a fast path first
//! (`fast`); the events decide everything else.

mod fast;

use std::borrow::Cow;
use std::io::{BufReader, Read};

use json_event_parser::{
    JsonEvent, JsonParseError, JsonSyntaxError, ReaderJsonParser, SliceJsonParser,
};
use serde_json::{Map, Number, Value};

use crate::document::Document;
use crate::error::InputError;
use crate::field_path::{self, shortened};
use crate::source::source_name;

/// The deepest nesting of arrays and objects accepted (`serde_json`'s limit).
pub const MAX_DEPTH: usize = 128;

/// Where a value sits in the document being built.
#[derive(Debug)]
enum Step {
    Key(String),
    Index(usize),
}

/// Why the events stopped: a syntax error, or a read that failed (its
/// message, one line).
enum Failure {
    Syntax(JsonSyntaxError),
    Read(String),
}

/// A parser's events, each owned (the reader's borrow its buffer).
trait Events {
    fn event(&mut self) -> Result<JsonEvent<'static>, Failure>;
}

fn owned(event: JsonEvent<'_>) -> JsonEvent<'static> {
    let own = |text: Cow<'_, str>| Cow::Owned(text.into_owned());
    match event {
        JsonEvent::String(text) => JsonEvent::String(own(text)),
        JsonEvent::Number(text) => JsonEvent::Number(own(text)),
        JsonEvent::ObjectKey(text) => JsonEvent::ObjectKey(own(text)),
        JsonEvent::Boolean(b) => JsonEvent::Boolean(b),
        JsonEvent::Null => JsonEvent::Null,
        JsonEvent::StartArray => JsonEvent::StartArray,
        JsonEvent::EndArray => JsonEvent::EndArray,
        JsonEvent::StartObject => JsonEvent::StartObject,
        JsonEvent::EndObject => JsonEvent::EndObject,
        JsonEvent::Eof => JsonEvent::Eof,
    }
}

impl Events for SliceJsonParser<'_> {
    fn event(&mut self) -> Result<JsonEvent<'static>, Failure> {
        self.parse_next().map(owned).map_err(Failure::Syntax)
    }
}

impl<R: Read> Events for ReaderJsonParser<R> {
    fn event(&mut self) -> Result<JsonEvent<'static>, Failure> {
        self.parse_next().map(owned).map_err(|e| match e {
            JsonParseError::Syntax(e) => Failure::Syntax(e),
            JsonParseError::Io(e) => Failure::Read(e.to_string()),
        })
    }
}

/// Builds the value tree from the parser's events, tracking the path.
struct Builder<'a, E> {
    parser: E,
    source: &'a str,
    /// The keys and indices from the root to the value being read.
    steps: Vec<Step>,
}

impl<E: Events> Builder<'_, E> {
    /// The path of the value being read, as errors show it.
    fn path(&self) -> String {
        self.steps
            .iter()
            .fold(String::new(), |path, step| match step {
                Step::Key(key) => field_path::join(&path, key),
                Step::Index(i) => field_path::index(&path, *i),
            })
    }

    fn next(&mut self) -> Result<JsonEvent<'static>, InputError> {
        self.parser.event().map_err(|e| {
            let message = match e {
                Failure::Syntax(e) => {
                    let at = e.location().start;
                    format!(
                        "invalid JSON at line {} column {}: {}",
                        at.line + 1,
                        at.column + 1,
                        e.message()
                    )
                }
                Failure::Read(message) => message,
            };
            InputError::new(source_name(self.source), message)
        })
    }

    /// Fails when a container opened here would nest deeper than [`MAX_DEPTH`].
    fn enter(&self) -> Result<(), InputError> {
        if self.steps.len() < MAX_DEPTH {
            Ok(())
        } else {
            Err(InputError::new(
                source_name(self.source),
                format!("invalid JSON: arrays and objects nested deeper than {MAX_DEPTH}"),
            ))
        }
    }

    /// The value that starts with `event`.
    fn value(&mut self, event: JsonEvent<'static>) -> Result<Value, InputError> {
        match event {
            JsonEvent::Null => Ok(Value::Null),
            JsonEvent::Boolean(b) => Ok(Value::Bool(b)),
            JsonEvent::String(s) => Ok(Value::String(s.into_owned())),
            JsonEvent::Number(literal) => self.number(&literal),
            JsonEvent::StartArray => {
                self.enter()?;
                let mut items = Vec::new();
                loop {
                    let event = self.next()?;
                    if event == JsonEvent::EndArray {
                        return Ok(Value::Array(items));
                    }
                    self.steps.push(Step::Index(items.len()));
                    items.push(self.value(event)?);
                    self.steps.pop();
                }
            }
            JsonEvent::StartObject => {
                self.enter()?;
                let mut map = Map::new();
                loop {
                    let key = match self.next()? {
                        JsonEvent::EndObject => return Ok(Value::Object(map)),
                        JsonEvent::ObjectKey(key) => key.into_owned(),
                        other => return Err(self.unexpected(&other)),
                    };
                    let duplicate = map.contains_key(&key);
                    self.steps.push(Step::Key(key));
                    if duplicate {
                        return Err(InputError::new(
                            self.path(),
                            "duplicate key: the field is given more than once",
                        ));
                    }
                    let event = self.next()?;
                    let value = self.value(event)?;
                    if let Some(Step::Key(key)) = self.steps.pop() {
                        map.insert(key, value);
                    }
                }
            }
            other => Err(self.unexpected(&other)),
        }
    }

    /// A finite number from its (grammatical) literal.
    fn number(&self, literal: &str) -> Result<Value, InputError> {
        // Rust's float syntax contains JSON's; beyond the range it reads ±∞.
        match literal.parse::<f64>().ok().and_then(Number::from_f64) {
            Some(n) => Ok(Value::Number(n)),
            None => Err(InputError::new(
                self.path_or_input(),
                format!(
                    "non-finite number: {} is beyond the range of f64",
                    shortened(literal)
                ),
            )),
        }
    }

    /// [`Builder::path`], or `input` for the top level.
    fn path_or_input(&self) -> String {
        if self.steps.is_empty() {
            "input".into()
        } else {
            self.path()
        }
    }

    /// An event the grammar does not allow here (the parser reports those first).
    fn unexpected(&self, event: &JsonEvent<'_>) -> InputError {
        InputError::new(
            source_name(self.source),
            format!("invalid JSON: unexpected {event:?}"),
        )
    }
}

/// Parses JSON text read from `source` (for error messages): syntax errors
/// name the source, line and column; duplicate keys and out-of-range numbers
/// their field path. Plain JSON is read by the fast path; where it stops,
/// the events read the text.
pub fn parse_json(text: &str, source: &str) -> Result<Document, InputError> {
    match fast::parse(text.as_bytes()) {
        fast::Parsed::Document(document) => Ok(document),
        fast::Parsed::Replay(_) => events(text, source).map(|value| Document::from_value(&value)),
    }
}

/// The value of `text` read by the events alone.
fn events(text: &str, source: &str) -> Result<Value, InputError> {
    build(SliceJsonParser::new(text.as_bytes()), source)
}

/// [`parse_json`] of what `reader` streams in (a file read through
/// [`crate::source::Checked`]): the parse stops at the first byte that is
/// not JSON, and a failed read is an error naming `source` with the
/// reader's one-line message. Where the fast path stops, the events read
/// the same input again from its start.
pub fn parse_json_from(reader: impl Read, source: &str) -> Result<Document, InputError> {
    match fast::parse(BufReader::new(reader)) {
        fast::Parsed::Document(document) => Ok(document),
        fast::Parsed::Replay(input) => {
            build(ReaderJsonParser::new(input), source).map(|value| Document::from_value(&value))
        }
    }
}

/// The whole document of `parser`'s events.
fn build(parser: impl Events, source: &str) -> Result<Value, InputError> {
    let mut builder = Builder {
        parser,
        source,
        steps: Vec::new(),
    };
    let event = builder.next()?;
    let value = builder.value(event)?;
    match builder.next()? {
        JsonEvent::Eof => Ok(value),
        other => Err(builder.unexpected(&other)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_read_as_serde_json_reads_them() {
        let text = r#"{"a": [1.0, -2.5e3, true, null, "x\u00e9\n"], "b": {"c": {}}, "": []}"#;
        let expected: Value = serde_json::from_str(text).unwrap();
        let document = parse_json(text, "t").unwrap();
        assert_eq!(document.root().to_value(), expected);
        assert_eq!(events(text, "t").unwrap(), expected);
        // Every number is read as an `f64`.
        assert_eq!(
            parse_json("[7]", "t").unwrap().root().to_value(),
            serde_json::json!([7.0])
        );
        assert_eq!(events("[7]", "t").unwrap(), serde_json::json!([7.0]));
        let keys: Vec<&str> = document.root().as_object().unwrap().keys().collect();
        assert_eq!(keys, ["a", "b", ""], "order kept");
    }

    #[test]
    fn out_of_range_literals_are_reported_at_their_field() {
        let error = parse_json("{\"a\": [1, -1e999]}", "x").unwrap_err();
        assert_eq!(error.path, "a[1]");
        assert_eq!(
            error.message,
            "non-finite number: -1e999 is beyond the range of f64"
        );
        let error = parse_json("{\"é\": \"ü\",\r\n \"b\": [2E+999]}", "x").unwrap_err();
        assert_eq!(error.path, "b[0]");
        assert_eq!(parse_json("1e400", "x").unwrap_err().path, "input");
        // Underflow reads as zero, as everywhere.
        assert_eq!(
            parse_json("[1e-999]", "x").unwrap().root().to_value(),
            serde_json::json!([0.0])
        );
    }

    #[test]
    fn duplicate_keys_are_reported_at_their_field() {
        let error = parse_json(r#"{"a": {"b": 1, "c": 2, "b": 3}}"#, "x").unwrap_err();
        assert_eq!(error.path, "a.b");
        assert!(error.message.starts_with("duplicate key"), "{error}");
        let error = parse_json(r#"{"": 1, "": 1}"#, "x").unwrap_err();
        assert_eq!(error.path, "\"\"");
    }

    #[test]
    fn syntax_errors_name_the_source_line_and_column() {
        let error = parse_json("{\"a\": \n  ", "in.json").unwrap_err();
        assert_eq!(error.path, "in.json");
        assert!(
            error.message.starts_with("invalid JSON at line 2"),
            "{error}"
        );
        for bad in ["", "{} {}", "[1,]", "{'a': 1}", "NaN", "01", "\"\\ud800\""] {
            let error = parse_json(bad, "-").unwrap_err();
            assert_eq!(error.path, "<stdin>", "{bad}");
            assert!(error.message.starts_with("invalid JSON"), "{bad}: {error}");
        }
    }

    #[test]
    fn nesting_is_limited_to_the_maximal_depth() {
        let arrays = |depth: usize| format!("{}{}", "[".repeat(depth), "]".repeat(depth));
        let objects =
            |depth: usize| format!("{}{}", "{\"a\":".repeat(depth - 1) + "{", "}".repeat(depth));
        for nested in [arrays, objects] {
            assert!(parse_json(&nested(MAX_DEPTH), "x").is_ok());
            let error = parse_json(&nested(MAX_DEPTH + 1), "x").unwrap_err();
            assert!(error.message.contains("nested deeper than 128"), "{error}");
        }
        // Found when reached, without reading the rest.
        let error = parse_json(&"[".repeat(1_000_000), "x").unwrap_err();
        assert!(error.message.contains("nested deeper than 128"), "{error}");
    }
}
