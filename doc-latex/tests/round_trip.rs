//! parse(render(tree)) == tree for every statement read from the documents,
//! and only the lines whose printed LaTeX is broken fail to parse.

use crate::common;

use common::{DOC000, DOC001, all_claims, doc000, doc001};
use doc_latex::{Document, parse_statement, render};

fn statements(doc: &Document) -> Vec<doc_latex::ast::Statement> {
    all_claims(doc)
        .into_iter()
        .flat_map(|c| std::iter::once(c.statement).chain(c.notes))
        .filter_map(Result::ok)
        .collect()
}

#[test]
fn every_parsed_statement_renders_to_latex_that_parses_back_to_it() {
    for doc in [doc000(), doc001()] {
        let statements = statements(&doc);
        for s in &statements {
            let latex = render::statement(s);
            let back = parse_statement(&latex)
                .unwrap_or_else(|e| panic!("`{latex}` does not parse back: {e}"));
            assert_eq!(&back, s, "round trip of `{latex}`");
        }
        // Every formula gives a statement at least, but those that fail and
        // the empty `$$(4.25)$$` of document 001.
        let floor = doc.formulas().len() - failures(&doc).len() - 1;
        assert!(statements.len() >= floor, "{} < {floor}", statements.len());
    }
}

/// `(document line, first words of the error)` of every line or side note
/// that does not parse, each because its printed LaTeX is broken.
fn failures(doc: &Document) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for f in doc.formulas() {
        match doc.claims(f) {
            Err(e) => out.push((f.line, e.kind.to_string())),
            Ok(claims) => {
                for c in claims {
                    for r in std::iter::once(&c.statement).chain(&c.notes) {
                        if let Err(e) = r {
                            out.push((c.line, e.kind.to_string()));
                        }
                    }
                }
            }
        }
    }
    out
}

#[test]
fn only_the_lines_printed_broken_fail_document_000() {
    let expected = vec![
        // `\{T = \left(\begin{array}…` runs into the next paragraph (the
        // conversion split the inline formula).
        (65, "`\\{` is not closed by `\\}`".to_string()),
        // `\frac{…}{= \lim … \frac{…}{= \begin{bmatrix}…}}`: a brace short.
        (102, "unbalanced braces".into()),
        // `\sigma = [|n| \mid v|]`: an empty entry after the last bar.
        (123, "empty group".into()),
        // `\lfloor \lfloor δω⌋× R + ⌊t⌋× ⌊δω⌋× R \\`: the outer ⌊ never closes.
        (178, "`\\lfloor` is not closed by `\\rfloor`".into()),
        (180, "`\\lfloor` is not closed by `\\rfloor`".into()),
        // §IV-A: the note `(y = (y_1 … y_4)) \in R^4)` has an extra `)`, and
        // a line of the ∂g/∂ξ chain an extra `}`.
        (239, "unexpected `)`".into()),
        (239, "unbalanced braces".into()),
        // §IV-B: `\log(exp(u) \oplus exp(u) = …` never closes its `(`.
        (243, "`(` is not closed by `)`".into()),
    ];
    assert_eq!(failures(&doc000()), expected);
    assert!(DOC000.lines().nth(101).unwrap().contains("{= \\lim"));
}

#[test]
fn only_the_lines_printed_broken_fail_document_001() {
    // (4.19) opens `-[C_{WB} …` and (4.20) closes it `…]`: one bracket
    // split over two displays.
    let expected = vec![
        (101, "`[` is not closed by `]`".to_string()),
        (103, "unexpected `]`".into()),
    ];
    assert_eq!(failures(&doc001()), expected);
    assert!(DOC001.lines().nth(100).unwrap().contains("-[C_{WB}"));
}
