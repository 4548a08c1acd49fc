//! Macro definitions as written in a document's text: `\newcommand`,
//! `\renewcommand`, `\providecommand`, `\def`, `\let`,
//! `\DeclareMathOperator`, read from the `\` that starts one.

/// A definition as written: name, parameter count, optional default and
/// body, raw.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Definition {
    pub name: String,
    pub params: u8,
    pub default: Option<String>,
    pub body: String,
}

/// The macro definition starting at byte `at` of `src` (at its `\`), and
/// the byte after it.
pub(crate) fn definition(src: &str, at: usize) -> Option<(Definition, usize)> {
    let rest = src.get(at..)?;
    let command = [
        "newcommand",
        "renewcommand",
        "providecommand",
        "DeclareMathOperator",
    ]
    .into_iter()
    .chain(["def", "let"])
    .find(|c| {
        rest[1..].starts_with(c)
            && !rest[1 + c.len()..].starts_with(|x: char| x.is_ascii_alphabetic())
    })?;
    let mut p = Cursor {
        src,
        pos: at + 1 + command.len(),
    };
    p.star();
    let name = p.name()?;
    let d = match command {
        "def" => {
            let params_start = p.pos;
            let open = src[params_start..].find('{')? + params_start;
            let params = src[params_start..open].matches('#').count().min(9) as u8;
            p.pos = open;
            Definition {
                name,
                params,
                default: None,
                body: p.group()?,
            }
        }
        "let" => {
            p.skip_space();
            if src[p.pos..].starts_with('=') {
                p.pos += 1;
            }
            let target = p.name()?;
            Definition {
                name,
                params: 0,
                default: None,
                body: format!("\\{target}"),
            }
        }
        "DeclareMathOperator" => Definition {
            name,
            params: 0,
            default: None,
            body: format!("\\operatorname{{{}}}", p.group()?),
        },
        _ => {
            let params = match p.bracket() {
                Some(n) => n.trim().parse::<u8>().ok().filter(|n| *n <= 9)?,
                None => 0,
            };
            let default = p.bracket();
            Definition {
                name,
                params,
                default,
                body: p.group()?,
            }
        }
    };
    Some((d, p.pos))
}

/// A cursor over the text of a definition.
struct Cursor<'a> {
    src: &'a str,
    pos: usize,
}

impl Cursor<'_> {
    fn skip_space(&mut self) {
        let rest = &self.src[self.pos..];
        self.pos += rest.len() - rest.trim_start().len();
    }

    fn star(&mut self) {
        if self.src[self.pos..].starts_with('*') {
            self.pos += 1;
        }
    }

    /// `\name` or `{\name}`: the name without backslash.
    fn name(&mut self) -> Option<String> {
        self.skip_space();
        let braced = self.src[self.pos..].starts_with('{');
        if braced {
            self.pos += 1;
            self.skip_space();
        }
        let rest = self.src[self.pos..].strip_prefix('\\')?;
        let len = match rest.find(|c: char| !c.is_ascii_alphabetic()) {
            Some(0) => rest.chars().next()?.len_utf8(),
            Some(n) => n,
            None => rest.len(),
        };
        if len == 0 {
            return None;
        }
        let name = rest[..len].to_string();
        self.pos += 1 + len;
        if braced {
            self.skip_space();
            self.src[self.pos..].strip_prefix('}')?;
            self.pos += 1;
        }
        Some(name)
    }

    /// An optional `[…]`.
    fn bracket(&mut self) -> Option<String> {
        self.skip_space();
        let rest = self.src[self.pos..].strip_prefix('[')?;
        let close = rest.find(']')?;
        let inner = rest[..close].to_string();
        self.pos += close + 2;
        Some(inner)
    }

    /// A braced group, braces balanced (escaped ones skipped): its content.
    fn group(&mut self) -> Option<String> {
        self.skip_space();
        let bytes = self.src.as_bytes();
        if bytes.get(self.pos) != Some(&b'{') {
            return None;
        }
        let start = self.pos + 1;
        let mut depth = 0usize;
        let mut i = self.pos;
        while i < bytes.len() {
            match bytes[i] {
                b'\\' => i += 1,
                b'{' => depth += 1,
                b'}' => {
                    depth -= 1;
                    if depth == 0 {
                        self.pos = i + 1;
                        return Some(self.src[start..i].to_string());
                    }
                }
                _ => {}
            }
            i += 1;
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn definitions_in_every_form() {
        let d = |s: &str| definition(s, 0).unwrap().0;
        assert_eq!(
            d("\\newcommand{\\deriv}[2]{\\frac{\\partial#1}{\\partial#2}}"),
            Definition {
                name: "deriv".into(),
                params: 2,
                default: None,
                body: "\\frac{\\partial#1}{\\partial#2}".into()
            }
        );
        assert_eq!(d("\\newcommand\\norm[1]{\\lVert #1 \\rVert}").params, 1);
        assert_eq!(
            d("\\renewcommand*{\\x}[2][a]{#1#2}").default,
            Some("a".into())
        );
        assert_eq!(d("\\def\\f#1#2{#2#1}").params, 2);
        assert_eq!(d("\\let\\x=\\y").body, "\\y");
        assert_eq!(
            d("\\DeclareMathOperator*{\\Ad}{Ad}").body,
            "\\operatorname{Ad}"
        );
        assert!(definition("\\newcommandx", 0).is_none());
        assert!(definition("\\newcommand{\\x}[2]", 0).is_none());
    }
}
