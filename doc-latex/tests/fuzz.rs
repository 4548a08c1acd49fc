//! Hostile input: mutated real formulas (of the specification documents
//! and of the corpus's LaTeX sources, their macro definitions included) and
//! random strings never panic, every error displays as one line, whatever
//! parses round-trips, nesting beyond `MAX_DEPTH` is an error rather than a
//! stack overflow, and macros that expand without end are an error rather
//! than a hang.

use crate::common;

use common::{DOC000, DOC001};
use doc_latex::{
    Document, ErrorKind, Locator, MAX_DEPTH, Options, ParseError, Syntax, parse_expr,
    parse_expr_with, parse_statement, render,
};
use proptest::prelude::*;

/// The corpus's LaTeX sources (`documents/corpus/`).
const CORPUS: [&str; 3] = [
    include_str!("../../documents/corpus/kindr/cheatsheet_kindr1.tex"),
    include_str!("../../documents/corpus/gtsam/math.tex"),
    include_str!("../../documents/corpus/gtsam/LieGroups.tex"),
];

fn latex(text: &str) -> Result<Document, ParseError> {
    Document::parse_with(
        text,
        Options {
            syntax: Syntax::Latex,
            ..Default::default()
        },
    )
}

/// The LaTeX between the delimiters of every formula of both documents and
/// of the corpus.
fn sources() -> Vec<String> {
    let markdown = [DOC000, DOC001]
        .iter()
        .flat_map(|d| Document::parse(d).unwrap().formulas().to_vec());
    let corpus = CORPUS
        .iter()
        .flat_map(|d| latex(d).unwrap().formulas().to_vec());
    markdown.chain(corpus).map(|f| f.source).collect()
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
    "\\newcommand{\\a}[1]{#1\\a}",
    "\\def\\b{\\b}",
    "#1",
    "#2",
    "\\mathop{\\lim}\\limits_",
    "\\buildrel",
    "\\over",
    "{\\rm",
    "\\left\\{",
    "\\right.",
    "\\label{",
    "\\[",
    "\\]",
    "\\f$",
    "\\begin{align}",
    "\\end{align}",
    "%",
    "_{+}",
    "^\\odot",
    "\\mathbf{Rp}",
    "\\bm{\\mathcal{J}}",
    "\\Delta",
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

/// Reads a whole LaTeX document (its macros, delimiters and comments) and
/// every claim of every formula: errors are one line, what parses
/// round-trips, and the vocabulary reads expressions too.
fn exercise_latex_document(text: &str) {
    match latex(text) {
        Err(e) => assert_one_line(&e),
        Ok(doc) => {
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
                if let Err(e) = parse_expr_with(&f.source, doc.vocabulary()) {
                    assert_one_line(&e);
                }
            }
            for anchor in ["\\deriv", "=", "\\frac{", "x"] {
                if let Err(e) = doc.locate(anchor) {
                    assert!(!e.to_string().contains('\n'), "{e}");
                }
            }
        }
    }
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

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// A window of a corpus document, its macro definitions kept first,
    /// mutated anywhere (definitions included).
    #[test]
    fn mutated_corpus_documents(
        which in 0..CORPUS.len(),
        start in any::<prop::sample::Index>(),
        mutations in prop::collection::vec(mutation(), 1..6),
    ) {
        let text = CORPUS[which];
        let lines: Vec<&str> = text.lines().collect();
        let macros: Vec<&str> = lines
            .iter()
            .copied()
            .filter(|l| l.contains("newcommand") || l.starts_with("\\def"))
            .collect();
        let at = start.index(lines.len());
        let window = lines[at..(at + 60).min(lines.len())].join("\n");
        let document = format!("{}\n{window}\n", macros.join("\n"));
        exercise_latex_document(&mutate(&document, &mutations));
    }
}

/// Macros that expand without end, or to an enormous text, are an error
/// at once (never a hang or an exhausted memory).
#[test]
fn runaway_macros_are_bounded() {
    let cases = [
        "\\newcommand{\\a}{\\a\\a}\n$$x = \\a$$\n",
        "\\def\\a{x\\a}\n\\[ y = \\a \\]\n",
        "\\newcommand{\\a}[1]{#1#1#1#1}\\newcommand{\\b}{\\a{\\a{\\a{\\a{\\a{\\a{\\a{\\a{\\a{\\a{x}}}}}}}}}}}\n$$y = \\b$$\n",
        "\\newcommand{\\a}[2]{#2\\a{#1}{#2}}\n$$y = \\a{1}{2}$$\n",
    ];
    for text in cases {
        let e = match latex(text) {
            Err(e) => e,
            Ok(doc) => match doc.claims(&doc.formulas()[0]) {
                Err(e) => e,
                Ok(claims) => claims[0].statement.clone().unwrap_err(),
            },
        };
        assert!(
            matches!(e.kind, ErrorKind::MacroExpansion(_)),
            "{text}: {e}"
        );
        assert_one_line(&e);
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

/// Found by `mutated_document_formulas` (inserting `\frac` before `4\times
/// 4`): an operator read as a one-token argument of `\frac` rendered as
/// `\frac{4}{\times}`, which does not parse. An operator is no operand of
/// a fraction or a root, braced or not.
#[test]
fn an_operator_is_no_operand_of_a_fraction_or_a_root() {
    for latex in [
        "\\frac4\\times 4",
        "\\frac{4}{\\times} 4",
        "\\sqrt\\times 4",
    ] {
        assert!(parse_statement(latex).is_err(), "{latex}");
        exercise(latex);
    }
    // A script may still name one, a pre-script too (found by
    // `random_commands`: `{}_x^\odot x` rendered its pre-superscript as
    // `^{{\odot}}`, which did not parse).
    assert!(parse_statement("a = x^\\times").is_ok());
    assert!(parse_statement("{}_x^\\odot x").is_ok());
    exercise("{}_x^\\odot x");
}
