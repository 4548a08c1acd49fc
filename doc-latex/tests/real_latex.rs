//! LaTeX as textbooks, papers and projects' notes write it, beyond the two
//! specification documents: each notation class read, rendered back and
//! read again to the same tree.

use doc_latex::ast::{Expr, Font, Head, PostfixOp, Rel, Symbol};
use doc_latex::{
    Document, Found, Locator, LookupError, MathKind, Options, Syntax, Vocabulary, parse_expr,
    parse_expr_with, parse_statement, render,
};

fn read(latex: &str) -> Expr {
    let e = parse_expr(latex).unwrap_or_else(|err| panic!("{latex}: {err}"));
    let back = e.to_string();
    assert_eq!(
        parse_expr(&back).as_ref(),
        Ok(&e),
        "{latex} renders as {back}, which reads differently"
    );
    e
}

fn same(a: &str, b: &str) {
    assert_eq!(read(a), read(b), "{a} and {b}");
}

#[test]
fn limits_fonts_and_plain_tex() {
    same(
        "\\mathop{\\lim}\\limits_{\\delta \\to 0} \\frac{f}{\\delta}",
        "\\lim_{\\delta \\to 0} \\frac{f}{\\delta}",
    );
    // Bold over several letters is their product; over a digit a symbol.
    same("\\mathbf{Rp}", "\\mathbf{R}\\mathbf{p}");
    let zero = read("\\mathbf{0}");
    assert_eq!(zero.as_symbol().map(|s| s.font), Some(Font::Bold));
    let one = read("\\mathds{1}");
    assert_eq!(one.as_symbol().map(|s| s.font), Some(Font::Blackboard));
    assert_eq!(
        read("\\bm{\\mathcal{J}}").as_symbol().map(|s| s.font),
        Some(Font::BoldCalligraphic)
    );
    same("\\boldsymbol{\\mathcal{J}}", "\\bm{\\mathcal J}");
    same("{\\rm d}x", "{\\mathrm{d}} x");
    same("a \\buildrel \\rm def \\over = b", "a = b");
    same("a \\stackrel{\\Delta}{=} b", "a = b");
    same("{a \\over b}", "\\frac{a}{b}");
    same("\\mbox{\\boldmath $\\omega$}", "\\boldsymbol{\\omega}");
    assert_eq!(
        parse_statement("x \\triangleq y").unwrap().steps[0].0,
        Rel::Define
    );
    assert_eq!(parse_statement("x := y").unwrap().steps[0].0, Rel::Define);
}

#[test]
fn functions_of_every_kind() {
    let function = |latex: &str| match read(latex) {
        Expr::Apply {
            head: Head::Function(f),
            args,
            ..
        } => (f.name, f.sub.map(|s| s.to_string()), args.len()),
        other => panic!("{latex}: {other}"),
    };
    assert_eq!(function("\\cot\\theta"), ("cot".into(), None, 1));
    assert_eq!(function("\\mathrm{Ad}(T)"), ("Ad".into(), None, 1));
    assert_eq!(function("\\mathrm{Foo}(T)"), ("Foo".into(), None, 1));
    assert_eq!(function("\\log_2 x"), ("log".into(), Some("2".into()), 1));
    // A function with a subscript may stand alone: the adjoint matrix.
    assert_eq!(
        function("\\operatorname{Ad}_{T}"),
        ("Ad".into(), Some("T".into()), 0)
    );
    let words = Vocabulary::with_words(&["between", "Ad"]);
    let e = parse_expr_with("-between(R_{2},R_{1}) + Ad_{T}", &words).unwrap();
    assert_eq!(
        e.to_string(),
        "-\\operatorname{between}(R_{2}, R_{1}) + {\\operatorname{Ad}_{T}}"
    );
    // `J_l^{-1}\left(\phi\right)` reads as printed: the symbols file says
    // whether `J_l` is a function.
    assert!(matches!(
        read("J_l^{-1}\\left(\\phi\\right)"),
        Expr::Product { .. }
    ));
    // Braces after a function name only group in print.
    same("(\\exp{(v))}", "(\\exp(v))");
    same("\\cos{(x)\\hat{v}}", "\\cos(x) \\hat{v}");
}

#[test]
fn derivatives_increments_and_operators() {
    let Expr::Derivative { of, wrt, .. } = read("\\frac{\\partial}{\\partial \\Phi}(\\Phi^{-1})")
    else {
        panic!()
    };
    assert_eq!(
        (of.to_string(), wrt.to_string()),
        ("\\Phi^{-1}".into(), "\\Phi".into())
    );
    let Expr::Derivative { of, .. } = read("\\dfrac{d}{d v_1}(\\hat{v}_1 v_2)") else {
        panic!()
    };
    assert_eq!(of.to_string(), "\\hat{v}_{1} v_{2}");
    let dx = read("\\Delta x");
    let s: &Symbol = dx.as_symbol().unwrap();
    assert!(s.capital_delta && s.delta.is_some());
    assert_ne!(read("\\Delta x"), read("\\delta x"));
    // Operators printed as superscripts.
    for (latex, op) in [
        ("p^\\odot", "odot"),
        ("x^*", "*"),
        ("x^{\\ast}", "ast"),
        ("A^+", "+"),
        ("A^\\dagger", "dagger"),
    ] {
        assert!(
            matches!(read(latex), Expr::Postfix { op: PostfixOp::Operator(o), .. } if o == op),
            "{latex}"
        );
    }
    same("x^{\\mathsf{T}}", "x^T");
    same("T_{1}^{^{-1}}", "T_1^{-1}");
    // Primes where printed: on the symbol, or in its superscript.
    assert_eq!(read("Z'^2").to_string(), "Z'^{2}");
    assert_eq!(read("p_i^{1'}").to_string(), "p_{i}^{1 '}");
    assert_ne!(read("Z'^2"), read("Z^{2'}"));
    // The cross-product matrix with its `×` inside the floor.
    same(
        "\\left\\lfloor R (p - q) \\times\\right\\rfloor",
        "\\lfloor R (p - q) \\rfloor_\\times",
    );
}

#[test]
fn cases_rows_and_punctuation() {
    let cases = read(
        "\\left\\{ \\begin{array}{l l} I + \\hat{v} & \\quad \\text{if $x$} \\\\ I & \\text{otherwise} \\end{array} \\right.",
    );
    let Expr::Cases(c) = cases else { panic!() };
    assert_eq!(c.len(), 2);
    assert!(c[0].condition.is_some());
    same(
        "\\begin{cases} a, & x > 0, \\\\ b. & \\text{else} \\end{cases}",
        "\\begin{cases} a & x > 0 \\\\ b & \\text{else} \\end{cases}",
    );
    same(
        "\\begin{bmatrix} a, & b \\\\ c & d. \\end{bmatrix}",
        "\\begin{bmatrix} a & b \\\\ c & d \\end{bmatrix}",
    );
    // Words between two statements separate them.
    let doc = Document::parse("$$a = b \\mbox{ and } c = d$$").unwrap();
    let claim = doc.claims(&doc.formulas()[0]).unwrap().remove(0);
    assert_eq!(claim.rhs().unwrap().to_string(), "b");
    assert_eq!(claim.notes.len(), 1);
}

#[test]
fn macros_defined_by_the_document() {
    let text = "\\newcommand{\\deriv}[2]{\\frac{\\partial#1}{\\partial#2}}\n\
                \\newcommand\\Skew[1]{[#1]_{\\times}}\n\
                \\def\\vC{\\mathbf C}\n\
                $$\\deriv{\\left(Rp\\right)}{\\omega}=-R\\Skew p \\quad (1)$$\n\
                $$\\deriv p{\\vC} = 0 \\quad (2)$$\n";
    let doc = Document::parse(text).unwrap();
    let one = doc
        .claims(doc.find(Locator::Label("1")).unwrap())
        .unwrap()
        .remove(0);
    assert_eq!(
        doc_latex::ast::Statement::to_string(one.statement.as_ref().unwrap()),
        "\\frac{\\partial R p}{\\partial \\omega} = -R \\lfloor p \\rfloor_{\\times}"
    );
    let two = doc
        .claims(doc.find(Locator::Label("2")).unwrap())
        .unwrap()
        .remove(0);
    assert_eq!(
        two.lhs.unwrap().to_string(),
        "\\frac{\\partial p}{\\partial \\boldsymbol{C}}"
    );
    // What a symbols file writes is read with the document's macros.
    assert_eq!(
        parse_expr_with("\\Skew{\\vC}", doc.vocabulary())
            .unwrap()
            .to_string(),
        "\\lfloor \\boldsymbol{C} \\rfloor_{\\times}"
    );
    // A macro that never ends is an error of its formula, not a hang.
    let looping = Document::parse("\\newcommand\\a{\\a\\a}\n$$x = \\a$$").unwrap();
    let e = looping.claims(&looping.formulas()[0]).unwrap_err();
    assert!(e.to_string().contains("expands without end"), "{e}");
}

#[test]
fn latex_and_doxygen_delimiters() {
    let tex = "% $not = math$\n\\section{A}\n\
               \\begin{equation}\n a = b \\label{eq:one}\n\\end{equation}\n\
               Then \\[ c = d \\] and \\(e\\) and\n\
               \\begin{align}\n x &= y \\\\\n &= z \\label{eq:two}\n\\end{align}\n";
    let doc = Document::parse_with(
        tex,
        Options {
            syntax: Syntax::Latex,
            words: &[],
        },
    )
    .unwrap();
    let kinds: Vec<MathKind> = doc.formulas().iter().map(|f| f.kind).collect();
    assert_eq!(
        kinds,
        [
            MathKind::Display,
            MathKind::Display,
            MathKind::Inline,
            MathKind::Display
        ]
    );
    let one = doc.find(Locator::Label("eq:one")).unwrap();
    assert_eq!(one.names, ["eq:one"]);
    let align = doc.find(Locator::Label("eq:two")).unwrap();
    let rows = doc.claims(align).unwrap();
    assert_eq!(rows.len(), 2);
    assert!(rows[1].continued);
    let dox = "\\f{align*}{ \\frac{\\partial f}{\\partial x} &= a \\\\[1em] \\empty g &= b \\f}\n\
               and \\f$ y \\f$.";
    let doc = Document::parse(dox).unwrap();
    assert_eq!(doc.formulas().len(), 2);
    assert_eq!(doc.claims(&doc.formulas()[0]).unwrap().len(), 2);
}

#[test]
fn anchors_are_never_silently_moved() {
    let text = "Prose with the words\n\n$$a = b$$\n\nand $$c = a$$\n";
    let doc = Document::parse(text).unwrap();
    match doc.locate("the words") {
        Ok(Found::Prose { line, after }) => assert_eq!((line, after.line), (1, 3)),
        other => panic!("{other:?}"),
    }
    assert!(matches!(doc.locate("b"), Ok(Found::Formula(f)) if f.line == 3));
    let e = doc.claim_in_formulas("the words").unwrap_err();
    assert!(
        matches!(e, LookupError::AnchorInProse { line: 1, .. }),
        "{e}"
    );
    let e = doc.locate("a").unwrap_err();
    assert_eq!(
        e.to_string(),
        "the anchor `a` occurs in 2 places (lines 3, 5); quote more of it, or say which with \
         `section` (a piece of its heading) or `occurrence` (1 to 2)"
    );
}

/// The same sentence before the same display in two sections: a section
/// (to the next heading of its level or a higher one) or an occurrence
/// names each; a quote that spans a display is refused, never read as the
/// display after it.
#[test]
fn a_claim_is_addressed_by_section_and_occurrence() {
    let text = "\\section{Points}\nThe Jacobian is:\n$$ J = a $$\n\\subsection{Detail}\n\
                The Jacobian is:\n$$ J = b $$\n\\section{Lines}\nThe Jacobian is:\n$$ J = c $$\n\
                @section lines2 Lines in Doxygen\nThe Jacobian is:\n$$ J = d $$\n";
    let doc = Document::parse(text).unwrap();
    let after = |section: Option<&str>, occurrence: Option<usize>| {
        let region = doc.region(section, occurrence)?;
        match doc.locate_in(&region, "The Jacobian is:")? {
            Found::Prose { after, .. } => Ok(after.source.trim().to_string()),
            Found::Formula(f) => Ok(f.source.clone()),
        }
    };
    assert!(matches!(
        after(None, None),
        Err(LookupError::AmbiguousAnchor { count: 4, .. })
    ));
    // `Points` holds its subsection: two places there.
    assert_eq!(after(Some("Points"), Some(2)).unwrap(), "J = b");
    assert_eq!(after(Some("Detail"), None).unwrap(), "J = b");
    assert_eq!(after(Some("{Lines}"), None).unwrap(), "J = c");
    assert_eq!(after(Some("lines2"), None).unwrap(), "J = d");
    assert_eq!(after(None, Some(4)).unwrap(), "J = d");
    assert!(matches!(
        after(None, Some(5)),
        Err(LookupError::NoOccurrence { count: 4, .. })
    ));
    assert!(matches!(
        after(Some("Nowhere"), None),
        Err(LookupError::NoSection(_))
    ));
    // A quote running over the first display names neither it nor the
    // next one.
    let e = doc
        .locate("The Jacobian is: $$ J = a $$ \\subsection")
        .unwrap_err();
    assert!(
        matches!(e, LookupError::QuoteSpansFormula { line: 3, .. }),
        "{e}"
    );
}

#[test]
fn renders_stay_readable() {
    let back = render::statement(&parse_statement("Z'^2 = {}_W p'").unwrap());
    assert_eq!(back, "Z'^{2} = {}_{W}p'");
}

/// A backslash before a character of several bytes (`\∂`) inside an
/// environment is stepped over whole (the fuzzer found a panic there).
#[test]
fn a_backslash_before_a_wide_character_is_read_safely() {
    let text = "\\begin{equation}\nx = \\∂ y\n\\end{equation}\n% \\∂ ω\n\\[ a \\ω \\]\n";
    let doc = Document::parse_with(
        text,
        Options {
            syntax: Syntax::Latex,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(doc.formulas().len(), 2);
}

/// A line that ends with a macro's argument is quoted whole (the macro's
/// tokens span its invocation, arguments included).
#[test]
fn a_line_ending_in_a_macro_is_quoted_whole() {
    let text = "\\newcommand{\\Skew}[1]{[#1]_{\\times}}\n\\[\nq = R\\Skew{-p}\n\\]\n";
    let doc = Document::parse_with(
        text,
        Options {
            syntax: Syntax::Latex,
            ..Default::default()
        },
    )
    .unwrap();
    let claims = doc.claims(&doc.formulas()[0]).unwrap();
    assert_eq!(claims[0].source, "q = R\\Skew{-p}");
}

/// LyX's reals `\mathfrak{\mathbb{R}^{3}}` are blackboard, a font over an
/// expression is the expression, and `\widehat` over a sum is the hat
/// operator on it (`\hat` stays one symbol's accent).
#[test]
fn fonts_and_wide_hats_over_expressions() {
    same("\\mathfrak{\\mathbb{R}^{3}}", "\\mathbb{R}^{3}");
    same("\\mathfrak{g^{*}}", "g^{*}");
    let e = read("Ad_{T}(\\widehat{\\xi_{b}+\\delta\\xi_{b}})");
    assert!(e.to_string().contains("\\wedge"), "{e}");
    assert!(doc_latex::parse_expr("\\hat{a + b}").is_err());
}
