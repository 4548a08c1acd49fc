//! Reads the math of a Markdown/LaTeX document: finds its formulas and
//! their equation labels, and parses each line of a formula into a syntax
//! tree ([`ast`]) that a canonical renderer ([`render`]) writes back, so a
//! reader sees what was understood. It knows nothing of what the symbols
//! mean: the caller (the audit, with a symbol table) decides that.
//!
//! ```
//! use doc_latex::{Document, Locator, ast::Expr};
//!
//! let doc = Document::parse(
//!     "The Jacobian:\n$$\\frac{\\partial \\phi}{\\partial y} = \\frac{1}{|y|} I - \
//!      \\frac{1}{|y|^{\\frac{3}{2}}} y y^T \\quad (7)$$\n",
//! )?;
//! let claim = doc.claims(doc.find(Locator::parse("(7)"))?)?.remove(0);
//! assert!(matches!(claim.lhs, Some(Expr::Derivative { .. })));
//! assert_eq!(
//!     claim.rhs().unwrap().to_string(),
//!     "\\frac{1}{\\left| y \\right|} I - \\frac{1}{\\left| y \\right|^{\\frac{3}{2}}} y y^{T}"
//! );
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # What it reads
//!
//! [`Document::parse`] finds `$$…$$` displays (which may span lines) and
//! `$…$` inline formulas (closed before a blank line, a `$` inside braces
//! not closing them), skipping fenced code blocks, code spans and `\$`; it
//! reads LaTeX's `\[…\]`, `\(…\)` and display environments (`equation`,
//! `align`, `gather`, `multline`, `eqnarray`, `flalign`, `alignat`) and
//! Doxygen's `\f$…\f$`, `\f[…\f]`, `\f{align}{…\f}` too;
//! [`Document::parse_with`] reads a LaTeX source ([`Syntax::Latex`]: `%`
//! comments) and takes words the document uses as function names. Each
//! [`Formula`] has its byte span, line, source, label and `\label{…}`
//! names. A label is a `\tag{…}` inside the display, a trailing `(N)` after
//! a spacing command (`\quad (1.1)`), a line `(N)` right after the display,
//! or a display holding only `(N)` (`$$(10)$$`), which labels the display
//! before it.
//!
//! The macros the document defines ([`macros`]: `\newcommand`, `\def`,
//! `\DeclareMathOperator`, …, in its preamble or inside math) are expanded
//! in the formulas after their definition; [`Document::vocabulary`] reads
//! LaTeX written about the document the same way ([`parse_expr_with`]).
//!
//! A formula is found ([`Document::find`]) by a [`Locator`]: its label or
//! `\label` name, or an anchor, a piece of its LaTeX (whitespace does not
//! matter) or, failing that, of the prose just before it.
//! [`Document::locate`] says which of the two an anchor was, and
//! [`Document::claim_in_formulas`] refuses an anchor found only in the
//! prose, so a caller never audits another display than meant without
//! saying so. [`Document::claims`] reads it as one
//! [`Claim`] per line: the rows of a display that is one `aligned`, `split`,
//! `align`, `gather`, `multline`, `eqnarray` or `alignat` environment (`&`
//! dropped), the rows of a display that is one `cases` environment (the
//! condition after `&` a side note), or its top-level `\\` lines. A line
//! is a [`ast::Statement`]: `[\Rightarrow] [left side] rel right side rel
//! …`; top-level `,`, `\quad`/`\qquad` and words (`\mbox{ and }` after a
//! right side) separate it from side notes (`\quad θ = |ω|`), except that a
//! piece starting with a relation continues the chain (`= R \qquad \in
//! SO(3)`); a trailing `.` or `,` is punctuation, in matrix rows and cases
//! too.
//!
//! A line that starts with a relation continues a chain: its
//! [`Claim::lhs`] is the left side of the last line that started one, in
//! the same display or in the displays just before it (with only whitespace
//! and label lines between): `$$(3.5)$$ = …` continues (3.4).
//! [`Document::chain`] gives a chain's lines, side notes skipped; its last
//! claim is where the derivation arrives.
//!
//! Some LaTeX of the documents is broken as printed (they look
//! machine-converted), so reading is tolerant where it can be without
//! guessing: lines are split on the tokens before parsing, so a broken line
//! (or side note) does not hide the others; a display that opens one
//! environment and never closes it is read as closed at its end, and says
//! so ([`Claim::unclosed_environment`]).
//!
//! # The tree
//!
//! [`ast::Expr`] records what is printed, not what it means:
//!
//! | printed | node |
//! | --- | --- |
//! | `2`, `0.5` | `Number` (never negative: `-1` is `Neg(1)`) |
//! | `x`, `\omega_1`, `{}_W\hat{\mathbf p}_C'`, `\delta\xi_j` | `Symbol`: letter or command, font, accent, `δ` increment prefix, primes, sub, sup, pre-sub, pre-sup |
//! | `a + b - c`, `-x` | `Sum`, `Neg` (`Pos` for a leading `+`) |
//! | `a b`, `a \cdot b`, `q \oplus p` | `Product` with the operator before each factor |
//! | `\frac{a}{b}` | `Fraction` |
//! | `\frac{\partial e}{\partial \xi}`, `\frac{d f}{dw}` | `Derivative` (partial or total) of `of` w.r.t. `wrt`; a chain rule is a `Product` of them |
//! | `\partial x` not over `\partial y` | `Differential` (document 000 (4) prints `∂(P)/ξ_j`) |
//! | `\lim_{δξ \to 0} …` | `Limit` over the rest of the product |
//! | `\sqrt[n]{x}`, single and double bars | `Sqrt`, `Norm` (single or double) |
//! | `\lfloor v \rfloor_\times`, `[v]_\times` | `Skew` |
//! | `\sin\theta`, `Exp(ω)`, `\cos^{-1}(x)`, `J_l(ω)`, `C_{WB}(…)` | `Apply`: a known function, or a symbol directly before `(` (application or product: the symbol table decides; after `\left(` it is a product) |
//! | `x^{-1}`, `\lvert y \rvert^{3/2}`, `f(x)^2` | `Power`: a negative, fractional or sum exponent on a symbol, any superscript elsewhere |
//! | `x^T`, `x^\top`, `ω^\wedge`, `S^\vee`, `T_w^{cT}` | `Postfix` (markers at the end of a superscript are stripped from it) |
//! | `M_{3\times6}` on a non-symbol | `Shaped`; other subscripts `Indexed` (`[p]_x`, `[\omega]_+`, printed back in brackets); primes `Primed` |
//! | `(a, b)`, `\{ω, ρ\}` | `Tuple` |
//! | `pmatrix`, `bmatrix`, `array`, `[K \ 0]`, `(δφ \quad δρ)`, `[n \mid v]`, `\frac{R \mid t}{0 \mid 1}` | `Matrix`, rows as printed (possibly ragged) |
//! | `\begin{cases}` | `Cases` (value, condition) |
//! | `(φ = …)`, `δξ \to 0`, `φ_v \in R^3` inside a group | `Relation` |
//! | `\text{…}`, `\lfloor . \rfloor` | `Text`, `Placeholder` |
//!
//! Parentheses that only group are not kept; the renderer puts them back.
//! A superscript written on a symbol stays part of it (`R_w^c`, `P_z^2`,
//! `l_i^{1'}`), since it may be an index or a power. Explicit word spaces
//! (`\ `, `~`, `\quad`) inside a bracket group or matrix entry separate row
//! entries (`[\mathcal{K} \ 0]` is the block row the documents mean); thin
//! spaces (`\,` `\;` `\:` `\!`) are always ignored.
//!
//! # Covered notation
//!
//! Numbers, letters, Greek and symbol commands (`\varGamma`…); `\mathbf`,
//! `\boldsymbol`, `\bm`, `\pmb`, `\mathcal`, `\mathscr`, `\mathbb`, `\mathds`,
//! `\mathrm`, `\mathsf`, `\mathfrak` (a font over several letters is their
//! product, `\mathbf{Rp}`; over a digit a symbol, `\mathbf{0}`, `\mathds{1}`;
//! bold over calligraphic combines, `\bm{\mathcal{J}}`), plain-TeX `{\rm d}`,
//! `\bf`, `\cal`; `\mbox{\boldmath $x$}`; `\hat`, `\tilde`, `\bar`, `\dot`,
//! `\ddot`, `\vec`, `\check`, `\breve` (and wide forms); pre-scripts `{}_W x`;
//! `\delta x` and `\Delta x` increments; `\frac`, `\dfrac`, `\tfrac`,
//! `\cfrac`, `{a \over b}`, nested and stacked; `\sqrt`; `\partial`, `d` in a
//! fraction, the operator forms `\frac{\partial}{\partial x} f` and
//! `\frac{d}{dt} f`, `\lim` (and `\mathop{\lim}\limits`); `\sin \cos \tan
//! \cot \sec \csc \exp \log \det \arccos \arcsin \arctan \ln \sinh \cosh
//! \tanh \coth` and the words `sin cos tan cot sec csc sinh cosh tanh sinc
//! exp log Exp Log det arccos arcsin arctan acos asin atan ln diag`,
//! `\text{…}`/`\operatorname{…}`/`\mathrm{…}` names (`Ad`, `ad`, `tr`, and any
//! word before `(`), powers and subscripts on names (`\cos^{-1}`, `\log_2`,
//! `Ad_T` standing alone); braces after a function name only group (`\cos{(x)
//! y}` is `cos(x) y`); `+ - * /`, `\cdot \times \otimes \oplus \ominus
//! \boxplus \boxminus \circ \odot \wedge \ast`; `= < > :` and `\approx
//! \doteq \equiv \sim \simeq \cong \in \notin \subset \subseteq \leftarrow
//! \gets \to \rightarrow \Rightarrow \implies \Leftrightarrow \iff \mapsto
//! \le(q) \ge(q) \ne(q) \propto \triangleq := \coloneqq`, and decorated
//! relations `\stackrel{…}{=}`, `\overset{…}{=}`, `\buildrel … \over =`;
//! `( ) [ ] \{ \}`, `\left…\right` (with `.`), `\big`-family sizes, `| |`,
//! `\| \|`, `\vert`, `\Vert`, `\lfloor \rfloor` (and `\lfloor v \times
//! \rfloor`); `matrix pmatrix bmatrix Bmatrix smallmatrix array` (with
//! `\hline`), `cases` (and `\left\{ \begin{array} … \right.`), and the
//! alignment environments above; `\mid` and `|` separators; `^T ^{T} ^\top
//! ^{\mathsf{T}} ^\wedge ^\vee ' ^\prime`, `^{^{-1}}`, operators as
//! superscripts (`p^\odot`, `x^*`, `A^\dagger`, `A^+`); `\underbrace{x}_{…}`;
//! `\quad \qquad \ ~ \hspace{…}`, `\, \; \: \! \> \kern…`, `\\[1em]`,
//! `\displaystyle`, `\limits`, `\label`, `\tag`, `\nonumber`, `\color{…}`,
//! `\phantom{…}`, `%` comments.
//!
//! # Errors and bounds
//!
//! Malformed LaTeX (unbalanced braces, an unknown command or environment, a
//! stray `&` or `\\`, an unclosed delimiter, …) is a [`ParseError`] naming
//! the formula's label, the line and byte offset in the document, and the
//! fragment there; it displays on one line. Nothing panics: a `proptest`
//! fuzz over mutated document formulas and random strings checks it.
//! Nesting is bounded by [`MAX_DEPTH`] = 64 steps (a group, a sign, a
//! factor and a command each count one; the deepest formula of the two
//! documents needs 24); deeper input is [`ErrorKind::TooDeep`]. At the
//! bound the parser needs at most 768 KiB of stack in a debug build and 128
//! KiB in a release build (measured over 26 shapes of hostile nesting; a
//! Rust thread gets 2 MiB). Each token is read once, with no backtracking,
//! and line numbers come from an index, so reading is linear in the input
//! (a 6.5 MB document of 200 000 formulas reads in about a third of a
//! second in release).
//!
//! # Known gaps
//!
//! All 37 formulas of the two documents that the audit reads parse, and so
//! do the formulas of the corpus (`documents/corpus/`) but six pieces that
//! state no derivative: the side notes `\forall \norm{\vvph} \in
//! \mathbb{R}\backslash\{0\}` of the kindr cheat sheet's four rate
//! formulas (`\forall` is not read; the formulas before them are), its
//! heading `$\Leftrightarrow$` (a relation alone), and GTSAM's `$^{*}$`
//! (a superscript alone, in prose).
//! The lines that do not are those whose printed LaTeX is broken:
//!
//! | document, line | printed | error |
//! | --- | --- | --- |
//! | 000, 65 | `$SE(3) \doteq \{T = …$`: an inline formula cut in two by the conversion | `\{` not closed |
//! | 000, 102 | `\frac{…}{= \lim … \frac{…}{= \begin{bmatrix}…}}`: a brace short | unbalanced braces |
//! | 000, 123 | the side note `\sigma = […]`, whose bracket ends in a stray bar after `v` | empty entry |
//! | 000, 178, 180 | `\lfloor \lfloor δω⌋× R + …`: the outer `\lfloor` never closes | `\lfloor` not closed |
//! | 000, 239 | the note `(y = (…)) \in R^4)` (extra `)`); one line of the ∂g/∂ξ chain (extra `}`) | unexpected `)`; unbalanced braces |
//! | 000, 243 | `\log(exp(u) \oplus exp(u) = …` (`(` never closed) | `(` not closed |
//! | 001, 101, 103 | (4.19) opens `-[C_{WB} …` and (4.20) closes it `…]`: one bracket over two displays | `[` not closed; unexpected `]` |
//!
//! Notation not covered (an error, or read literally): `vmatrix`
//! determinants; `\dots`-family ellipses, `\sum`, `\prod`, `\int`; `\pm`;
//! `\atop`, `\binom`, `\substack`; `\langle…\rangle`; an accent over more
//! than one symbol (`\hat{x+y}`). Conventions a reader should know:
//! a function without parentheses takes one factor (`\sin 2x` is
//! `sin(2)·x`); a script without braces takes one token (`x^12` is `x^1 2`,
//! but a decimal `x^0.5` is taken whole); `|` separates entries inside
//! brackets and matrices, and only `\mid` inside a fraction.

pub mod ast;
mod definition;
mod document;
pub mod error;
mod extract;
mod lexer;
mod lines;
pub mod macros;
mod names;
mod parser;
pub mod render;
mod rewrite;

pub use document::{Claim, Document, Formula, Found, Locator, Options, Region};
pub use error::{ErrorKind, LookupError, ParseError};
pub use extract::{MathKind, Syntax};
pub use macros::Vocabulary;
pub use parser::MAX_DEPTH;

use ast::{Expr, Statement};
use error::Lines;
use parser::{Parser, Place};

/// One line of LaTeX math (no `$`), read as a statement.
pub fn parse_statement(latex: &str) -> Result<Statement, ParseError> {
    with_parser(latex, &Vocabulary::default(), |p| p.statement())
}

/// LaTeX math (no `$`), read as one expression (a relation chain becomes an
/// [`Expr::Relation`]).
pub fn parse_expr(latex: &str) -> Result<Expr, ParseError> {
    parse_expr_with(latex, &Vocabulary::default())
}

/// LaTeX math read as one expression with a document's macros and words
/// ([`Document::vocabulary`]): what a symbols file writes about it.
pub fn parse_expr_with(latex: &str, vocabulary: &Vocabulary) -> Result<Expr, ParseError> {
    with_parser(latex, vocabulary, |p| p.whole_expression())
}

fn with_parser<T>(
    latex: &str,
    vocabulary: &Vocabulary,
    parse: impl FnOnce(Parser<'_>) -> Result<T, ParseError>,
) -> Result<T, ParseError> {
    let lines = Lines::new(latex);
    let toks = macros::tokens(latex, vocabulary, usize::MAX)
        .map_err(|(offset, kind)| ParseError::at(latex, &lines, offset, None, kind))?;
    let place = Place {
        text: latex,
        lines: &lines,
        base: 0,
        label: None,
    };
    parse(Parser::new(latex, toks, place)?)
}
