//! A formula's lines and statements, found on its tokens before parsing, so
//! a garbled line or side note does not hide the others.
//!
//! A display that is one `aligned`/`split`/`align`/… environment has a line
//! per row (`&` marks alignment and is dropped); one that is a `cases`
//! environment has a line per case (the condition after `&` a side note);
//! otherwise top-level `\\` separate lines. Within a line, top-level `,` and
//! `\quad`/`\qquad` separate statements: the first is the line's claim, the
//! others side notes (`\quad θ = |ω|`), except that a piece starting with a
//! relation continues the chain (`= R \qquad \in SO(3)`); so do words of
//! text between two statements (`a = b \mbox{ and } c = d`). Trailing `.`
//! and `,` are punctuation. A formula whose delimiters are themselves an
//! alignment environment (`\begin{align}…\end{align}` in LaTeX) is read as
//! one.

use std::ops::Range;

use crate::lexer::{Delim, LexError, Tok, Token};
use crate::macros::{Vocabulary, tokens};
use crate::names::{ALIGNMENT_ENVIRONMENTS, CASES_ENVIRONMENTS, RELATION_COMMANDS, lookup};

/// One line of a formula, split into statements.
#[derive(Debug, Clone)]
pub(crate) struct Line {
    /// The line's bytes in the formula's math.
    pub span: Range<usize>,
    /// The statements' tokens: the claim first, then side notes.
    pub statements: Vec<Vec<Token>>,
    /// The line starts with a relation: it continues an earlier line.
    pub continued: bool,
    /// The line does not continue one but holds a top-level relation: it
    /// starts a chain.
    pub heads_chain: bool,
    /// The environment around the whole display, when the display never
    /// closes it (read as closed at the display's end).
    pub unclosed: Option<String>,
}

/// How a formula's rows are written.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Layout {
    /// No environment around the whole formula.
    Plain,
    /// An alignment environment: `&` marks alignment.
    Aligned,
    /// A `cases` environment: `&` introduces a side condition.
    Cases,
}

/// The lines of a formula's math (at byte `at` of its document, read with
/// `vocab`; `environment` the alignment its delimiters open). Only a lexing
/// error stops the split: unbalanced braces or environments are left to
/// each line's parse, so one garbled line does not hide the others.
pub(crate) fn lines(
    math: &str,
    vocab: &Vocabulary,
    at: usize,
    environment: Option<&str>,
) -> Result<Vec<Line>, LexError> {
    let toks = tokens(math, vocab, at)?;
    let env = environment_depths(&toks);
    let (layout, body, unclosed) = match environment {
        Some(_) => (Layout::Aligned, 0..toks.len(), None),
        None => layout(&toks, &env),
    };
    let base = body.clone().next().map_or(0, |i| env[i]);
    // `multline` holds one equation broken over rows.
    let one_equation = environment
        .map(str::to_string)
        .or_else(|| {
            match toks
                .iter()
                .find(|t| !matches!(t.tok, Tok::Quad | Tok::Space))
            {
                Some(Token {
                    tok: Tok::Begin(name),
                    ..
                }) => Some(name.clone()),
                _ => None,
            }
        })
        .is_some_and(|name| name.starts_with("multline"));
    let mut out = Vec::new();
    let mut row_start = body.start;
    for i in body.clone().chain(std::iter::once(body.end)) {
        if i == body.end || (toks[i].tok == Tok::RowBreak && env[i] == base) {
            if let Some(mut line) = line(&toks[row_start..i], &env[row_start..i], base, layout) {
                line.unclosed = unclosed.clone();
                out.push(line);
            }
            row_start = i + 1;
        }
    }
    if layout != Layout::Cases {
        out = joined(out, one_equation);
    }
    Ok(out)
}

/// Rows that continue the expression of the row before them joined to it:
/// a row starting with a binary operator (`&+ b`, `&\quad - c`, `\cdot
/// d`) and holding no relation of its own, a row after one that ends with
/// such an operator (`a = b +`), and every row of a `multline`.
fn joined(rows: Vec<Line>, one_equation: bool) -> Vec<Line> {
    let mut out: Vec<Line> = Vec::with_capacity(rows.len());
    for row in rows {
        let continues = out.last().is_some_and(|prev: &Line| {
            one_equation || ends_in_operator(&prev.statements[0]) || starts_a_continuation(&row)
        });
        match out.last_mut() {
            Some(prev) if continues => {
                let mut statements = row.statements.into_iter();
                if let Some(first) = statements.next() {
                    prev.statements[0].extend(first);
                }
                prev.statements.extend(statements);
                prev.span.end = prev.span.end.max(row.span.end);
            }
            _ => out.push(row),
        }
    }
    out
}

/// How many tokens at the start of a statement are words, not math:
/// `\text{where}`, `{\rm where}` (an upright word), with the spaces
/// around them; none when no word is there.
fn prose_before(piece: &[Token]) -> usize {
    let mut i = 0;
    let mut words = false;
    while i < piece.len() {
        let word = match &piece[i].tok {
            Tok::Space | Tok::Quad => {
                i += 1;
                continue;
            }
            Tok::Text(w) if !w.trim().is_empty() => Some(1),
            _ => upright_word(&piece[i..]),
        };
        // A word applied to something (`\mathrm{Ad}(T)`, `\text{Log}_x`) is
        // a function's name, not prose.
        let applied = |after: usize| {
            matches!(
                piece.get(after).map(|t| &t.tok),
                Some(Tok::Open(Delim::Paren) | Tok::Left(Delim::Paren) | Tok::Sub | Tok::Sup)
            )
        };
        match word {
            Some(n) if !applied(i + n) => {
                words = true;
                i += n;
            }
            _ => break,
        }
    }
    if words { i } else { 0 }
}

/// The length of an upright word at the start of `toks`: `\mathrm{where}`
/// (how `{\rm where}` is read), braced or not.
fn upright_word(toks: &[Token]) -> Option<usize> {
    let braced = usize::from(toks.first()?.tok == Tok::LBrace);
    let toks = &toks[braced..];
    if !matches!(&toks.first()?.tok, Tok::Command(c) if c == "mathrm")
        || toks.get(1)?.tok != Tok::LBrace
    {
        return None;
    }
    let letters = toks[2..]
        .iter()
        .take_while(|t| matches!(t.tok, Tok::Letter(_)))
        .count();
    if letters < 2 || toks.get(2 + letters)?.tok != Tok::RBrace {
        return None;
    }
    if braced == 1 && toks.get(3 + letters)?.tok != Tok::RBrace {
        return None;
    }
    Some(letters + 3 + 2 * braced)
}

/// Whether `tok` is an operator that needs an operand on each side.
fn is_binary_operator(tok: &Tok) -> bool {
    match tok {
        Tok::Plus | Tok::Minus | Tok::Star => true,
        Tok::Command(c) => lookup(crate::names::MULOP_COMMANDS, c).is_some(),
        _ => false,
    }
}

/// Whether a row's claim starts with a binary operator and states no
/// relation: the rest of an expression begun on an earlier row.
fn starts_a_continuation(row: &Line) -> bool {
    let claim = &row.statements[0];
    claim
        .iter()
        .find(|t| !matches!(t.tok, Tok::Space | Tok::Quad))
        .is_some_and(|t| is_binary_operator(&t.tok))
        && !row.continued
        && !claim.iter().any(|t| is_relation(&t.tok))
}

/// Whether a statement ends with a binary operator (its expression goes
/// on in the next row); a script's marker (`^\wedge`, `^*`) is none.
fn ends_in_operator(statement: &[Token]) -> bool {
    match statement {
        [.., before, last] => {
            is_binary_operator(&last.tok) && !matches!(before.tok, Tok::Sup | Tok::Sub)
        }
        [last] => is_binary_operator(&last.tok),
        [] => false,
    }
}

/// The depth of `\begin…\end` nesting before each token (an `\end`
/// without its `\begin` does not go below zero).
fn environment_depths(toks: &[Token]) -> Vec<usize> {
    let mut depth = 0usize;
    toks.iter()
        .map(|t| match t.tok {
            Tok::Begin(_) => {
                depth += 1;
                depth - 1
            }
            Tok::End(_) => {
                depth = depth.saturating_sub(1);
                depth
            }
            _ => depth,
        })
        .collect()
}

/// Whether the whole formula is one alignment or `cases` environment, the
/// tokens holding its rows, and the environment's name if it is not closed.
fn layout(toks: &[Token], env: &[usize]) -> (Layout, Range<usize>, Option<String>) {
    let plain = (Layout::Plain, 0..toks.len(), None);
    let Some(first) = toks
        .iter()
        .position(|t| !matches!(t.tok, Tok::Quad | Tok::Space))
    else {
        return plain;
    };
    let Tok::Begin(name) = &toks[first].tok else {
        return plain;
    };
    let layout = if CASES_ENVIRONMENTS.contains(&name.as_str()) {
        Layout::Cases
    } else if ALIGNMENT_ENVIRONMENTS.contains(&name.as_str()) {
        Layout::Aligned
    } else {
        return plain;
    };
    let close = (first + 1..toks.len())
        .find(|&i| env[i] == env[first] && matches!(toks[i].tok, Tok::End(_)));
    let ignorable = |t: &Tok| matches!(t, Tok::Quad | Tok::Space | Tok::Period | Tok::Comma);
    match close {
        Some(c) if toks[c + 1..].iter().all(|t| ignorable(&t.tok)) => (layout, first + 1..c, None),
        Some(_) => plain,
        None => (layout, first + 1..toks.len(), Some(name.clone())),
    }
}

/// Whether a token is a relation (`\Rightarrow` included).
pub(crate) fn is_relation(tok: &Tok) -> bool {
    match tok {
        Tok::Eq | Tok::Lt | Tok::Gt | Tok::Colon => true,
        Tok::Command(c) => lookup(RELATION_COMMANDS, c).is_some(),
        _ => false,
    }
}

/// Whether a token can end an operand (so that words after it start
/// another statement, not the operand a relation waits for).
fn ends_operand(tok: &Tok) -> bool {
    match tok {
        Tok::Letter(_)
        | Tok::Number(_)
        | Tok::Word(_)
        | Tok::RBrace
        | Tok::Close(_)
        | Tok::Right(_)
        | Tok::Prime
        | Tok::Bar
        | Tok::DoubleBar
        | Tok::End(_) => true,
        Tok::Command(c) => {
            lookup(RELATION_COMMANDS, c).is_none()
                && lookup(crate::names::MULOP_COMMANDS, c).is_none()
        }
        _ => false,
    }
}

fn is_implies(tok: &Tok) -> bool {
    matches!(tok, Tok::Command(c) if c == "Rightarrow" || c == "implies")
}

/// One row's statements: split at the row's top level (outside braces,
/// environments and delimiters; extra closers do not go below zero).
fn line(toks: &[Token], env: &[usize], base: usize, layout: Layout) -> Option<Line> {
    // Tokens a macro expanded to carry the place of its invocation, so the
    // line spans from the least start to the greatest end.
    let span = toks.iter().map(|t| t.start).min()?..toks.iter().map(|t| t.end).max()?;
    let mut statements: Vec<Vec<Token>> = Vec::new();
    let mut current: Vec<Token> = Vec::new();
    let (mut braces, mut depth) = (0usize, 0usize);
    let mut heads_chain = false;
    // Whether the statement being read was opened by a `\quad`.
    let mut after_quad = false;
    for (t, e) in toks.iter().zip(env) {
        match t.tok {
            Tok::LBrace => braces += 1,
            Tok::RBrace => braces = braces.saturating_sub(1),
            _ => {}
        }
        let top = *e == base && braces == 0;
        if top {
            match t.tok {
                Tok::Open(_) | Tok::Left(_) => depth += 1,
                Tok::Close(_) | Tok::Right(_) => depth = depth.saturating_sub(1),
                _ => {}
            }
        }
        let separator = top
            && depth == 0
            && match t.tok {
                Tok::Comma | Tok::Quad => true,
                Tok::Text(ref words) => {
                    !words.trim().is_empty()
                        && current.iter().any(|c| is_relation(&c.tok))
                        && current
                            .iter()
                            .rev()
                            .find(|c| !matches!(c.tok, Tok::Space | Tok::Quad))
                            .is_some_and(|c| ends_operand(&c.tok))
                }
                Tok::Amp => layout == Layout::Cases,
                _ => false,
            };
        if top && t.tok == Tok::Amp && layout == Layout::Aligned {
            continue;
        }
        if separator {
            close_statement(&mut statements, &mut current, after_quad);
            after_quad = t.tok == Tok::Quad;
            continue;
        }
        if top && depth == 0 && statements.is_empty() && is_relation(&t.tok) && !is_implies(&t.tok)
        {
            heads_chain = true;
        }
        current.push(t.clone());
    }
    close_statement(&mut statements, &mut current, after_quad);
    // Trailing punctuation.
    if let Some(last) = statements.last_mut() {
        while matches!(last.last().map(|t| &t.tok), Some(Tok::Period | Tok::Comma)) {
            last.pop();
        }
        if last.is_empty() {
            statements.pop();
        }
    }
    let first = statements.first()?.first()?;
    let continued = is_relation(&first.tok) && !is_implies(&first.tok);
    Some(Line {
        span,
        heads_chain: heads_chain && !continued,
        continued,
        statements,
        unclosed: None,
    })
}

/// Ends the statement being read: a piece opened by `\quad` that starts with
/// a relation continues the previous statement. Words before a formula on
/// its row (`{\rm where}~~ \frac{…}{…} = …`) are prose, dropped.
fn close_statement(statements: &mut Vec<Vec<Token>>, current: &mut Vec<Token>, after_quad: bool) {
    let mut piece = std::mem::take(current);
    let words = prose_before(&piece);
    if words == piece.len() && words > 0 {
        return; // only words: no statement
    }
    piece.drain(..words);
    if piece.is_empty() {
        return;
    }
    let starts_with_relation = is_relation(&piece[0].tok) && !is_implies(&piece[0].tok);
    match statements.last_mut() {
        Some(prev) if after_quad && starts_with_relation => prev.extend(piece),
        _ => statements.push(piece),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(math: &str) -> Vec<Vec<String>> {
        lines(math, &Vocabulary::default(), 0, None)
            .unwrap()
            .iter()
            .map(|l| {
                l.statements
                    .iter()
                    .map(|s| math[s[0].start..s.last().unwrap().end].to_string())
                    .collect()
            })
            .collect()
    }

    #[test]
    fn aligned_rows_are_lines_and_quads_separate_statements() {
        let math =
            "\\begin{aligned} a &= b \\quad (c = d) \\\\ &= e \\qquad \\in R. \\end{aligned}";
        assert_eq!(
            texts(math),
            vec![vec!["a &= b", "(c = d)"], vec!["= e \\qquad \\in R"]]
        );
        let l = lines(math, &Vocabulary::default(), 0, None).unwrap();
        assert!(l[0].heads_chain && !l[0].continued);
        assert!(l[1].continued && !l[1].heads_chain);
    }

    #[test]
    fn cases_rows_are_lines_with_conditions_as_notes() {
        assert_eq!(
            texts(
                "\\begin{cases} x = 1 & a > 0 \\\\ x = \\begin{bmatrix} 1 & 2 \\end{bmatrix} \\end{cases}"
            ),
            vec![
                vec!["x = 1", "a > 0"],
                vec!["x = \\begin{bmatrix} 1 & 2 \\end{bmatrix}"]
            ]
        );
    }

    #[test]
    fn commas_inside_groups_do_not_separate() {
        assert_eq!(
            texts("E(\\xi, \\omega) = (a \\quad b), c = d"),
            vec![vec!["E(\\xi, \\omega) = (a \\quad b)", "c = d"]]
        );
    }

    #[test]
    fn a_sum_continued_over_rows_is_one_line() {
        // `&+`, `\quad -`, a row ending in an operator, `\notag`.
        let math = "\\begin{align} a &= b \\notag \\\\ &\\quad + c \\\\ &- d \\cdot \\\\ & e \\\\ f &= g \\end{align}";
        assert_eq!(
            texts(math),
            vec![
                vec!["a &= b \\notag \\\\ &\\quad + c \\\\ &- d \\cdot \\\\ & e"],
                vec!["f &= g"]
            ]
        );
        // A script's marker is no operator; a row starting with a sign that
        // states a relation is a line.
        assert_eq!(texts("a = b^\\wedge \\\\ c = d^* \\\\ e = f").len(), 3);
        assert_eq!(texts("a = b \\\\ -c = d").len(), 2);
        // `multline`: one equation.
        assert_eq!(
            texts("\\begin{multline} a = b \\\\ c d \\end{multline}").len(),
            1
        );
    }

    #[test]
    fn words_before_a_formula_are_prose_but_a_function_name_is_not() {
        let statements = |math: &str| {
            lines(math, &Vocabulary::default(), 0, None).unwrap()[0].statements[0]
                .iter()
                .map(|t| math[t.start..t.end].to_string())
                .collect::<String>()
        };
        assert_eq!(statements("\\empty {\\rm where}~~ c = d"), "c=d");
        assert_eq!(statements("\\text{with} \\quad c = d"), "c=d");
        assert_eq!(statements("\\mathrm{Ad}(T) = x"), "\\mathrm{Ad}(T)=x");
    }

    #[test]
    fn a_garbled_row_does_not_hide_the_others() {
        let math = "\\begin{split} a &= \\frac{b}}{c} \\\\ &= d \\end{split}";
        assert_eq!(texts(math), vec![vec!["a &= \\frac{b}}{c}"], vec!["= d"]]);
    }

    #[test]
    fn an_unclosed_environment_around_the_display_closes_at_its_end() {
        let l = lines(
            "\\begin{cases} a = b \\\\ c = d",
            &Vocabulary::default(),
            0,
            None,
        )
        .unwrap();
        assert_eq!(l.len(), 2);
        assert_eq!(l[1].unclosed.as_deref(), Some("cases"));
    }
}
