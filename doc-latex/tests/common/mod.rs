//! The two specification documents, and helpers to take the parsed tree
//! apart in the tests.
#![allow(dead_code)]

use doc_latex::ast::{Expr, Matrix, Statement, Symbol};
use doc_latex::{Claim, Document, Locator};

/// Document 000 (Huang, point-line-plane reprojection factors).
pub const DOC000: &str = include_str!("../../../documents/000_29653f4af9b68bb8.txt");
/// Document 001 (free-line parametrisation, bearing-vector measurement).
pub const DOC001: &str = include_str!("../../../documents/001_85032ab900231dbd.txt");

pub fn doc000() -> Document {
    Document::parse(DOC000).expect("document 000 has no unclosed $$")
}

pub fn doc001() -> Document {
    Document::parse(DOC001).expect("document 001 has no unclosed $$")
}

/// The claims of the formula labelled `label`.
pub fn labelled(doc: &Document, label: &str) -> Vec<Claim> {
    let f = doc
        .find(Locator::Label(label))
        .expect("the label is printed");
    doc.claims(f).expect("the formula splits into lines")
}

/// The only claim of the formula labelled `label`.
pub fn only_claim(doc: &Document, label: &str) -> Claim {
    let mut claims = labelled(doc, label);
    assert_eq!(claims.len(), 1, "({label}) has one line");
    claims.pop().unwrap()
}

/// The statement of a claim that must have parsed.
pub fn statement(c: &Claim) -> &Statement {
    c.statement
        .as_ref()
        .unwrap_or_else(|e| panic!("line {} does not parse: {e}", c.line))
}

/// The last right side of a claim.
pub fn rhs(c: &Claim) -> &Expr {
    statement(c).rhs().expect("the claim has a relation")
}

/// Canonical LaTeX of an expression.
pub fn tex(e: &Expr) -> String {
    e.to_string()
}

/// The matrix `e` is (through a shape annotation).
pub fn matrix(e: &Expr) -> &Matrix {
    e.as_matrix()
        .unwrap_or_else(|| panic!("not a matrix: {}", tex(e)))
}

/// `(rows, cols)` of a rectangular matrix.
pub fn shape(e: &Expr) -> (usize, usize) {
    matrix(e).shape().expect("rectangular")
}

/// The entry `(i, j)` of a matrix.
pub fn entry(e: &Expr, i: usize, j: usize) -> &Expr {
    matrix(e).entry(i, j).expect("the entry is printed")
}

/// The operand of a leading minus.
pub fn negated(e: &Expr) -> &Expr {
    match e {
        Expr::Neg(x) => x,
        other => panic!("not negated: {}", tex(other)),
    }
}

/// `(of, wrt)` of a derivative, and whether it is partial.
pub fn derivative(e: &Expr) -> (&Expr, &Expr, bool) {
    match e {
        Expr::Derivative { kind, of, wrt } => {
            (of, wrt, *kind == doc_latex::ast::DerivativeKind::Partial)
        }
        other => panic!("not a derivative: {}", tex(other)),
    }
}

/// The symbol `e` is.
pub fn symbol(e: &Expr) -> &Symbol {
    e.as_symbol()
        .unwrap_or_else(|| panic!("not a symbol: {}", tex(e)))
}

/// `(num, den)` of a fraction.
pub fn fraction(e: &Expr) -> (&Expr, &Expr) {
    match e {
        Expr::Fraction { num, den } => (num, den),
        other => panic!("not a fraction: {}", tex(other)),
    }
}

/// `(base, exponent)` of a power.
pub fn power(e: &Expr) -> (&Expr, &Expr) {
    match e {
        Expr::Power { base, exponent } => (base, exponent),
        other => panic!("not a power: {}", tex(other)),
    }
}

/// Every claim of a document (formulas that do not split are skipped and
/// returned apart).
pub fn all_claims(doc: &Document) -> Vec<Claim> {
    doc.formulas()
        .iter()
        .filter_map(|f| doc.claims(f).ok())
        .flatten()
        .collect()
}
