//! Hostile input: mutated real formulas and random strings never panic,
//! every error displays as one line, whatever parses round-trips, and
//! nesting beyond `MAX_DEPTH` is an error rather than a stack overflow.

mod common;

use common::{DOC000, DOC001};
use doc_latex::{
    Document, ErrorKind, Locator, MAX_DEPTH, ParseError, parse_expr, parse_statement, render,
};
use proptest::prelude::*;

/// The LaTeX between the delimiters of every formula of both documents.
fn sources() -> Vec<String> {
    [DOC000, DOC001]
        .iter()
        .flat_map(|d| Document::parse(d).unwrap().formulas().to_vec())
        .map(|f| f.source)
        .collect()
}

/// Pieces a mutation inserts: the syntax most likely to unbalance a parse.
const PIECES: &[&str] = &[
    "{",
    "}",
    "(",
    ")",
    "[",
    "]",
    "\\left(",
    "\\right)",
    "|",
    "\\|",
    "&",
    "\\\\",
    "^",
    "_",
    "'",
    "\\frac",
    "\\partial",
    "\\begin{bmatrix}",
    "\\end{bmatrix}",
    "\\begin{cases}",
    "\\end{split}",
    "\\lfloor",
    "\\rfloor_\\times",
    "\\mid",
    "\\quad",
    "=",
    "-",
    ",",
    ".",
    "\\",
    "$",
    "$$",
    "\\lim_",
    "{}_",
    "\\delta",
    "\\mathbf",
    "\\hat",
    "\\sqrt[",
    "\\text{",
    "\\foo",
    "ω",
    "\n\n",
];

#[derive(Debug, Clone)]
enum Mutation {
    Delete { at: usize, len: usize },
    Insert { at: usize, piece: usize },
    Duplicate { at: usize, len: usize },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), 1usize..12).prop_map(|(at, len)| Mutation::Delete { at, len }),
        (any::<usize>(), 0..PIECES.len()).prop_map(|(at, piece)| Mutation::Insert { at, piece }),
        (any::<usize>(), 1usize..40).prop_map(|(at, len)| Mutation::Duplicate { at, len }),
    ]
}

/// `s` with the mutations applied (positions taken modulo the length, in
/// characters, so the result stays UTF-8).
fn mutate(s: &str, mutations: &[Mutation]) -> String {
    let mut chars: Vec<char> = s.chars().collect();
    for m in mutations {
        let n = chars.len().max(1);
        match *m {
            Mutation::Delete { at, len } => {
                let at = at % n;
                let end = (at + len).min(chars.len());
                if at < end {
                    chars.drain(at..end);
                }
            }
            Mutation::Insert { at, piece } => {
                let at = at % (chars.len() + 1);
                chars.splice(at..at, PIECES[piece].chars());
            }
            Mutation::Duplicate { at, len } => {
                let at = at % n;
                let end = (at + len).min(chars.len());
                let copy: Vec<char> = chars[at.min(end)..end].to_vec();
                chars.splice(end..end, copy);
            }
        }
    }
    chars.into_iter().collect()
}

fn assert_one_line(e: &ParseError) {
    let shown = e.to_string();
    assert!(!shown.contains('\n') && !shown.contains('\r'), "{shown:?}");
}

/// Reads `latex` every way the crate offers; checks errors and round trips.
fn exercise(latex: &str) {
    match parse_statement(latex) {
        Ok(s) => {
            let back = render::statement(&s);
            assert_eq!(
                parse_statement(&back).as_ref(),
                Ok(&s),
                "round trip of {back:?}"
            );
        }
        Err(e) => assert_one_line(&e),
    }
    if let Err(e) = parse_expr(latex) {
        assert_one_line(&e);
    }
    for text in [
        format!("$${latex}$$\n"),
        format!("x ${latex}$ y"),
        latex.to_string(),
    ] {
        match Document::parse(&text) {
            Err(e) => assert_one_line(&e),
            Ok(doc) => {
                for locator in ["(1)", "=", "x", "\\frac{", "(4.25)"] {
                    let locator = Locator::parse(locator);
                    let errors = [doc.chain(locator).err(), doc.find(locator).err()];
                    for e in errors.into_iter().flatten() {
                        assert!(!e.to_string().contains('\n'), "{e}");
                    }
                }
                if let Err(e) = doc.claim("=") {
                    assert!(!e.to_string().contains('\n'), "{e}");
                }
                for f in doc.formulas() {
                    match doc.claims(f) {
                        Err(e) => assert_one_line(&e),
                        Ok(claims) => {
                            for c in claims {
                                for r in std::iter::once(&c.statement).chain(&c.notes) {
                                    match r {
                                        Err(e) => assert_one_line(e),
                                        Ok(s) => {
                                            let back = render::statement(s);
                                            assert_eq!(parse_statement(&back).as_ref(), Ok(s));
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn mutated_document_formulas(
        index in any::<prop::sample::Index>(),
        mutations in prop::collection::vec(mutation(), 1..6),
    ) {
        let sources = sources();
        let original = index.get(&sources);
        exercise(&mutate(original, &mutations));
    }

    #[test]
    fn latex_like_random_strings(s in r"[\\{}()\[\]^_&|'a-zT0-9 +\-=.,$~\n]{0,200}") {
        exercise(&s);
    }

    #[test]
    fn random_commands(words in prop::collection::vec(prop::sample::select(PIECES.to_vec()), 0..60)) {
        exercise(&words.join(" x "));
    }

    #[test]
    fn any_unicode(s in r"\PC{0,120}") {
        exercise(&s);
    }
}

/// Deeply nested inputs of every recursive shape of the grammar.
fn hostile() -> Vec<String> {
    let nest = |open: &str, close: &str| {
        let deep = 10_000;
        format!("{}x{}", open.repeat(deep), close.repeat(deep))
    };
    vec![
        nest("{", "}"),
        nest("(", ")"),
        nest("[", "]_\\times"),
        nest("\\frac{", "}{1}"),
        nest("\\frac", "1"),
        nest("-", ""),
        nest("\\partial ", ""),
        nest("\\lim_{", "} y"),
        nest("x^{", "}"),
        nest("x_{", "}"),
        nest("{}_{", "}x"),
        nest("\\sin ", ""),
        nest("\\sin(", ")"),
        nest("f(", ")"),
        nest("\\hat ", ""),
        nest("\\hat{", "}"),
        nest("\\mathbf{", "}"),
        nest("\\sqrt ", ""),
        nest("\\sqrt[", "]{2}"),
        nest("|", "|"),
        nest("\\left|", "\\right|"),
        nest("\\lfloor ", "\\rfloor_\\times"),
        nest("\\begin{bmatrix}", "\\end{bmatrix}"),
        nest("\\begin{cases}", "\\end{cases}"),
    ]
}

#[test]
fn nesting_beyond_the_bound_is_an_error_not_a_stack_overflow() {
    // Half the stack a Rust thread gets by default: the parser needs at
    // most 768 KiB at the bound in a debug build.
    let run = std::thread::Builder::new()
        .stack_size(1024 * 1024)
        .spawn(|| {
            for latex in hostile() {
                let e = parse_statement(&latex).unwrap_err();
                assert_eq!(e.kind, ErrorKind::TooDeep(MAX_DEPTH), "{}", &latex[..20]);
                assert_one_line(&e);
                let doc = Document::parse(&format!("$${latex}$$")).unwrap();
                let claims = doc.claims(&doc.formulas()[0]).unwrap();
                assert!(claims[0].statement.is_err());
            }
        });
    run.unwrap().join().unwrap();
}

#[test]
fn nesting_below_the_bound_still_parses() {
    // Each brace costs three steps (group, term, factor).
    let latex = format!(
        "{}x{}",
        "{".repeat(MAX_DEPTH / 4),
        "}".repeat(MAX_DEPTH / 4)
    );
    let s = parse_statement(&latex).unwrap();
    assert_eq!(render::statement(&s), "x");
}
