//! Token rewrites done before parsing: notation that only decorates, or
//! that plain TeX writes differently, brought to the forms the parser
//! reads.
//!
//! - an accent over nothing after an operand, `\{…\}\check{}`: the vee (a
//!   `\hat{}`: the hat) on it;
//! - `\mathop{\lim}`, `\mathrel{=}`, `\mathbin`, `\mathord`, `\boxed{x}`, …:
//!   the wrapper is dropped (`\mathop{\lim}\limits_{x \to 0}` is `\lim_{x \to 0}`);
//! - `\stackrel{\Delta}{=}`, `\overset{a}{b}`, `\underset{a}{b}`,
//!   `\buildrel a \over =`: the decoration above or below is dropped;
//!   `\underbrace{x}_{\text{…}}` and `\overbrace{x}^{…}` keep `x`;
//! - plain-TeX font switches `{\rm d}`, `{\bf x}`, `{\cal L}`: the font
//!   command over the rest of the group;
//! - `{a \over b}`: `\frac{a}{b}`;
//! - braces right after a function name (`\cos{(\theta)}`, `\exp{(v))}`)
//!   only group in print: they are dropped, so the function takes what is
//!   printed after it; so are braces that only group and hold unbalanced
//!   parentheses (`(\exp{(v))}` prints `(exp((v))`).

use crate::lexer::{Delim, Tok, Token};
use crate::names::function_command;

/// Commands dropped with the braces of their argument, which stays.
const WRAPPERS: &[&str] = &[
    "mathop",
    "mathrel",
    "mathbin",
    "mathord",
    "mathpunct",
    "mathinner",
    "mathopen",
    "mathclose",
    "boxed",
    "smash",
    "mathstrut",
    "ensuremath",
];

/// Commands of two arguments whose second is what is read.
const DECORATED: &[&str] = &["stackrel", "overset", "underset", "textcolor"];

/// Plain-TeX font switches and the font command each stands for.
const SWITCHES: &[(&str, &str)] = &[
    ("rm", "mathrm"),
    ("bf", "mathbf"),
    ("it", "mathit"),
    ("cal", "mathcal"),
    ("sf", "mathsf"),
    ("mit", "mathit"),
];

/// Every rewrite, in order.
pub(crate) fn rewrite(toks: Vec<Token>) -> Vec<Token> {
    let toks = empty_accents(toks);
    let toks = unwrap_wrappers(toks);
    let toks = drop_decorations(toks);
    let toks = font_switches(toks);
    let toks = over_to_frac(toks);
    dissolve_groups(toks)
}

/// For each `{`, the index of its `}` (unbalanced braces map to nothing).
fn matching(toks: &[Token]) -> Vec<Option<usize>> {
    let mut out = vec![None; toks.len()];
    let mut open = Vec::new();
    for (i, t) in toks.iter().enumerate() {
        match t.tok {
            Tok::LBrace => open.push(i),
            Tok::RBrace => {
                if let Some(o) = open.pop() {
                    out[o] = Some(i);
                    out[i] = Some(o);
                }
            }
            _ => {}
        }
    }
    out
}

fn is_command(t: &Token, names: &[&str]) -> bool {
    matches!(&t.tok, Tok::Command(c) if names.contains(&c.as_str()))
}

/// An accent over nothing after an operand is an operator on it:
/// `\{ R^\top F \} \check{}` → `\{ … \}^{\vee}` (a vee), `X \hat{}` →
/// `X^{\wedge}` (a hat).
fn empty_accents(toks: Vec<Token>) -> Vec<Token> {
    let empty_accent = |i: usize| -> Option<&'static str> {
        let op = match &toks.get(i)?.tok {
            Tok::Command(c) if c == "check" => "vee",
            Tok::Command(c) if c == "hat" || c == "widehat" => "wedge",
            _ => return None,
        };
        (toks.get(i + 1)?.tok == Tok::LBrace
            && toks.get(i + 2)?.tok == Tok::RBrace
            && i > 0
            && matches!(
                toks[i - 1].tok,
                Tok::RBrace | Tok::Close(_) | Tok::Right(_) | Tok::Letter(_) | Tok::Number(_)
            ))
        .then_some(op)
    };
    if !(0..toks.len()).any(|i| empty_accent(i).is_some()) {
        return toks;
    }
    let mut out = Vec::with_capacity(toks.len() + 2);
    let mut i = 0;
    while i < toks.len() {
        if let Some(op) = empty_accent(i) {
            let (start, end) = (toks[i].start, toks[i + 2].end);
            let at = |tok| Token { tok, start, end };
            out.extend([
                at(Tok::Sup),
                at(Tok::LBrace),
                at(Tok::Command(op.into())),
                at(Tok::RBrace),
            ]);
            i += 3;
            continue;
        }
        out.push(toks[i].clone());
        i += 1;
    }
    out
}

/// `\mathop{x}` → `x`.
fn unwrap_wrappers(toks: Vec<Token>) -> Vec<Token> {
    if !toks.iter().any(|t| is_command(t, WRAPPERS)) {
        return toks;
    }
    let m = matching(&toks);
    let mut drop = vec![false; toks.len()];
    for (i, t) in toks.iter().enumerate() {
        if is_command(t, WRAPPERS) {
            drop[i] = true;
            if toks.get(i + 1).map(|t| &t.tok) == Some(&Tok::LBrace)
                && let Some(close) = m[i + 1]
            {
                drop[i + 1] = true;
                drop[close] = true;
            }
        }
    }
    keep(toks, &drop)
}

/// `\stackrel{a}{b}` → `b`; `\buildrel a \over b` → `b`;
/// `\underbrace{x}_{l}` → `x`.
fn drop_decorations(toks: Vec<Token>) -> Vec<Token> {
    let interesting = ["stackrel", "overset", "underset", "textcolor", "buildrel"]
        .into_iter()
        .chain(["underbrace", "overbrace"]);
    let names: Vec<&str> = interesting.collect();
    if !toks.iter().any(|t| is_command(t, &names)) {
        return toks;
    }
    let m = matching(&toks);
    let mut drop = vec![false; toks.len()];
    // The end (exclusive) of the argument starting at `i`.
    let arg_end = |i: usize| -> Option<usize> {
        match toks.get(i).map(|t| &t.tok) {
            Some(Tok::LBrace) => m[i].map(|c| c + 1),
            Some(_) => Some(i + 1),
            None => None,
        }
    };
    let mut i = 0;
    while i < toks.len() {
        if is_command(&toks[i], DECORATED) {
            if let Some(first_end) = arg_end(i + 1)
                && let Some(second_end) = arg_end(first_end)
            {
                drop[i..first_end].iter_mut().for_each(|d| *d = true);
                if toks[first_end].tok == Tok::LBrace {
                    drop[first_end] = true;
                    drop[second_end - 1] = true;
                }
                i = second_end;
                continue;
            }
        } else if is_command(&toks[i], &["buildrel"]) {
            if let Some(over) = (i + 1..toks.len()).find(|k| is_command(&toks[*k], &["over"])) {
                drop[i..=over].iter_mut().for_each(|d| *d = true);
                i = over + 1;
                continue;
            }
        } else if is_command(&toks[i], &["underbrace", "overbrace"])
            && let Some(end) = arg_end(i + 1)
        {
            drop[i] = true;
            if toks[i + 1].tok == Tok::LBrace {
                drop[i + 1] = true;
                drop[end - 1] = true;
            }
            if matches!(toks.get(end).map(|t| &t.tok), Some(Tok::Sub | Tok::Sup))
                && let Some(label_end) = arg_end(end + 1)
            {
                drop[end..label_end].iter_mut().for_each(|d| *d = true);
            }
            i = end;
            continue;
        }
        i += 1;
    }
    keep(toks, &drop)
}

/// `{\rm d}` → `{\mathrm{d}}`; outside a group the switch takes the letters
/// that follow it.
fn font_switches(mut toks: Vec<Token>) -> Vec<Token> {
    let switch = |t: &Token| match &t.tok {
        Tok::Command(c) => SWITCHES.iter().find(|(s, _)| s == c).map(|(_, f)| *f),
        _ => None,
    };
    while let Some(i) = toks.iter().position(|t| switch(t).is_some()) {
        let font = switch(&toks[i]).expect("a switch");
        let m = matching(&toks);
        // The end of the enclosing group, or of the run of letters after.
        let enclosing = (0..i)
            .rev()
            .find(|&o| toks[o].tok == Tok::LBrace && m[o].is_some_and(|c| c > i))
            .and_then(|o| m[o]);
        let end = enclosing.unwrap_or_else(|| {
            (i + 1..toks.len())
                .find(|&k| {
                    !matches!(toks[k].tok, Tok::Letter(_))
                        || (k > i + 1 && toks[k].start != toks[k - 1].end)
                })
                .unwrap_or(toks.len())
        });
        let (start, stop) = (toks[i].start, toks[i].end);
        let at = |tok| Token {
            tok,
            start,
            end: stop,
        };
        toks[i] = at(Tok::Command(font.into()));
        toks.insert(end, at(Tok::RBrace));
        toks.insert(i + 1, at(Tok::LBrace));
    }
    toks
}

/// `{a \over b}` → `\frac{a}{b}` (the innermost group holding `\over`).
fn over_to_frac(mut toks: Vec<Token>) -> Vec<Token> {
    while let Some(over) = toks.iter().position(|t| is_command(t, &["over"])) {
        let m = matching(&toks);
        let open = (0..over)
            .rev()
            .find(|&o| toks[o].tok == Tok::LBrace && m[o].is_some_and(|c| c > over));
        let (start, end) = (toks[over].start, toks[over].end);
        let at = |tok| Token { tok, start, end };
        match open {
            Some(o) => {
                toks[over] = at(Tok::RBrace);
                toks.insert(over + 1, at(Tok::LBrace));
                toks.insert(o, at(Tok::Command("frac".into())));
            }
            None => {
                // A whole formula `a \over b`.
                toks[over] = at(Tok::RBrace);
                toks.insert(over + 1, at(Tok::LBrace));
                toks.insert(0, at(Tok::LBrace));
                toks.insert(0, at(Tok::Command("frac".into())));
                toks.push(at(Tok::RBrace));
            }
        }
    }
    toks
}

/// Whether a `{` after token `prev` is a command's or a script's argument.
fn is_argument_position(prev: Option<&Token>) -> bool {
    match prev.map(|t| &t.tok) {
        Some(Tok::Sup | Tok::Sub | Tok::RBrace | Tok::Close(Delim::Bracket)) => true,
        Some(Tok::Command(c)) => function_command(c).is_none(),
        _ => false,
    }
}

/// Drops the braces of groups that only group: right after a function
/// name, or holding unbalanced parentheses.
fn dissolve_groups(toks: Vec<Token>) -> Vec<Token> {
    let m = matching(&toks);
    let mut drop = vec![false; toks.len()];
    for (i, t) in toks.iter().enumerate() {
        if t.tok != Tok::LBrace {
            continue;
        }
        let Some(close) = m[i] else { continue };
        if close == i + 1 {
            continue;
        }
        let prev = i.checked_sub(1).map(|k| &toks[k]);
        let after_function = match prev.map(|t| &t.tok) {
            Some(Tok::Word(_)) => true,
            Some(Tok::Command(c)) => function_command(c).is_some(),
            _ => false,
        };
        let unbalanced = !is_argument_position(prev) && {
            let mut depth = 0i64;
            for t in &toks[i + 1..close] {
                match t.tok {
                    Tok::Open(Delim::Paren) | Tok::Left(Delim::Paren) => depth += 1,
                    Tok::Close(Delim::Paren) | Tok::Right(Delim::Paren) => depth -= 1,
                    _ => {}
                }
            }
            depth != 0
        };
        if after_function || unbalanced {
            drop[i] = true;
            drop[close] = true;
        }
    }
    keep(toks, &drop)
}

fn keep(toks: Vec<Token>, drop: &[bool]) -> Vec<Token> {
    toks.into_iter()
        .zip(drop)
        .filter(|(_, d)| !**d)
        .map(|(t, _)| t)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lexer::lex;

    fn same(a: &str, b: &str) {
        let kinds = |s: &str| -> Vec<Tok> {
            rewrite(lex(s).unwrap())
                .into_iter()
                .map(|t| t.tok)
                .collect()
        };
        assert_eq!(kinds(a), kinds(b), "{a}");
    }

    #[test]
    fn decorations_and_plain_tex() {
        same("\\mathop{\\lim}\\limits_{x}", "\\lim_{x}");
        same("a \\stackrel{\\Delta}{=} b", "a = b");
        same("a \\buildrel \\rm def \\over = b", "a = b");
        same("\\underbrace{x}_{\\text{y}} + 1", "x + 1");
        same("{\\rm Ad}", "{\\mathrm{Ad}}");
        same("{a \\over b}", "\\frac{a}{b}");
        same("(\\exp{(v))}", "(\\exp(v))");
        same("\\cos{(x) y}", "\\cos(x) y");
        // A script's braces stay.
        same("x^{(a)}", "x^{(a)}");
    }
}
