//! How error messages show field paths and text taken from the input, so that
//! an error stays one printable line whatever the input holds.
//!
//! - A key that is a plain identifier (an ASCII letter or `_`, then ASCII
//!   letters, digits or `_`) joins its parent with a dot, `variables.pose`;
//!   any other key is quoted, in brackets below the top level,
//!   `variables["a b"]`, alone at it, `"a b"`. An empty key shows as `""`:
//!   no path is empty.
//! - An array index is bracketed: `rotation[3]`, `input[0]` at the top level.
//! - Quoted text is escaped as in JSON: `\"`, `\\`, `\n`, `\r`, `\t`, and
//!   `\uXXXX` for every other unprintable character (see [`is_unprintable`]),
//!   e.g. `\u001b`, `\u0085`, `\u2028`.
//! - Input text longer than [`MAX_SHOWN_CHARS`] characters (a key, a string
//!   value, a number literal) is cut there, the cut marked with `…`.

use std::borrow::Cow;

pub use slamjac_io::printable::{escape as escape_unprintable, is_unprintable};

/// How many characters of a key, string or literal from the input an error shows.
pub const MAX_SHOWN_CHARS: usize = 64;

/// Pushes `c` JSON-escaped: unprintable characters always
/// ([`is_unprintable`]: controls, separators, format characters such as a
/// byte-order mark or a zero-width space), `"` and `\` when `quoting`
/// (inside a quoted string).
fn push_escaped(out: &mut String, c: char, quoting: bool) {
    if quoting && matches!(c, '"' | '\\') {
        out.push('\\');
        out.push(c);
    } else {
        slamjac_io::printable::push(out, c);
    }
}

/// A path as the output shows it: its unprintable characters escaped (a
/// file name is input too).
pub fn shown_path(path: &std::path::Path) -> String {
    escape_unprintable(&path.display().to_string()).into_owned()
}

/// `text` cut after [`MAX_SHOWN_CHARS`] characters, the cut marked with `…`.
pub fn shortened(text: &str) -> Cow<'_, str> {
    match text.char_indices().nth(MAX_SHOWN_CHARS) {
        Some((end, _)) => Cow::Owned(format!("{}…", &text[..end])),
        None => Cow::Borrowed(text),
    }
}

/// `text` from the input, [`shortened`], escaped and in double quotes: `"a\nb"`.
pub fn quoted(text: &str) -> String {
    let mut out = String::from("\"");
    for c in shortened(text).chars() {
        push_escaped(&mut out, c, true);
    }
    out.push('"');
    out
}

/// Whether `key` joins a path with a dot rather than in quotes.
fn is_identifier(key: &str) -> bool {
    let mut chars = key.chars();
    key.len() <= MAX_SHOWN_CHARS
        && chars
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// The path of field `key` of the object at `parent` (`""` for the top level).
pub fn join(parent: &str, key: &str) -> String {
    match (parent.is_empty(), is_identifier(key)) {
        (true, true) => key.to_owned(),
        (false, true) => [parent, ".", key].concat(),
        (true, false) => quoted(key),
        (false, false) => format!("{parent}[{}]", quoted(key)),
    }
}

/// The path of item `index` of the array at `parent` (`""` for the top level).
pub fn index(parent: &str, index: usize) -> String {
    let parent = if parent.is_empty() { "input" } else { parent };
    format!("{parent}[{index}]")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_join_with_dots_and_other_keys_are_quoted() {
        assert_eq!(join("", "factor"), "factor");
        assert_eq!(join("variables", "pose_2"), "variables.pose_2");
        assert_eq!(join("", ""), "\"\"");
        assert_eq!(join("variables", ""), "variables[\"\"]");
        assert_eq!(join("variables", "a b"), "variables[\"a b\"]");
        assert_eq!(join("v", "2d"), "v[\"2d\"]");
        assert_eq!(join("v", "é"), "v[\"é\"]");
        assert_eq!(index("", 0), "input[0]");
        assert_eq!(index("variables.point", 2), "variables.point[2]");
    }

    #[test]
    fn quoted_text_is_json_escaped() {
        let cases = [
            ("a\nb", r#""a\nb""#),
            ("a\r\tb", r#""a\r\tb""#),
            ("\u{1b}[31m", r#""\u001b[31m""#),
            ("\u{0}", r#""\u0000""#),
            ("\u{7f}\u{85}", r#""\u007f\u0085""#),
            ("\u{2028}\u{2029}", r#""\u2028\u2029""#),
            ("\u{202e}evil", r#""\u202eevil""#),
            ("\u{feff}x\u{200b}", r#""\ufeffx\u200b""#),
            ("say \"hi\" \\", r#""say \"hi\" \\""#),
            ("ü", "\"ü\""),
        ];
        for (text, shown) in cases {
            assert_eq!(quoted(text), shown, "{text:?}");
        }
    }

    #[test]
    fn long_text_is_cut_after_the_cap_in_characters() {
        let text = "é".repeat(MAX_SHOWN_CHARS + 1);
        assert_eq!(
            quoted(&text),
            format!("\"{}…\"", "é".repeat(MAX_SHOWN_CHARS))
        );
        let exact = "x".repeat(MAX_SHOWN_CHARS);
        assert_eq!(shortened(&exact), exact.as_str());
        // A long identifier is quoted, so the cut stays inside quotes.
        let key = "k".repeat(MAX_SHOWN_CHARS + 1);
        assert_eq!(
            join("", &key),
            format!("\"{}…\"", "k".repeat(MAX_SHOWN_CHARS))
        );
    }

    #[test]
    fn only_unprintable_characters_are_escaped_in_lines() {
        assert_eq!(escape_unprintable("plain \"text\" \\"), "plain \"text\" \\");
        assert_eq!(
            escape_unprintable("a\nb\u{1b}c\u{2028}"),
            "a\\nb\\u001bc\\u2028"
        );
    }
}
