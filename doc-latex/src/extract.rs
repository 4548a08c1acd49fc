//! Finding the math of a Markdown/LaTeX document: `$$…$$` displays (which
//! may span lines) and `$…$` inline formulas, with their equation labels.
//!
//! Code blocks (``` or ~~~ fences) and code spans are skipped, `\$` is a
//! dollar sign. An inline formula must close before a blank line; an
//! unclosed `$` is text, an unclosed `$$` an error.
//!
//! A display's label is a `\tag{…}` inside it, a trailing `(N)` after a
//! spacing command (`\quad (1.1)`), a line `(N)` right after it, or a display
//! holding only `(N)` (as `$$(10)$$`), which labels the display before it
//! when that one has none. `N` is digits with dots: `5`, `4.27`.

use std::ops::Range;

use crate::error::{ErrorKind, Lines, ParseError};

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
}

/// Every formula of `text`, in order.
pub(crate) fn extract(text: &str) -> Result<Vec<Found>, ParseError> {
    let b = text.as_bytes();
    let mut out: Vec<Found> = Vec::new();
    let mut last_display_end: Option<usize> = None;
    let mut i = 0;
    let mut line_start = true;
    let mut in_fence = false;
    while i < b.len() {
        if line_start {
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
            b'\\' => i += if b.get(i + 1) == Some(&b'$') { 2 } else { 1 },
            b'`' => i = skip_code_span(text, i),
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
                    span,
                    label,
                    label_span,
                    follows_display,
                });
            }
            b'$' => match inline_close(text, i + 1) {
                Some(close) => {
                    out.push(Found {
                        kind: MathKind::Inline,
                        span: i + 1..close,
                        label: None,
                        label_span: None,
                        follows_display: false,
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

/// The closing `$` of an inline formula whose content starts at `from`:
/// unescaped, before a blank line, after a non-empty content.
fn inline_close(text: &str, from: usize) -> Option<usize> {
    let b = text.as_bytes();
    let mut k = from;
    while k < b.len() {
        match b[k] {
            b'\\' => k += 2,
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
        extract(text)
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
        let e = extract("text $$ a = b").unwrap_err();
        assert_eq!(e.kind, ErrorKind::UnterminatedDisplay);
        assert_eq!(e.offset, 5);
    }

    #[test]
    fn runs_of_displays() {
        let found = extract("$$a = b$$\n\n$$= c$$\ntext\n$$d$$").unwrap();
        let follows: Vec<bool> = found.iter().map(|f| f.follows_display).collect();
        assert_eq!(follows, vec![false, true, false]);
    }
}
