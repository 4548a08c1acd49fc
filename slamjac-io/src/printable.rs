//! Text from the input made one printable line: every character that would
//! break a line, steer a terminal or hide itself is escaped as in JSON
//! (`\n`, `\r`, `\t`, `\uXXXX`, characters beyond U+FFFF as their surrogate
//! pair `\ud83d\ude00`).
//!
//! The characters escaped ([`is_unprintable`]): the control characters (C0,
//! DEL, C1), the line and paragraph separators U+2028 and U+2029, and the
//! format characters (Unicode category Cf) — among them the byte-order mark
//! U+FEFF, the zero-width space, joiners and word joiner U+200B–U+200D and
//! U+2060, the soft hyphen U+00AD, the bidirectional controls and the tag
//! characters — which print nothing or reorder what follows.

use std::borrow::Cow;

/// The format characters (Unicode 16 category Cf), as inclusive ranges.
const FORMAT: [(char, char); 21] = [
    ('\u{00ad}', '\u{00ad}'),
    ('\u{0600}', '\u{0605}'),
    ('\u{061c}', '\u{061c}'),
    ('\u{06dd}', '\u{06dd}'),
    ('\u{070f}', '\u{070f}'),
    ('\u{0890}', '\u{0891}'),
    ('\u{08e2}', '\u{08e2}'),
    ('\u{180e}', '\u{180e}'),
    ('\u{200b}', '\u{200f}'),
    ('\u{202a}', '\u{202e}'),
    ('\u{2060}', '\u{2064}'),
    ('\u{2066}', '\u{206f}'),
    ('\u{feff}', '\u{feff}'),
    ('\u{fff9}', '\u{fffb}'),
    ('\u{110bd}', '\u{110bd}'),
    ('\u{110cd}', '\u{110cd}'),
    ('\u{13430}', '\u{1343f}'),
    ('\u{1bca0}', '\u{1bca3}'),
    ('\u{1d173}', '\u{1d17a}'),
    ('\u{e0001}', '\u{e0001}'),
    ('\u{e0020}', '\u{e007f}'),
];

/// Whether `c` would break a one-line message, steer a terminal or print
/// nothing: a control character, a line or paragraph separator, or a
/// format character (see the module documentation).
pub fn is_unprintable(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{2028}' | '\u{2029}')
        || FORMAT.iter().any(|(low, high)| (*low..=*high).contains(&c))
}

/// Pushes `c` escaped when [`is_unprintable`], else as it is.
pub fn push(out: &mut String, c: char) {
    match c {
        '\n' => out.push_str("\\n"),
        '\r' => out.push_str("\\r"),
        '\t' => out.push_str("\\t"),
        c if is_unprintable(c) => {
            let mut units = [0u16; 2];
            for unit in c.encode_utf16(&mut units) {
                out.push_str(&format!("\\u{unit:04x}"));
            }
        }
        c => out.push(c),
    }
}

/// `text` with its unprintable characters escaped, and nothing else.
pub fn escape(text: &str) -> Cow<'_, str> {
    if !text.chars().any(is_unprintable) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        push(&mut out, c);
    }
    Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invisible_and_steering_characters_are_escaped() {
        let cases = [
            ("a\nb\r\tc", "a\\nb\\r\\tc"),
            ("\u{1b}[31m", "\\u001b[31m"),
            ("\u{7f}\u{85}", "\\u007f\\u0085"),
            ("\u{2028}\u{2029}", "\\u2028\\u2029"),
            ("\u{feff}bom", "\\ufeffbom"),
            ("zero\u{200b}width\u{200d}", "zero\\u200bwidth\\u200d"),
            ("soft\u{ad}hyphen\u{2060}", "soft\\u00adhyphen\\u2060"),
            ("\u{202e}evil\u{2066}", "\\u202eevil\\u2066"),
            ("tag\u{e0041}", "tag\\udb40\\udc41"),
            ("plain \"é\" ü 😀 \\", "plain \"é\" ü 😀 \\"),
        ];
        for (text, shown) in cases {
            assert_eq!(escape(text), shown, "{text:?}");
        }
    }
}
