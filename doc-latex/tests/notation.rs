//! The notation the crate covers, one small input each (beyond the
//! documents' own formulas), and the errors malformed LaTeX gets.

use doc_latex::ast::{DerivativeKind, Expr, Font, Head, MulOp, PostfixOp, Rel, Statement, Symbol};
use doc_latex::{Document, ErrorKind, Locator, LookupError, parse_expr, parse_statement};

fn read(latex: &str) -> Expr {
    parse_expr(latex).unwrap_or_else(|e| panic!("{latex}: {e}"))
}

/// The canonical LaTeX of `latex`.
fn canonical(latex: &str) -> String {
    read(latex).to_string()
}

fn error(latex: &str) -> ErrorKind {
    match parse_statement(latex) {
        Err(e) => e.kind,
        Ok(s) => panic!("{latex} parsed as {s}"),
    }
}

/// `k!` of a whole number is its value (a series' coefficients); of
/// anything else it is an error at the `!`.
#[test]
fn factorials_of_whole_numbers_are_their_values() {
    assert_eq!(canonical("\\frac{1}{3!}"), canonical("\\frac{1}{6}"));
    assert_eq!(canonical("\\frac{x^2}{2!}"), canonical("\\frac{x^2}{2}"));
    assert_eq!(canonical("0! + 1!"), canonical("1 + 1"));
    assert_eq!(canonical("20!"), "2432902008176640000");
    for bad in ["21!", "0.5!", "x!"] {
        assert!(parse_statement(bad).is_err(), "{bad}");
    }
}

#[test]
fn spellings_of_one_thing_read_the_same() {
    let same = [
        (
            &["\\frac{a}{b}", "\\dfrac{a}{b}", "\\tfrac ab"][..],
            "\\frac{a}{b}",
        ),
        (&["x^T", "x^{T}", "x^\\top", "{x}^{T}"], "x^{T}"),
        (
            &["\\omega^\\wedge", "\\omega^{\\wedge}", "(\\omega)^\\wedge"],
            "\\omega^{\\wedge}",
        ),
        (
            &[
                "\\lfloor v \\rfloor_\\times",
                "[v]_{\\times}",
                "\\left\\lfloor v \\right\\rfloor_{\\times}",
            ],
            "\\lfloor v \\rfloor_{\\times}",
        ),
        (
            &["\\mathbf{x}", "\\boldsymbol{x}", "\\bm x"],
            "\\boldsymbol{x}",
        ),
        (
            &["\\hat{\\mathbf{t}}", "\\mathbf{\\hat{t}}"],
            "\\hat{\\boldsymbol{t}}",
        ),
        (
            &["\\text{Exp}(x)", "Exp(x)", "\\operatorname{Exp}(x)"],
            "\\operatorname{Exp}(x)",
        ),
        (&["\\exp(x)", "exp(x)"], "\\exp(x)"),
        // Without parentheses the function takes one factor, and says so.
        (&["\\exp x", "\\exp{x}", "exp x"], "\\exp {x}"),
        (&["a\\,b\\;c\\!d\\:e", "a b c d e"], "a b c d e"),
        (
            &[
                "(a + b) c",
                "\\left(a + b\\right) c",
                "\\bigl(a + b\\bigr) c",
            ],
            "\\left(a + b\\right) c",
        ),
        (
            &[
                "\\lfloor . \\rfloor_\\times",
                "\\lfloor \\cdot \\rfloor_\\times",
            ],
            "\\lfloor {\\cdot} \\rfloor_{\\times}",
        ),
    ];
    for (spellings, expected) in same {
        for s in spellings {
            assert_eq!(canonical(s), expected, "{s}");
        }
    }
}

#[test]
fn block_matrices_in_every_printed_form() {
    let forms = [
        "\\begin{bmatrix} R & t \\\\ 0 & 1 \\end{bmatrix}",
        "\\begin{pmatrix} R & t \\\\ 0 & 1 \\\\ \\end{pmatrix}",
        "\\left(\\begin{array}{c|c} R & t \\\\ \\hline 0 & 1 \\end{array}\\right)",
        "\\left(\\frac{R \\mid t}{0 \\mid 1}\\right)",
        "\\begin{bmatrix} R \\ t \\\\ 0 \\quad 1 \\end{bmatrix}",
        "\\begin{bmatrix} R | t \\\\ 0 \\mid 1 \\end{bmatrix}",
    ];
    let expected = read(forms[0]);
    assert_eq!(expected.as_matrix().unwrap().shape(), Some((2, 2)));
    for f in forms {
        assert_eq!(read(f), expected, "{f}");
    }
    // A row vector from a bracket group, and a ragged matrix kept as printed.
    assert_eq!(read("[K \\ 0]").as_matrix().unwrap().shape(), Some((1, 2)));
    assert_eq!(read("[a, b]"), read("(a, b)"));
    assert!(matches!(read("(a, b)"), Expr::Tuple(t) if t.len() == 2));
    let ragged = read("\\begin{bmatrix} a & b \\\\ c \\end{bmatrix}");
    let m = ragged.as_matrix().unwrap();
    assert_eq!((m.shape(), m.rows[1].len()), (None, 1));
    // A shape annotation on a group.
    let Expr::Shaped {
        rows: 3, cols: 6, ..
    } = read("[K \\ 0]_{3 \\times 6}")
    else {
        panic!()
    };
}

#[test]
fn norms_powers_and_scripts() {
    let Expr::Power { base, exponent } = read("|y|^{\\frac{3}{2}}") else {
        panic!()
    };
    assert!(matches!(*base, Expr::Norm { double: false, .. }));
    assert_eq!(exponent.to_string(), "\\frac{3}{2}");
    assert!(
        matches!(read("\\|w\\|^3"), Expr::Power { base, .. } if matches!(*base, Expr::Norm { double: true, .. }))
    );
    // A superscript on a symbol is part of it, unless it reads as an exponent.
    let s = read("R_w^c");
    assert_eq!(
        s.as_symbol()
            .unwrap()
            .sup
            .as_deref()
            .map(|e| e.to_string())
            .as_deref(),
        Some("c")
    );
    assert!(matches!(read("q^{-1}"), Expr::Power { .. }));
    let i3 = read("I_{3\\times3}");
    assert_eq!(
        i3.as_symbol()
            .unwrap()
            .sub
            .as_ref()
            .unwrap()
            .shape_annotation(),
        Some((3, 3))
    );
    // T_w^{cT}: the transpose stripped from the index.
    let Expr::Postfix {
        base,
        op: PostfixOp::Transpose,
    } = read("T_w^{cT}")
    else {
        panic!()
    };
    assert_eq!(base.to_string(), "T_{w}^{c}");
    // LaTeX takes one token for a script: x^12 is x^1 2.
    assert_eq!(canonical("x^12"), "x^{1} 2");
    assert_eq!(canonical("\\frac12"), "\\frac{1}{2}");
    // Pre-scripts, primes.
    let p = read("{}_W\\mathbf{P}_L'");
    let p: &Symbol = p.as_symbol().unwrap();
    assert_eq!(
        (
            p.font,
            p.primes,
            p.pre_sub.as_deref().map(|e| e.to_string())
        ),
        (Font::Bold, 1, Some("W".into()))
    );
}

#[test]
fn functions() {
    let name = |latex: &str| match read(latex) {
        Expr::Apply {
            head: Head::Function(f),
            ..
        } => (f.name, f.power.map(|p| p.to_string())),
        other => panic!("{latex}: {other}"),
    };
    for (latex, n) in [
        ("\\sin x", "sin"),
        ("cos(x)", "cos"),
        ("Log(R)", "Log"),
        ("log(q)", "log"),
        ("sinc(x)", "sinc"),
        ("\\arccos(x)", "arccos"),
        ("\\det R", "det"),
    ] {
        assert_eq!(name(latex), (n.to_string(), None));
    }
    assert_eq!(name("cos^{-1}(x)"), ("cos".into(), Some("-1".into())));
    // Arguments: a comma list; a paren-less argument is one factor.
    assert!(matches!(read("E(\\xi, \\omega)"), Expr::Apply { args, .. } if args.len() == 2));
    assert_eq!(
        canonical("\\sin\\theta(\\hat{\\omega})^\\wedge"),
        "\\sin {\\theta} \\hat{\\omega}^{\\wedge}"
    );
    // A symbol before `(` is an application; before `\left(` a product.
    assert!(matches!(
        read("J_l(\\omega)"),
        Expr::Apply {
            head: Head::Symbol(_),
            ..
        }
    ));
    assert!(matches!(
        read("n^T \\left(a + b\\right)"),
        Expr::Product { .. }
    ));
}

#[test]
fn operators_and_relations() {
    let Expr::Product { rest, .. } = read("a \\cdot b \\times c \\otimes d \\oplus e * f g") else {
        panic!()
    };
    let ops: Vec<MulOp> = rest.iter().map(|(op, _)| *op).collect();
    assert_eq!(
        ops,
        [
            MulOp::Cdot,
            MulOp::Times,
            MulOp::Otimes,
            MulOp::Oplus,
            MulOp::Star,
            MulOp::Implicit
        ]
    );
    let s = parse_statement("\\Rightarrow C \\leftarrow C Exp(x) \\approx C \\doteq D \\in SO(3)")
        .unwrap();
    assert!(s.implied);
    let rels: Vec<Rel> = s.steps.iter().map(|(r, _)| *r).collect();
    assert_eq!(rels, [Rel::LeftArrow, Rel::Approx, Rel::Doteq, Rel::In]);
    // The value the chain arrives at skips the membership.
    assert_eq!(s.rhs().unwrap().to_string(), "D");
    let cont: Statement = parse_statement("= x").unwrap();
    assert_eq!(cont.head, None);
}

#[test]
fn derivatives_and_increments() {
    let Expr::Product { first, rest } =
        read("\\frac{\\partial e}{\\partial u} \\frac{\\partial u}{\\partial \\xi}")
    else {
        panic!()
    };
    assert!(matches!(
        *first,
        Expr::Derivative {
            kind: DerivativeKind::Partial,
            ..
        }
    ));
    assert!(matches!(rest[0].1, Expr::Derivative { .. }));
    assert!(matches!(
        read("\\frac{d \\|w\\|}{d w}"),
        Expr::Derivative {
            kind: DerivativeKind::Total,
            ..
        }
    ));
    assert!(matches!(
        read("\\frac{\\mathrm{d} f}{\\mathrm{d} x}"),
        Expr::Derivative {
            kind: DerivativeKind::Total,
            ..
        }
    ));
    // d alone over a denominator is a plain fraction; so is ∂x over x.
    assert!(matches!(read("\\frac{d}{x}"), Expr::Fraction { .. }));
    assert!(matches!(
        read("\\frac{\\partial x}{y}"),
        Expr::Fraction { .. }
    ));
    // \delta before a symbol is an increment; braced, it is not.
    assert_eq!(
        read("\\delta\\xi_j^\\wedge").to_string(),
        "\\delta \\xi_{j}^{\\wedge}"
    );
    assert!(matches!(read("{\\delta} \\xi"), Expr::Product { .. }));
    assert!(matches!(
        read("\\lim_{\\delta x \\to 0} \\frac{f}{\\delta x}"),
        Expr::Limit { .. }
    ));
    assert_eq!(canonical("\\sqrt[3]{x}"), "\\sqrt[3]{x}");
}

#[test]
fn malformed_latex_is_an_error() {
    assert_eq!(error("\\frac{a}{b"), ErrorKind::UnbalancedBraces);
    assert_eq!(error("a}"), ErrorKind::UnbalancedBraces);
    assert_eq!(
        error("\\begin{foo} a \\end{foo}"),
        ErrorKind::UnknownEnvironment("foo".into())
    );
    assert_eq!(
        error("\\begin{bmatrix} a"),
        ErrorKind::UnclosedEnvironment("bmatrix".into())
    );
    assert_eq!(error("a & b"), ErrorKind::StrayAmpersand);
    assert_eq!(error("a \\\\ b"), ErrorKind::StrayRowBreak);
    assert_eq!(error("\\foo x"), ErrorKind::UnknownCommand("foo".into()));
    assert_eq!(error("x^a^b"), ErrorKind::DoubleScript("super"));
    assert_eq!(
        error("(a"),
        ErrorKind::Unclosed {
            open: "(".into(),
            expected: ")".into()
        }
    );
    assert_eq!(error("\\lfloor x \\rfloor_{y}"), ErrorKind::FloorSubscript);
    assert_eq!(
        error("(= a)"),
        ErrorKind::RelationWithoutLeftSide("=".into())
    );
    assert_eq!(error("\\hat{a + b}"), ErrorKind::NotASymbol("hat".into()));
    assert_eq!(error("x \\"), ErrorKind::LoneBackslash);
    assert_eq!(
        error("\\begin{aligned} a \\end{aligned} + b"),
        ErrorKind::NestedAlignment("aligned".into())
    );
    let e = parse_statement("\\frac{a}\n{b").unwrap_err();
    // The `{` never closed is the second one, on line 2.
    assert_eq!((e.line, e.offset), (2, 9));
    assert_eq!(
        e.to_string(),
        "formula, line 2, byte 9: unbalanced braces at `{b`"
    );
}

#[test]
fn documents_lines_labels_and_lookups() {
    let text = "Intro $x = 1$.\n\n\
        $$\\begin{align} a &= b \\\\ &= c \\end{align}$$\n(2)\n\n\
        $$d = e \\\\ = f \\tag{3}$$\n\n\
        A. Derivation of g\n\n\
        $$g = h \\qquad (4.1)$$\n\n$$= k \\quad (4.2)$$\n";
    let doc = Document::parse(text).unwrap();
    assert_eq!(doc.formulas().len(), 5);
    let two = doc.find(Locator::parse("(2)")).unwrap();
    assert_eq!((two.line, two.label.as_deref()), (3, Some("2")));
    let claims = doc.claims(two).unwrap();
    assert_eq!(claims.len(), 2);
    assert!(claims[1].continued);
    assert_eq!(claims[1].lhs.as_ref().unwrap().to_string(), "a");
    assert_eq!(claims[1].rhs().unwrap().to_string(), "c");
    assert_eq!(
        doc.claims(doc.find(Locator::Label("3")).unwrap())
            .unwrap()
            .len(),
        2
    );
    // (4.2) continues (4.1) across displays.
    let c = doc.chain(Locator::Label("4.1")).unwrap();
    assert_eq!(c.len(), 2);
    assert_eq!(c[1].lhs.as_ref().unwrap().to_string(), "g");
    // An anchor in the prose finds the display after it; whitespace does not matter.
    assert_eq!(
        doc.find(Locator::Anchor("Derivation  of g"))
            .unwrap()
            .label
            .as_deref(),
        Some("4.1")
    );
    assert_eq!(doc.claim("d=e").unwrap().line, 6);
    assert!(matches!(
        doc.find(Locator::Label("9")),
        Err(LookupError::NoLabel(_))
    ));
    assert!(matches!(
        doc.find(Locator::Anchor("=")),
        Err(LookupError::AmbiguousAnchor { count: 5, .. })
    ));
    assert!(matches!(
        doc.find(Locator::Anchor("nowhere")),
        Err(LookupError::NoAnchor(_))
    ));
    // A label printed as a display of its own after a labelled display
    // stays an empty formula.
    let doc = Document::parse("$$a = b \\quad (1)$$\n\n$$(2)$$").unwrap();
    assert!(
        doc.claims(doc.find(Locator::Label("2")).unwrap())
            .unwrap()
            .is_empty()
    );
    assert!(matches!(
        doc.chain(Locator::Label("2")),
        Err(LookupError::Empty(3))
    ));
}
