//! The macros a document defines and the words it uses as function names:
//! its [`Vocabulary`], applied to every formula's tokens.
//!
//! Definitions are `\newcommand`, `\renewcommand`, `\providecommand` (with
//! `[n]` parameters and an optional `[default]` for the first),
//! `\def\name#1#2{…}`, `\let\a\b` and `\DeclareMathOperator{\name}{text}`,
//! in the prose (a LaTeX preamble) or inside math (`$\newcommand…$`, as
//! MathJax reads Markdown). A formula sees the definitions made before it;
//! a later one of the same name replaces an earlier one. A macro is
//! expanded on the tokens: its arguments are braced groups or single
//! tokens, its body's tokens carry the place of the invocation (errors
//! point at it). Expansion is bounded: at most [`MAX_EXPANSIONS`] macros a
//! formula and [`MAX_EXPANDED_TOKENS`] tokens, so a macro defined in terms
//! of itself is an error, not a hang.

use std::collections::VecDeque;

use crate::definition::{Definition, definition};
use crate::error::ErrorKind;
use crate::lexer::{LexError, Tok, Token, lex_words};
use crate::rewrite::rewrite;

/// Most macro expansions in one formula.
pub const MAX_EXPANSIONS: usize = 4096;
/// Most tokens a formula may expand to.
pub const MAX_EXPANDED_TOKENS: usize = 100_000;

/// A macro: its name (without backslash), parameters and body.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Macro {
    /// Where it is defined in the document (byte offset).
    at: usize,
    name: String,
    params: u8,
    /// The default of the first parameter, which is then optional (`[…]`).
    default: Option<Vec<Token>>,
    body: Vec<Token>,
}

/// The macros and function words a document's formulas are read with.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Vocabulary {
    words: Vec<String>,
    macros: Vec<Macro>,
}

impl Vocabulary {
    /// No macros; `words` read as function names (`between(a, b)`) besides
    /// the built-in ones.
    pub fn with_words(words: &[&str]) -> Self {
        Vocabulary {
            words: words.iter().map(|w| w.to_string()).collect(),
            macros: Vec::new(),
        }
    }

    /// The vocabulary of `text`: `words`, and every macro it defines
    /// (skipping `%` comments when `comments`).
    pub(crate) fn scan(text: &str, words: &[&str], comments: bool) -> Self {
        let mut v = Vocabulary::with_words(words);
        let bytes = text.as_bytes();
        let mut i = 0;
        while i < bytes.len() {
            match bytes[i] {
                b'%' if comments && (i == 0 || bytes[i - 1] != b'\\') => {
                    i = text[i..].find('\n').map_or(text.len(), |k| i + k);
                }
                b'\\' => match definition(text, i) {
                    Some((d, end)) => {
                        v.define(i, &d);
                        i = end;
                    }
                    None => i += 2,
                },
                _ => i += 1,
            }
        }
        v
    }

    /// Adds the definitions of `latex` (a symbols file's own macros), as if
    /// made at the end of the document.
    pub fn define_all(&mut self, latex: &str) {
        let scanned = Vocabulary::scan(latex, &[], true);
        for mut m in scanned.macros {
            m.at = usize::MAX - 1;
            self.macros.push(m);
        }
    }

    /// The function words it adds.
    pub fn words(&self) -> &[String] {
        &self.words
    }

    /// The names of its macros, in the order defined.
    pub fn macro_names(&self) -> Vec<&str> {
        self.macros.iter().map(|m| m.name.as_str()).collect()
    }

    fn define(&mut self, at: usize, d: &Definition) {
        let lexed = |s: &str| lex_words(s, &self.words).ok();
        let Some(body) = lexed(&d.body) else {
            return;
        };
        let default = match &d.default {
            Some(s) => match lexed(s) {
                Some(t) => Some(t),
                None => return,
            },
            None => None,
        };
        self.macros.push(Macro {
            at,
            name: d.name.clone(),
            params: d.params,
            default,
            body,
        });
    }

    /// The macro `name` as defined before byte `at`.
    fn lookup(&self, name: &str, at: usize) -> Option<&Macro> {
        self.macros
            .iter()
            .rev()
            .find(|m| m.name == name && m.at < at)
    }

    /// `toks` with every macro defined before byte `at` expanded.
    pub(crate) fn expand(&self, toks: Vec<Token>, at: usize) -> Result<Vec<Token>, LexError> {
        if self.macros.is_empty() {
            return Ok(toks);
        }
        let mut input: VecDeque<Token> = toks.into();
        let mut out = Vec::with_capacity(input.len());
        let mut expansions = 0;
        while let Some(t) = input.pop_front() {
            let Tok::Command(name) = &t.tok else {
                out.push(t);
                continue;
            };
            let Some(m) = self.lookup(name, at) else {
                out.push(t);
                continue;
            };
            expansions += 1;
            if expansions > MAX_EXPANSIONS || out.len() + input.len() > MAX_EXPANDED_TOKENS {
                return Err((t.start, ErrorKind::MacroExpansion(name.clone())));
            }
            let mut args: Vec<Vec<Token>> = Vec::with_capacity(m.params as usize);
            let mut needed = m.params as usize;
            // Where the invocation ends (its last argument's closing brace).
            let mut end = t.end;
            if let Some(default) = &m.default {
                needed = needed.saturating_sub(1);
                args.push(match input.front().map(|t| &t.tok) {
                    Some(Tok::Open(crate::lexer::Delim::Bracket)) => {
                        let (arg, at) = optional(&mut input)
                            .ok_or((t.start, ErrorKind::MissingOperand(format!("\\{name}"))))?;
                        end = end.max(at);
                        arg
                    }
                    _ => default.clone(),
                });
            }
            for _ in 0..needed {
                let (arg, at) = argument(&mut input)
                    .ok_or((t.start, ErrorKind::MissingOperand(format!("\\{name}"))))?;
                end = end.max(at);
                args.push(arg);
            }
            let mut body = Vec::with_capacity(m.body.len());
            for b in &m.body {
                match b.tok {
                    Tok::Param(k) => match args.get(k as usize - 1) {
                        Some(arg) => body.extend(arg.iter().cloned()),
                        None => return Err((t.start, ErrorKind::MacroExpansion(name.clone()))),
                    },
                    // The macro's own tokens span the whole invocation, so
                    // that a line ends where its last argument does.
                    ref tok => body.push(Token {
                        tok: tok.clone(),
                        start: t.start,
                        end,
                    }),
                }
            }
            for b in body.into_iter().rev() {
                input.push_front(b);
            }
        }
        Ok(out)
    }
}

/// The tokens of a formula's `src` (at byte `at` of its document): lexed
/// with the vocabulary's words, macros expanded, rewritten
/// ([`crate::rewrite`]).
pub(crate) fn tokens(src: &str, vocab: &Vocabulary, at: usize) -> Result<Vec<Token>, LexError> {
    let toks = lex_words(src, &vocab.words)?;
    let toks = vocab.expand(toks, at)?;
    Ok(rewrite(toks))
}

/// A macro's argument at the front of `input` (after spaces): a braced
/// group's content, or one token; with the end of what it took.
fn argument(input: &mut VecDeque<Token>) -> Option<(Vec<Token>, usize)> {
    // TeX skips spaces before an undelimited argument (`\skew 1p`).
    while input.front().is_some_and(|t| t.tok == Tok::Space) {
        input.pop_front();
    }
    let first = input.pop_front()?;
    if first.tok != Tok::LBrace {
        let end = first.end;
        return (!matches!(first.tok, Tok::RBrace)).then(|| (vec![first], end));
    }
    let mut depth = 1usize;
    let mut out = Vec::new();
    while let Some(t) = input.pop_front() {
        match t.tok {
            Tok::LBrace => depth += 1,
            Tok::RBrace => {
                depth -= 1;
                if depth == 0 {
                    return Some((out, t.end));
                }
            }
            _ => {}
        }
        out.push(t);
    }
    None
}

/// An optional argument `[…]` at the front of `input` (brackets inside
/// braces do not close it), with the end of what it took.
fn optional(input: &mut VecDeque<Token>) -> Option<(Vec<Token>, usize)> {
    input.pop_front()?;
    let mut braces = 0usize;
    let mut out = Vec::new();
    while let Some(t) = input.pop_front() {
        match t.tok {
            Tok::LBrace => braces += 1,
            Tok::RBrace => braces = braces.saturating_sub(1),
            Tok::Close(crate::lexer::Delim::Bracket) if braces == 0 => return Some((out, t.end)),
            _ => {}
        }
        out.push(t);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lexer::lex;

    fn expanded(defs: &str, math: &str) -> Vec<Tok> {
        let v = Vocabulary::scan(defs, &[], true);
        v.expand(lex(math).unwrap(), usize::MAX)
            .unwrap()
            .into_iter()
            .map(|t| t.tok)
            .collect()
    }

    #[test]
    fn expansion_substitutes_arguments_and_nests() {
        let defs = "\\newcommand{\\deriv}[2]{\\frac{\\partial#1}{\\partial#2}}\n\
                    \\newcommand\\Skew[1]{[#1]_{\\times}}\n% \\newcommand\\Skew[1]{no}\n";
        assert_eq!(
            expanded(defs, "\\deriv p{\\Skew q}"),
            expanded("", "\\frac{\\partial p}{\\partial [q]_{\\times}}")
        );
        let looping = "\\newcommand\\a{\\a x}";
        let v = Vocabulary::scan(looping, &[], true);
        assert!(matches!(
            v.expand(lex("\\a").unwrap(), usize::MAX),
            Err((_, ErrorKind::MacroExpansion(_)))
        ));
        // A macro is seen only after its definition.
        let v = Vocabulary::scan("$\\x$ \\newcommand\\x{y}", &[], true);
        assert_eq!(
            v.expand(lex("\\x").unwrap(), 3).unwrap()[0].tok,
            Tok::Command("x".into())
        );
    }
}
