//! Tokens of LaTeX math.
//!
//! Whitespace, comments, thin spaces (`\,` `\;` `\:` `\!`, `\kern…`),
//! sizing commands (`\big`, …), `\displaystyle`, `\hline`, `\label{…}`,
//! `\tag{…}`, `\nonumber`, `\color{…}`, `\phantom{…}`, `\vspace{…}`, the
//! spacing of a row break `\\[1em]` and macro definitions met inside math
//! (`\newcommand…`, collected by [`crate::macros`]) produce no token. Wide
//! spaces do: `\quad`/`\qquad` as [`Tok::Quad`], `\ `/`~`/`\hspace{…}` as
//! [`Tok::Space`], because the documents separate row-vector entries (and
//! statements) with them. `\mbox{\boldmath $x$}` and `\text{$x$}`, text
//! holding only math, are that math (bold for `\boldmath`).

use crate::definition::definition;
use crate::error::ErrorKind;
use crate::names::function_word;

/// One token and the bytes it spans.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Token {
    /// What it is.
    pub tok: Tok,
    /// First byte.
    pub start: usize,
    /// One past the last byte.
    pub end: usize,
}

/// A token's kind.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Tok {
    /// Digits, with an optional decimal part.
    Number(String),
    /// One letter.
    Letter(char),
    /// A run of letters that is a function name (`Exp`, `sinc`, or a word
    /// the caller names).
    Word(String),
    /// `#1` … `#9`: a parameter of a macro's body.
    Param(u8),
    /// `\name` or `\c` (one non-letter) not handled below.
    Command(String),
    /// `\begin{name}`.
    Begin(String),
    /// `\end{name}`.
    End(String),
    /// `\text{…}`, `\textrm{…}`, `\mbox{…}`: the raw content.
    Text(String),
    /// `\operatorname{…}`: the raw content.
    OperatorName(String),
    /// `{`.
    LBrace,
    /// `}`.
    RBrace,
    /// An opening delimiter: `(`, `[`, `\{`, `\lfloor`.
    Open(Delim),
    /// A closing delimiter: `)`, `]`, `\}`, `\rfloor`.
    Close(Delim),
    /// `\left` and its delimiter.
    Left(Delim),
    /// `\right` and its delimiter.
    Right(Delim),
    /// `|`, `\vert`, `\lvert`, `\rvert`.
    Bar,
    /// `\|`, `\Vert`, `\lVert`, `\rVert`.
    DoubleBar,
    /// `&`.
    Amp,
    /// `\\`.
    RowBreak,
    /// `\quad`, `\qquad`.
    Quad,
    /// `\ `, `~`, `\hspace{…}`.
    Space,
    /// `^`.
    Sup,
    /// `_`.
    Sub,
    /// `'`.
    Prime,
    /// `,`.
    Comma,
    /// `.`.
    Period,
    /// `:`.
    Colon,
    /// `+`.
    Plus,
    /// `-`.
    Minus,
    /// `*`.
    Star,
    /// `/`.
    Slash,
    /// `=`.
    Eq,
    /// `<`.
    Lt,
    /// `>`.
    Gt,
    /// Any other character.
    Other(char),
}

/// A delimiter's kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Delim {
    /// `(` `)`.
    Paren,
    /// `[` `]`.
    Bracket,
    /// `\{` `\}`.
    Brace,
    /// `\lfloor` `\rfloor`.
    Floor,
    /// `|`.
    Bar,
    /// `\|`.
    DoubleBar,
    /// `.` after `\left`/`\right`.
    Invisible,
}

impl Delim {
    /// The opening delimiter as printed.
    pub fn open(self) -> &'static str {
        match self {
            Delim::Paren => "(",
            Delim::Bracket => "[",
            Delim::Brace => "\\{",
            Delim::Floor => "\\lfloor",
            Delim::Bar => "|",
            Delim::DoubleBar => "\\|",
            Delim::Invisible => ".",
        }
    }

    /// The closing delimiter as printed.
    pub fn close(self) -> &'static str {
        match self {
            Delim::Paren => ")",
            Delim::Bracket => "]",
            Delim::Brace => "\\}",
            Delim::Floor => "\\rfloor",
            Delim::Bar => "|",
            Delim::DoubleBar => "\\|",
            Delim::Invisible => ".",
        }
    }
}

/// A lexing error: the byte offset and what is wrong.
pub type LexError = (usize, ErrorKind);

/// Commands that produce no token.
const IGNORED: &[&str] = &[
    "empty",
    "space",
    "allowbreak",
    "nobreak",
    "hfill",
    "boldmath",
    "unboldmath",
    "displaystyle",
    "textstyle",
    "scriptstyle",
    "scriptscriptstyle",
    "limits",
    "nolimits",
    "nonumber",
    "notag",
    "empty",
    "hline",
    "big",
    "Big",
    "bigg",
    "Bigg",
    "bigl",
    "bigr",
    "Bigl",
    "Bigr",
    "biggl",
    "biggr",
    "Biggl",
    "Biggr",
];

/// Commands whose braced argument is read raw and dropped.
const IGNORED_WITH_ARGUMENT: &[&str] = &[
    "label", "tag", "tag*", "color", "phantom", "hphantom", "vphantom", "vspace", "vspace*",
    "mspace",
];

/// Commands followed by a dimension (`\kern-.05em`), dropped with it.
const IGNORED_WITH_DIMENSION: &[&str] = &["kern", "mkern", "hskip", "mskip", "vskip"];

/// Text commands whose raw argument is kept.
const TEXT_COMMANDS: &[&str] = &["text", "textrm", "textit", "textbf", "textnormal", "mbox"];

/// How deep `\mbox{$…$}` may nest math in text in math.
const MAX_TEXT_NESTING: usize = 8;

/// The tokens of `src`.
#[cfg(test)]
pub fn lex(src: &str) -> Result<Vec<Token>, LexError> {
    lex_words(src, &[])
}

/// The tokens of `src`, with `words` read as function names too.
pub fn lex_words(src: &str, words: &[String]) -> Result<Vec<Token>, LexError> {
    Lexer {
        src,
        pos: 0,
        words,
        nesting: 0,
    }
    .run()
}

struct Lexer<'a> {
    src: &'a str,
    pos: usize,
    words: &'a [String],
    /// How deep this text is in `\mbox{$…$}` math.
    nesting: usize,
}

impl Lexer<'_> {
    fn run(mut self) -> Result<Vec<Token>, LexError> {
        let mut out = Vec::new();
        while let Some(c) = self.peek() {
            let start = self.pos;
            let tok = match c {
                c if c.is_whitespace() => {
                    self.bump(c);
                    continue;
                }
                '%' => {
                    while let Some(c) = self.peek() {
                        if c == '\n' {
                            break;
                        }
                        self.bump(c);
                    }
                    continue;
                }
                '\\' => match self.command()? {
                    Some(Command::One(t)) => t,
                    Some(Command::Many(toks)) => {
                        out.extend(toks);
                        continue;
                    }
                    None => continue,
                },
                ':' if self.src[self.pos + 1..].starts_with('=') => {
                    self.pos += 2;
                    Tok::Command("coloneqq".into())
                }
                '0'..='9' => self.number(),
                '#' if self.src[self.pos + 1..].starts_with(|d: char| ('1'..='9').contains(&d)) => {
                    let d = self.src.as_bytes()[self.pos + 1] - b'0';
                    self.pos += 2;
                    Tok::Param(d)
                }
                c if c.is_ascii_alphabetic() => {
                    let words = self.words;
                    let run = self.take_while(|c| c.is_ascii_alphabetic());
                    if function_word(run).is_some() || words.iter().any(|w| w == run) {
                        Tok::Word(run.to_string())
                    } else {
                        // One token per letter: `yy^T` is y · y^T.
                        for (i, c) in run.char_indices() {
                            out.push(Token {
                                tok: Tok::Letter(c),
                                start: start + i,
                                end: start + i + 1,
                            });
                        }
                        continue;
                    }
                }
                c => {
                    self.bump(c);
                    single(c)
                }
            };
            out.push(Token {
                tok,
                start,
                end: self.pos,
            });
        }
        Ok(out)
    }

    fn peek(&self) -> Option<char> {
        self.src[self.pos..].chars().next()
    }

    fn bump(&mut self, c: char) {
        self.pos += c.len_utf8();
    }

    fn take_while(&mut self, f: impl Fn(char) -> bool) -> &str {
        let start = self.pos;
        while let Some(c) = self.peek().filter(|c| f(*c)) {
            self.bump(c);
        }
        &self.src[start..self.pos]
    }

    fn skip_whitespace(&mut self) {
        self.take_while(char::is_whitespace);
    }

    fn number(&mut self) -> Tok {
        let start = self.pos;
        self.take_while(|c| c.is_ascii_digit());
        let rest = &self.src[self.pos..];
        if rest.starts_with('.') && rest[1..].starts_with(|c: char| c.is_ascii_digit()) {
            self.pos += 1;
            self.take_while(|c| c.is_ascii_digit());
        }
        Tok::Number(self.src[start..self.pos].to_string())
    }

    /// The command at `\`; `None` when it produces no token.
    fn command(&mut self) -> Result<Option<Command>, LexError> {
        let start = self.pos;
        if let Some((_, end)) = definition(self.src, start) {
            // A macro definition inside math: collected by the document.
            self.pos = end;
            return Ok(None);
        }
        self.pos += 1;
        let Some(c) = self.peek() else {
            return Err((start, ErrorKind::LoneBackslash));
        };
        if !c.is_ascii_alphabetic() {
            self.bump(c);
            return Ok(match c {
                ',' | ';' | ':' | '!' | '>' => None,
                ' ' | '\t' | '\n' | '\r' => Some(Tok::Space),
                '\\' => {
                    self.row_break_spacing();
                    Some(Tok::RowBreak)
                }
                '{' => Some(Tok::Open(Delim::Brace)),
                '}' => Some(Tok::Close(Delim::Brace)),
                '|' => Some(Tok::DoubleBar),
                c => Some(Tok::Command(c.to_string())),
            }
            .map(Command::One));
        }
        let mut name = self.take_while(|c| c.is_ascii_alphabetic()).to_string();
        let starred = ["tag", "begin", "end", "operatorname", "vspace"];
        if starred.contains(&name.as_str()) && self.peek() == Some('*') {
            // `\tag*{…}`; `\begin*` does not exist but costs nothing to allow.
            self.pos += 1;
            if name != "operatorname" {
                name.push('*');
            }
        }
        let tok = match name.as_str() {
            "begin" => Tok::Begin(self.raw_argument(start)?),
            "end" => Tok::End(self.raw_argument(start)?),
            n if TEXT_COMMANDS.contains(&n) => {
                let content = self.raw_argument(start)?;
                if let Some(toks) = self.text_math(&content, start)? {
                    return Ok(Some(Command::Many(toks)));
                }
                Tok::Text(content)
            }
            "operatorname" => Tok::OperatorName(self.raw_argument(start)?),
            "hspace" | "hspace*" => {
                self.raw_argument(start)?;
                Tok::Space
            }
            "quad" | "qquad" => Tok::Quad,
            "cr" => Tok::RowBreak,
            "left" => Tok::Left(self.delimiter(start)?),
            "right" => Tok::Right(self.delimiter(start)?),
            "lfloor" => Tok::Open(Delim::Floor),
            "rfloor" => Tok::Close(Delim::Floor),
            "vert" | "lvert" | "rvert" => Tok::Bar,
            "Vert" | "lVert" | "rVert" => Tok::DoubleBar,
            n if IGNORED.contains(&n) => return Ok(None),
            n if IGNORED_WITH_ARGUMENT.contains(&n) => {
                self.raw_argument(start)?;
                return Ok(None);
            }
            n if IGNORED_WITH_DIMENSION.contains(&n) => {
                self.dimension();
                return Ok(None);
            }
            _ => Tok::Command(name),
        };
        Ok(Some(Command::One(tok)))
    }

    /// Skips the `[1em]` or `*` after a row break.
    fn row_break_spacing(&mut self) {
        let rest = &self.src[self.pos..];
        let trimmed = rest.trim_start();
        let skipped = rest.len() - trimmed.len();
        if trimmed.starts_with('*') {
            self.pos += skipped + 1;
            return self.row_break_spacing();
        }
        if let Some(inner) = trimmed.strip_prefix('[')
            && let Some(close) = inner.find(']')
            && is_dimension(inner[..close].trim())
        {
            self.pos += skipped + 1 + close + 1;
        }
    }

    /// Skips a dimension `-.05em`, `3mu`, `= 2pt`.
    fn dimension(&mut self) {
        self.skip_whitespace();
        if self.peek() == Some('=') {
            self.pos += 1;
            self.skip_whitespace();
        }
        let rest = &self.src[self.pos..];
        let number = rest
            .char_indices()
            .find(|(_, c)| !(c.is_ascii_digit() || *c == '.' || *c == '-' || *c == '+'))
            .map_or(rest.len(), |(i, _)| i);
        let unit = rest[number..]
            .char_indices()
            .find(|(_, c)| !c.is_ascii_alphabetic())
            .map_or(rest.len() - number, |(i, _)| i)
            .min(2);
        self.pos += number + unit;
    }

    /// The tokens of text that holds only math (`\boldmath $\omega$`): the
    /// math, bold for `\boldmath`, spanning the whole command.
    fn text_math(&self, content: &str, start: usize) -> Result<Option<Vec<Token>>, LexError> {
        let mut rest = content.trim();
        let mut bold = false;
        while let Some(r) = rest.strip_prefix("\\boldmath") {
            bold = true;
            rest = r.trim_start();
        }
        let Some(inner) = rest
            .strip_prefix('$')
            .and_then(|r| r.strip_suffix('$'))
            .filter(|i| !i.contains('$') && !i.trim().is_empty())
        else {
            return Ok(None);
        };
        if self.nesting >= MAX_TEXT_NESTING {
            return Err((start, ErrorKind::TooDeep(MAX_TEXT_NESTING)));
        }
        let inner_toks = Lexer {
            src: inner,
            pos: 0,
            words: self.words,
            nesting: self.nesting + 1,
        }
        .run()
        .map_err(|(_, kind)| (start, kind))?;
        let end = self.pos;
        let at = |tok| Token { tok, start, end };
        let mut out = Vec::new();
        if bold {
            out.push(at(Tok::Command("boldsymbol".into())));
            out.push(at(Tok::LBrace));
        }
        out.extend(inner_toks.into_iter().map(|t| at(t.tok)));
        if bold {
            out.push(at(Tok::RBrace));
        }
        Ok(Some(out))
    }

    /// The delimiter after `\left` or `\right`.
    fn delimiter(&mut self, start: usize) -> Result<Delim, LexError> {
        self.skip_whitespace();
        let rest = &self.src[self.pos..];
        let table: &[(&str, Delim)] = &[
            ("(", Delim::Paren),
            (")", Delim::Paren),
            ("[", Delim::Bracket),
            ("]", Delim::Bracket),
            ("\\{", Delim::Brace),
            ("\\}", Delim::Brace),
            ("\\|", Delim::DoubleBar),
            ("|", Delim::Bar),
            (".", Delim::Invisible),
            ("\\lfloor", Delim::Floor),
            ("\\rfloor", Delim::Floor),
            ("\\lVert", Delim::DoubleBar),
            ("\\rVert", Delim::DoubleBar),
            ("\\Vert", Delim::DoubleBar),
            ("\\lvert", Delim::Bar),
            ("\\rvert", Delim::Bar),
            ("\\vert", Delim::Bar),
        ];
        for (text, d) in table {
            if rest.starts_with(text)
                && !rest[text.len()..].starts_with(|c: char| {
                    text.starts_with("\\") && text.len() > 2 && c.is_ascii_alphabetic()
                })
            {
                self.pos += text.len();
                return Ok(*d);
            }
        }
        let what = self.src[start..self.pos].trim_end().to_string();
        Err((start, ErrorKind::MissingOperand(what)))
    }

    /// The content of the `{…}` after a command, braces balanced.
    fn raw_argument(&mut self, start: usize) -> Result<String, LexError> {
        self.skip_whitespace();
        if self.peek() != Some('{') {
            let what = self.src[start..self.pos].trim_end().to_string();
            return Err((start, ErrorKind::MissingOperand(what)));
        }
        self.pos += 1;
        let content_start = self.pos;
        let mut depth = 1usize;
        while let Some(c) = self.peek() {
            match c {
                '\\' => {
                    self.pos += 1;
                    if let Some(n) = self.peek() {
                        self.bump(n);
                    }
                    continue;
                }
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        let content = self.src[content_start..self.pos].to_string();
                        self.pos += 1;
                        return Ok(content);
                    }
                }
                _ => {}
            }
            self.bump(c);
        }
        Err((start, ErrorKind::UnbalancedBraces))
    }
}

/// What a command stands for: one token, or several (text holding math).
enum Command {
    One(Tok),
    Many(Vec<Token>),
}

/// Whether `s` is a TeX dimension such as `1em`, `-2pt`, `0.5ex`.
fn is_dimension(s: &str) -> bool {
    let digits = s.trim_start_matches(['-', '+']);
    let unit_at = digits
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(digits.len());
    unit_at > 0
        && ["em", "ex", "pt", "mm", "cm", "in", "mu", "pc", "bp", "sp"]
            .contains(&digits[unit_at..].trim())
}

fn single(c: char) -> Tok {
    match c {
        '{' => Tok::LBrace,
        '}' => Tok::RBrace,
        '(' => Tok::Open(Delim::Paren),
        ')' => Tok::Close(Delim::Paren),
        '[' => Tok::Open(Delim::Bracket),
        ']' => Tok::Close(Delim::Bracket),
        '|' => Tok::Bar,
        '&' => Tok::Amp,
        '~' => Tok::Space,
        '^' => Tok::Sup,
        '_' => Tok::Sub,
        '\'' => Tok::Prime,
        ',' => Tok::Comma,
        '.' => Tok::Period,
        ':' => Tok::Colon,
        '+' => Tok::Plus,
        '-' => Tok::Minus,
        '*' => Tok::Star,
        '/' => Tok::Slash,
        '=' => Tok::Eq,
        '<' => Tok::Lt,
        '>' => Tok::Gt,
        c if c.is_alphabetic() => Tok::Letter(c),
        c => Tok::Other(c),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(s: &str) -> Vec<Tok> {
        lex(s).unwrap().into_iter().map(|t| t.tok).collect()
    }

    #[test]
    fn letter_runs_split_unless_a_function_name() {
        assert_eq!(
            kinds("Exp yy dw"),
            vec![
                Tok::Word("Exp".into()),
                Tok::Letter('y'),
                Tok::Letter('y'),
                Tok::Letter('d'),
                Tok::Letter('w')
            ]
        );
    }

    #[test]
    fn spacing_commands_and_delimiters() {
        assert_eq!(
            kinds("\\left( a\\,b \\right) \\quad \\ ~ \\lfloor \\| 4.27"),
            vec![
                Tok::Left(Delim::Paren),
                Tok::Letter('a'),
                Tok::Letter('b'),
                Tok::Right(Delim::Paren),
                Tok::Quad,
                Tok::Space,
                Tok::Space,
                Tok::Open(Delim::Floor),
                Tok::DoubleBar,
                Tok::Number("4.27".into())
            ]
        );
    }

    #[test]
    fn raw_arguments_and_errors() {
        assert_eq!(
            kinds("\\text{ formula}\\begin{align*}\\tag{3}"),
            vec![Tok::Text(" formula".into()), Tok::Begin("align*".into())]
        );
        assert_eq!(lex("x \\").unwrap_err().1, ErrorKind::LoneBackslash);
        assert_eq!(lex("\\text{a").unwrap_err().1, ErrorKind::UnbalancedBraces);
    }
}
