//! Tokens of LaTeX math.
//!
//! Whitespace, comments, thin spaces (`\,` `\;` `\:` `\!`), sizing commands
//! (`\big`, …), `\displaystyle`, `\hline`, `\label{…}`, `\tag{…}` and
//! `\nonumber` produce no token. Wide spaces do: `\quad`/`\qquad` as
//! [`Tok::Quad`], `\ `/`~`/`\hspace{…}` as [`Tok::Space`], because the
//! documents separate row-vector entries (and statements) with them.

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
    /// A run of letters that is a function name (`Exp`, `sinc`).
    Word(&'static str),
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
    "displaystyle",
    "textstyle",
    "scriptstyle",
    "scriptscriptstyle",
    "limits",
    "nolimits",
    "nonumber",
    "notag",
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
const IGNORED_WITH_ARGUMENT: &[&str] = &["label", "tag", "tag*"];

/// The tokens of `src`.
pub fn lex(src: &str) -> Result<Vec<Token>, LexError> {
    Lexer { src, pos: 0 }.run()
}

struct Lexer<'a> {
    src: &'a str,
    pos: usize,
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
                    Some(t) => t,
                    None => continue,
                },
                '0'..='9' => self.number(),
                c if c.is_ascii_alphabetic() => {
                    let run = self.take_while(|c| c.is_ascii_alphabetic());
                    if let Some(w) = function_word(run) {
                        Tok::Word(w)
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
    fn command(&mut self) -> Result<Option<Tok>, LexError> {
        let start = self.pos;
        self.pos += 1;
        let Some(c) = self.peek() else {
            return Err((start, ErrorKind::LoneBackslash));
        };
        if !c.is_ascii_alphabetic() {
            self.bump(c);
            return Ok(match c {
                ',' | ';' | ':' | '!' | '>' => None,
                ' ' | '\t' | '\n' | '\r' => Some(Tok::Space),
                '\\' => Some(Tok::RowBreak),
                '{' => Some(Tok::Open(Delim::Brace)),
                '}' => Some(Tok::Close(Delim::Brace)),
                '|' => Some(Tok::DoubleBar),
                c => Some(Tok::Command(c.to_string())),
            });
        }
        let mut name = self.take_while(|c| c.is_ascii_alphabetic()).to_string();
        if (name == "tag" || name == "begin" || name == "end") && self.peek() == Some('*') {
            // `\tag*{…}`; `\begin*` does not exist but costs nothing to allow.
            self.pos += 1;
            name.push('*');
        }
        let tok = match name.as_str() {
            "begin" => Tok::Begin(self.raw_argument(start)?),
            "end" => Tok::End(self.raw_argument(start)?),
            "text" | "textrm" | "textit" | "textbf" | "mbox" => {
                Tok::Text(self.raw_argument(start)?)
            }
            "operatorname" => Tok::OperatorName(self.raw_argument(start)?),
            "hspace" => {
                self.raw_argument(start)?;
                Tok::Space
            }
            "quad" | "qquad" => Tok::Quad,
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
            _ => Tok::Command(name),
        };
        Ok(Some(tok))
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
                Tok::Word("Exp"),
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
