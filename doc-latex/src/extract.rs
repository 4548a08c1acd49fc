//! Finding the math of a Markdown/LaTeX document: `$$…$$` displays (which
//! may span lines) and `$…$` inline formulas, with their equation labels;
//! LaTeX's `\[…\]`, `\(…\)` and display environments (`equation`,
//! `align`, `gather`, `multline`, `eqnarray`, `flalign`, `alignat`, starred
//! or not, `displaymath`); Doxygen's `\f$…\f$`, `\f[…\f]` and
//! `\f{align}{…\f}`. A formula delimited by an alignment environment is read
//! as one (its rows are its lines).
//!
//! In Markdown, code blocks (``` or ~~~ fences) and code spans are skipped;
//! in LaTeX ([`Syntax::Latex`]) `%` starts a comment. `\$` is a dollar sign.
//! An inline formula must close before a blank line, and a `$` inside
//! braces (`\text{if $x$}`) does not close it; an unclosed `$` is text, an
//! unclosed display an error.
//!
//! A display's label is a `\tag{…}` inside it, a trailing `(N)` after a
//! spacing command (`\quad (1.1)`), a line `(N)` right after it, or a display
//! holding only `(N)` (as `$$(10)$$`), which labels the display before it
//! when that one has none. `N` is digits with dots: `5`, `4.27`.

use std::ops::Range;

use crate::error::{ErrorKind, Lines, ParseError};

/// How a document is written: Markdown with math (`%` is text), or LaTeX
/// (`%` starts a comment, backticks are text).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Syntax {
    /// Markdown with `$…$` and `$$…$$` math (the default).
    #[default]
    Markdown,
    /// A LaTeX source (`.tex`).
    Latex,
}

/// LaTeX environments that make a display, and whether each is an
/// alignment (its rows are lines).
const DISPLAY_ENVIRONMENTS: &[(&str, bool)] = &[
    ("equation", false),
    ("equation*", false),
    ("displaymath", false),
    ("align", true),
    ("align*", true),
    ("gather", true),
    ("gather*", true),
    ("multline", true),
    ("multline*", true),
    ("eqnarray", true),
    ("eqnarray*", true),
    ("subeqnarray", true),
    ("flalign", true),
    ("flalign*", true),
    ("alignat", true),
    ("alignat*", true),
];

/// Display or inline math.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MathKind {
    /// `$$…$$`.
    Display,
    /// `$…$`.
    Inline,
}

/// A formula as found, before parsing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Found {
    pub kind: MathKind,
    /// The bytes between the delimiters.
    pub span: Range<usize>,
    /// The label, without parentheses.
    pub label: Option<String>,
    /// The label's bytes inside `span` (relative to it), to blank before
    /// parsing.
    pub label_span: Option<Range<usize>>,
    /// Only whitespace (and label lines) since the previous display.
    pub follows_display: bool,
    /// Its `\label{…}` names.
    pub names: Vec<String>,
    /// The alignment environment its delimiters open (`\begin{align}`),
    /// whose rows are its lines.
    pub environment: Option<String>,
}

/// A formula delimited by LaTeX or Doxygen syntax at a `\`.
struct Delimited {
    kind: MathKind,
    span: Range<usize>,
    /// The byte after the closing delimiter.
    end: usize,
    environment: Option<String>,
}

/// Every formula of `text`, in order.
pub(crate) fn extract(text: &str, syntax: Syntax) -> Result<Vec<Found>, ParseError> {
    let b = text.as_bytes();
    let mut out: Vec<Found> = Vec::new();
    let mut last_display_end: Option<usize> = None;
    let mut i = 0;
    let mut line_start = true;
    let mut in_fence = false;
    let markdown = syntax == Syntax::Markdown;
    while i < b.len() {
        if line_start && markdown {
            line_start = false;
            let line = &text[i..line_end(text, i)];
            let trimmed = line.trim_start();
            if trimmed.starts_with("```") || trimmed.starts_with("~~~") {
                in_fence = !in_fence;
                i = next_line(text, i);
                line_start = true;
                continue;
            }
            if in_fence {
                i = next_line(text, i);
                line_start = true;
                continue;
            }
        }
        match b[i] {
            b'\n' => {
                i += 1;
                line_start = true;
            }
            b'%' if !markdown => i = line_end(text, i),
            b'\\' => match delimited(text, i, syntax)? {
                Some(d) => {
                    let names = label_names(&text[d.span.clone()]);
                    let display = d.kind == MathKind::Display;
                    let follows_display =
                        display && last_display_end.is_some_and(|e| text[e..i].trim().is_empty());
                    let (label, label_span) = if display {
                        label_inside(&text[d.span.clone()])
                    } else {
                        (None, None)
                    };
                    let mut end = d.end;
                    let mut label = label;
                    if display {
                        if let Some((after_label, line_label)) = label_after(text, end) {
                            end = after_label;
                            label = label.or(Some(line_label));
                        }
                        last_display_end = Some(end);
                    }
                    out.push(Found {
                        kind: d.kind,
                        span: d.span,
                        label,
                        label_span,
                        follows_display,
                        names,
                        environment: d.environment,
                    });
                    line_start = text[..end].ends_with('\n');
                    i = end;
                }
                None => {
                    i += if b.get(i + 1).is_some_and(|c| *c == b'$' || *c == b'%') {
                        2
                    } else {
                        1
                    }
                }
            },
            b'`' if markdown => i = skip_code_span(text, i),
            b'$' if b.get(i + 1) == Some(&b'$') => {
                let open = i;
                let Some(close) = text[i + 2..].find("$$").map(|k| i + 2 + k) else {
                    return Err(ParseError::at(
                        text,
                        &Lines::new(text),
                        open,
                        None,
                        ErrorKind::UnterminatedDisplay,
                    ));
                };
                let span = open + 2..close;
                let (mut label, label_span) = label_inside(&text[span.clone()]);
                let mut end = close + 2;
                if let Some((after_label, line_label)) = label_after(text, end) {
                    end = after_label;
                    label = label.or(Some(line_label));
                }
                let follows_display =
                    last_display_end.is_some_and(|e| text[e..open].trim().is_empty());
                last_display_end = Some(end);
                i = end;
                line_start = text[..end].ends_with('\n');
                let blank = {
                    let content = &text[span.clone()];
                    let kept = match &label_span {
                        Some(r) => format!("{}{}", &content[..r.start], &content[r.end..]),
                        None => content.to_string(),
                    };
                    kept.trim().is_empty()
                };
                // `$$(10)$$` labels the display before it.
                if blank
                    && follows_display
                    && let Some(prev) = out.last_mut().filter(|p| p.label.is_none())
                {
                    prev.label = label;
                    continue;
                }
                out.push(Found {
                    kind: MathKind::Display,
                    names: label_names(&text[span.clone()]),
                    span,
                    label,
                    label_span,
                    follows_display,
                    environment: None,
                });
            }
            b'$' => match inline_close(text, i + 1) {
                Some(close) => {
                    out.push(Found {
                        kind: MathKind::Inline,
                        names: label_names(&text[i + 1..close]),
                        span: i + 1..close,
                        label: None,
                        label_span: None,
                        follows_display: false,
                        environment: None,
                    });
                    i = close + 1;
                }
                None => i += 1,
            },
            _ => i += 1,
        }
    }
    Ok(out)
}

fn line_end(text: &str, i: usize) -> usize {
    text[i..].find('\n').map_or(text.len(), |k| i + k)
}

fn next_line(text: &str, i: usize) -> usize {
    (line_end(text, i) + 1).min(text.len())
}

/// Past a code span opened by the backticks at `i` (or past the backticks
/// when it is never closed).
fn skip_code_span(text: &str, i: usize) -> usize {
    let run = text[i..].bytes().take_while(|c| *c == b'`').count();
    let fence = &text[i..i + run];
    let mut k = i + run;
    while let Some(found) = text[k..].find(fence) {
        let at = k + found;
        let len = text[at..].bytes().take_while(|c| *c == b'`').count();
        if len == run {
            return at + run;
        }
        k = at + len;
    }
    i + run
}

/// The formula whose LaTeX or Doxygen delimiter starts at the `\` at
/// byte `at`, if one does.
fn delimited(text: &str, at: usize, syntax: Syntax) -> Result<Option<Delimited>, ParseError> {
    let rest = &text[at..];
    let unterminated = || {
        ParseError::at(
            text,
            &Lines::new(text),
            at,
            None,
            ErrorKind::UnterminatedDisplay,
        )
    };
    let pair = |open: &str, close: &str, kind: MathKind| -> Result<Option<Delimited>, ParseError> {
        let from = at + open.len();
        let close_at = find_outside_comments(text, from, close, syntax).ok_or_else(unterminated)?;
        Ok(Some(Delimited {
            kind,
            span: from..close_at,
            end: close_at + close.len(),
            environment: None,
        }))
    };
    if rest.starts_with("\\[") {
        return pair("\\[", "\\]", MathKind::Display);
    }
    if rest.starts_with("\\(") {
        return pair("\\(", "\\)", MathKind::Inline);
    }
    if rest.starts_with("\\f$") {
        return pair("\\f$", "\\f$", MathKind::Inline);
    }
    if rest.starts_with("\\f[") {
        return pair("\\f[", "\\f]", MathKind::Display);
    }
    // `\f{align*}{ … \f}`, or `\f{align*} … \f}` with the brace left out.
    if let Some(env_rest) = rest.strip_prefix("\\f{")
        && let Some(close) = env_rest.find('}')
        && env_rest[..close]
            .trim()
            .chars()
            .all(|c| c.is_ascii_alphabetic() || c == '*')
    {
        let name = env_rest[..close].trim().to_string();
        let brace = usize::from(env_rest[close + 1..].starts_with('{'));
        let mut d = match pair(&rest[..3 + close + 1 + brace], "\\f}", MathKind::Display)? {
            Some(d) => d,
            None => return Ok(None),
        };
        d.environment = alignment(&name).then_some(name);
        return Ok(Some(d));
    }
    if let Some(env_rest) = rest.strip_prefix("\\begin{")
        && let Some(close) = env_rest.find('}')
        && let Some(&(name, aligned)) = DISPLAY_ENVIRONMENTS
            .iter()
            .find(|(n, _)| *n == &env_rest[..close])
    {
        let mut from = at + 8 + close;
        if name.starts_with("alignat") {
            // `\begin{alignat}{2}`: the column count.
            let after = &text[from..];
            let trimmed = after.trim_start();
            if let Some(arg) = trimmed.strip_prefix('{')
                && let Some(c) = arg.find('}')
            {
                from += after.len() - trimmed.len() + c + 2;
            }
        }
        let end_tag = format!("\\end{{{name}}}");
        let close_at =
            find_outside_comments(text, from, &end_tag, syntax).ok_or_else(unterminated)?;
        return Ok(Some(Delimited {
            kind: MathKind::Display,
            span: from..close_at,
            end: close_at + end_tag.len(),
            environment: aligned.then(|| name.to_string()),
        }));
    }
    Ok(None)
}

/// Whether an environment named by a Doxygen delimiter is an alignment.
fn alignment(name: &str) -> bool {
    DISPLAY_ENVIRONMENTS
        .iter()
        .any(|(n, aligned)| *n == name && *aligned)
}

/// The first `needle` at or after `from`, outside LaTeX comments.
fn find_outside_comments(text: &str, from: usize, needle: &str, syntax: Syntax) -> Option<usize> {
    if syntax == Syntax::Markdown {
        return text[from..].find(needle).map(|k| from + k);
    }
    let b = text.as_bytes();
    let mut k = from;
    while k < b.len() {
        // Bytes, not `str` slices: `k` may sit inside a character after
        // a backslash (`\∂`).
        if b[k..].starts_with(needle.as_bytes()) {
            return Some(k);
        }
        match b[k] {
            b'\\' => k += 2,
            b'%' => k = line_end(text, k),
            _ => k += 1,
        }
    }
    None
}

/// The names of the `\label{…}`s in a formula's LaTeX.
fn label_names(content: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = content;
    while let Some(at) = rest.find("\\label") {
        let after = rest[at + 6..].trim_start();
        match after
            .strip_prefix('{')
            .and_then(|a| a.find('}').map(|c| &a[..c]))
        {
            Some(name) if !name.trim().is_empty() => out.push(name.trim().to_string()),
            _ => {}
        }
        rest = &rest[at + 6..];
    }
    out
}

/// The closing `$` of an inline formula whose content starts at `from`:
/// unescaped, outside braces (`\text{if $x$}` holds text math), before a
/// blank line, after a non-empty content.
fn inline_close(text: &str, from: usize) -> Option<usize> {
    let b = text.as_bytes();
    let mut k = from;
    let mut braces = 0usize;
    while k < b.len() {
        match b[k] {
            b'\\' => k += 2,
            b'{' => {
                braces += 1;
                k += 1;
            }
            b'}' => {
                braces = braces.saturating_sub(1);
                k += 1;
            }
            b'$' if braces > 0 => k += 1,
            b'$' => {
                return (!text[from..k].trim().is_empty()).then_some(k);
            }
            b'\n' => {
                let next = &text[k + 1..line_end(text, k + 1)];
                if next.trim().is_empty() {
                    return None;
                }
                k += 1;
            }
            _ => k += 1,
        }
    }
    None
}

/// `(N)` with `N` digits and dots: `N`.
fn label_text(s: &str) -> Option<String> {
    let inner = s.trim().strip_prefix('(')?.strip_suffix(')')?.trim();
    let ok = !inner.is_empty()
        && inner
            .split('.')
            .all(|p| !p.is_empty() && p.bytes().all(|c| c.is_ascii_digit()));
    ok.then(|| inner.to_string())
}

/// A label inside a display's content: `\tag{N}`, or a trailing `(N)` after
/// a spacing command or alone. The span is that of the trailing `(N)`
/// (`\tag` is dropped by the lexer).
fn label_inside(content: &str) -> (Option<String>, Option<Range<usize>>) {
    if let Some(at) = content.find("\\tag") {
        let rest = content[at + 4..].trim_start_matches('*').trim_start();
        if let Some(body) = rest.strip_prefix('{')
            && let Some(close) = body.find('}')
        {
            return (Some(body[..close].trim().to_string()), None);
        }
    }
    let t = content.trim_end();
    if t.ends_with(')')
        && let Some(open) = t.rfind('(')
        && let Some(label) = label_text(&t[open..])
    {
        let before = t[..open].trim_end();
        let spaced = before.is_empty()
            || ["\\quad", "\\qquad", "~", "\\,", "\\;", "\\"]
                .iter()
                .any(|s| before.ends_with(s));
        if spaced {
            return (Some(label), Some(open..t.len()));
        }
    }
    (None, None)
}

/// A label `(N)` on the rest of the closing line at `end`, or alone on the
/// next line: the byte after it and the label.
fn label_after(text: &str, end: usize) -> Option<(usize, String)> {
    let eol = line_end(text, end);
    let rest = &text[end..eol];
    if let Some(label) = label_text(rest) {
        return Some((eol, label));
    }
    if !rest.trim().is_empty() || eol >= text.len() {
        return None;
    }
    let next_eol = line_end(text, eol + 1);
    label_text(&text[eol + 1..next_eol]).map(|l| (next_eol, l))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(text: &str) -> Vec<(MathKind, String, Option<String>)> {
        extract(text, Syntax::Markdown)
            .unwrap()
            .into_iter()
            .map(|f| (f.kind, text[f.span].to_string(), f.label))
            .collect()
    }

    #[test]
    fn labels_in_every_printed_form() {
        let text =
            "$$a = b \\quad (1.1)$$\n\n$$c = d \\tag{3}$$\n$$e\n= f$$\n(5)\n\n$$g$$\n\n$$(10)$$\n";
        let found = labels(text);
        assert_eq!(found.len(), 4);
        assert_eq!(found[0].2.as_deref(), Some("1.1"));
        assert_eq!(found[1].2.as_deref(), Some("3"));
        assert_eq!(found[2].1, "e\n= f");
        assert_eq!(found[2].2.as_deref(), Some("5"));
        assert_eq!(found[3].2.as_deref(), Some("10"));
    }

    #[test]
    fn a_parenthesis_after_math_is_not_a_label() {
        assert_eq!(labels("$$x \\in SO(3)$$")[0].2, None);
    }

    #[test]
    fn inline_math_code_and_escapes() {
        let found = labels("costs \\$5, `$x$` but $y$ and\n```\n$z$\n```\n$w$ and $ alone\n\nend");
        let texts: Vec<&str> = found.iter().map(|f| f.1.as_str()).collect();
        assert_eq!(texts, vec!["y", "w"]);
    }

    #[test]
    fn an_unclosed_display_is_an_error() {
        let e = extract("text $$ a = b", Syntax::Markdown).unwrap_err();
        assert_eq!(e.kind, ErrorKind::UnterminatedDisplay);
        assert_eq!(e.offset, 5);
    }

    #[test]
    fn runs_of_displays() {
        let found = extract("$$a = b$$\n\n$$= c$$\ntext\n$$d$$", Syntax::Markdown).unwrap();
        let follows: Vec<bool> = found.iter().map(|f| f.follows_display).collect();
        assert_eq!(follows, vec![false, true, false]);
    }
}
