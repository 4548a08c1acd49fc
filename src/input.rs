//! JSON → typed values. Every error names the offending field by its path
//! (`variables.pose.rotation[3]`) and says what is wrong, in one line.
//!
//! Objects are closed: a key that is not expected is an error at every level,
//! as is a missing one. Numbers must be finite; a literal beyond the `f64`
//! range (`1e999`), which `serde_json` refuses to parse, is reported at its
//! field path too (see [`parse_json`]).

use std::io::Read;

use serde_json::{Map, Value};

use crate::error::InputError;

/// The name errors use for an input source: the path, or `<stdin>` for `-`.
pub fn source_name(source: &str) -> String {
    if source == "-" {
        "<stdin>".into()
    } else {
        source.into()
    }
}

/// Reads a file, or standard input for `-`.
pub fn read_source(source: &str) -> Result<String, InputError> {
    let name = source_name(source);
    let result = if source == "-" {
        let mut text = String::new();
        std::io::stdin().read_to_string(&mut text).map(|_| text)
    } else {
        std::fs::read_to_string(source)
    };
    result.map_err(|e| InputError::new(name, format!("cannot read input: {e}")))
}

/// Marks a number literal `serde_json` could not represent (see [`parse_json`]).
const OUT_OF_RANGE: &str = "\u{1}slamjac:out-of-range:";

/// Parses JSON text. A number literal beyond the `f64` range makes
/// `serde_json` fail with "number out of range"; such a literal is replaced by
/// a marked string and parsing retried, so that the reader reports it at its
/// field path as a non-finite number instead of at a line and column.
pub fn parse_json(text: &str, source: &str) -> Result<Value, InputError> {
    let mut text = text.to_owned();
    loop {
        let error = match serde_json::from_str::<Value>(&text) {
            Ok(value) => return Ok(value),
            Err(error) => error,
        };
        let replaced = error
            .to_string()
            .starts_with("number out of range")
            .then(|| mark_number_at(&text, error.line(), error.column()))
            .flatten();
        match replaced {
            Some(marked) => text = marked,
            None => {
                return Err(InputError::new(
                    source_name(source),
                    format!("invalid JSON: {error}"),
                ));
            }
        }
    }
}

/// `text` with the number literal at (or just before) `line`:`column`
/// (`serde_json`'s 1-based line, 0-based byte column) replaced by a marked string.
fn mark_number_at(text: &str, line: usize, column: usize) -> Option<String> {
    let line_start: usize = text
        .split_inclusive('\n')
        .take(line.checked_sub(1)?)
        .map(str::len)
        .sum();
    let bytes = text.as_bytes();
    let number_byte = |b: u8| b.is_ascii_digit() || matches!(b, b'-' | b'+' | b'.' | b'e' | b'E');
    let mut start = (line_start + column).min(bytes.len());
    let mut end = start;
    while end < bytes.len() && number_byte(bytes[end]) {
        end += 1;
    }
    while start > 0 && number_byte(bytes[start - 1]) {
        start -= 1;
    }
    let literal = text.get(start..end)?;
    if !literal.bytes().any(|b| b.is_ascii_digit()) {
        return None;
    }
    let marker = serde_json::to_string(&format!("{OUT_OF_RANGE}{literal}")).ok()?;
    Some(format!(
        "{}{marker}{}",
        text.get(..start)?,
        text.get(end..)?
    ))
}

/// `parent.key`, or `key` at the top level.
fn join(parent: &str, key: &str) -> String {
    if parent.is_empty() {
        key.into()
    } else {
        format!("{parent}.{key}")
    }
}

/// What kind of JSON value this is, for "expected X, found Y".
fn kind(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(s) if s.starts_with(OUT_OF_RANGE) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// A finite number at `path`.
pub fn number(value: &Value, path: &str) -> Result<f64, InputError> {
    match value {
        Value::Number(n) => match n.as_f64() {
            Some(x) if x.is_finite() => Ok(x),
            _ => Err(InputError::new(path, format!("non-finite number {n}"))),
        },
        Value::String(s) if s.starts_with(OUT_OF_RANGE) => {
            let literal = &s[OUT_OF_RANGE.len()..];
            let shown = match literal.char_indices().nth(24) {
                Some((end, _)) => format!("{}…", &literal[..end]),
                None => literal.to_owned(),
            };
            Err(InputError::new(
                path,
                format!("non-finite number: {shown} is beyond the range of f64"),
            ))
        }
        other => Err(InputError::new(
            path,
            format!("expected a number, found {}", kind(other)),
        )),
    }
}

/// An array of exactly `n` finite numbers at `path`.
pub fn numbers(value: &Value, path: &str, n: usize) -> Result<Vec<f64>, InputError> {
    let items = value.as_array().ok_or_else(|| {
        InputError::new(
            path,
            format!("expected an array of {n} numbers, found {}", kind(value)),
        )
    })?;
    if items.len() != n {
        return Err(InputError::new(
            path,
            format!("wrong length: expected {n} numbers, found {}", items.len()),
        ));
    }
    items
        .iter()
        .enumerate()
        .map(|(i, item)| number(item, &format!("{path}[{i}]")))
        .collect()
}

/// A JSON object whose keys have been checked: none unknown, none missing.
#[derive(Debug, Clone)]
pub struct Object<'a> {
    path: String,
    map: &'a Map<String, Value>,
}

impl<'a> Object<'a> {
    /// Checks that `value` (at `path`, `""` for the top level) is an object
    /// with exactly the fields `keys`.
    pub fn new(value: &'a Value, path: &str, keys: &[&str]) -> Result<Self, InputError> {
        let expected = keys.join(", ");
        let map = value.as_object().ok_or_else(|| {
            let at = if path.is_empty() { "input" } else { path };
            InputError::new(
                at,
                format!(
                    "expected an object with fields {expected}, found {}",
                    kind(value)
                ),
            )
        })?;
        if let Some(unknown) = map.keys().find(|k| !keys.contains(&k.as_str())) {
            return Err(InputError::new(
                join(path, unknown),
                format!("unknown field; expected only {expected}"),
            ));
        }
        if let Some(missing) = keys.iter().find(|k| !map.contains_key(**k)) {
            return Err(InputError::new(join(path, missing), "missing field"));
        }
        Ok(Object {
            path: path.into(),
            map,
        })
    }

    /// The path of field `key`.
    pub fn path_of(&self, key: &str) -> String {
        join(&self.path, key)
    }

    /// The value of field `key` (checked present by [`Object::new`]).
    pub fn get(&self, key: &str) -> &'a Value {
        &self.map[key]
    }

    /// A string field.
    pub fn string(&self, key: &str) -> Result<&'a str, InputError> {
        let value = self.get(key);
        value
            .as_str()
            .filter(|s| !s.starts_with(OUT_OF_RANGE))
            .ok_or_else(|| {
                InputError::new(
                    self.path_of(key),
                    format!("expected a string, found {}", kind(value)),
                )
            })
    }

    /// A sub-object with exactly the fields `keys`.
    pub fn object(&self, key: &str, keys: &[&str]) -> Result<Object<'a>, InputError> {
        Object::new(self.get(key), &self.path_of(key), keys)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn out_of_range_literals_are_reported_at_their_field() {
        let value = parse_json("{\"a\": [1, -1e999]}", "x").unwrap();
        let a = Object::new(&value, "", &["a"]).unwrap();
        let error = numbers(a.get("a"), &a.path_of("a"), 2).unwrap_err();
        assert_eq!(error.path, "a[1]");
        assert!(error.message.contains("-1e999"), "{error}");
    }

    #[test]
    fn several_out_of_range_literals_after_non_ascii_text_are_all_marked() {
        let value = parse_json("{\"é\": \"ü\",\r\n \"b\": [1e999, 2E+999, 3]}", "x").unwrap();
        let b = Object::new(&value, "", &["é", "b"]).unwrap();
        assert_eq!(numbers(b.get("b"), "b", 3).unwrap_err().path, "b[0]");
        assert_eq!(number(&value["b"][1], "b[1]").unwrap_err().path, "b[1]");
        assert_eq!(number(&value["b"][2], "b[2]"), Ok(3.0));
    }

    #[test]
    fn invalid_json_names_the_source() {
        let error = parse_json("{\"a\": ", "in.json").unwrap_err();
        assert_eq!(error.path, "in.json");
        assert!(error.message.starts_with("invalid JSON"));
    }
}
