//! The syntax tree of a formula line.
//!
//! A line of a formula is a [`Statement`]: an optional left side and a chain
//! of relations (`a = b ≈ c`). Its parts are [`Expr`]s. The tree records what
//! is printed, not what it means: `C(x)` is an [`Expr::Apply`] whether `C` is
//! a function or a matrix times a vector, and a superscript written on a
//! symbol stays part of the symbol (`R_w^c`, `P_z^2`) unless it is one of the
//! postfix markers `T`, `\top`, `\wedge`, `\vee` or a negative or fractional
//! exponent. A symbol table decides the rest.
//!
//! Parentheses that only group are not kept (the tree's shape shows the
//! grouping); the renderer puts them back where they are needed.

/// One line of a formula: `[⇒] [head] rel₁ rhs₁ rel₂ rhs₂ …`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Statement {
    /// The line starts with `\Rightarrow` ("it follows that").
    pub implied: bool,
    /// The left side; `None` when the line starts with a relation (it
    /// continues the chain of an earlier line).
    pub head: Option<Expr>,
    /// The relations and right sides, in order.
    pub steps: Vec<(Rel, Expr)>,
}

impl Statement {
    /// The value the chain arrives at: the last right side of a relation
    /// other than a membership (`exp(ω) = (…) \in S^3` arrives at `(…)`).
    pub fn rhs(&self) -> Option<&Expr> {
        self.steps
            .iter()
            .rev()
            .find(|(r, _)| !r.is_membership())
            .map(|(_, e)| e)
    }
}

/// An expression.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Expr {
    /// A decimal number as printed (`2`, `0.5`); never negative.
    Number(String),
    /// A symbol with its decorations.
    Symbol(Symbol),
    /// `\text{…}`, `\mathrm{…}` of a word that is no function name.
    Text(String),
    /// `\cdot` or `.` standing for an argument, as in `\lfloor . \rfloor_\times`.
    Placeholder,
    /// `\cdots`, `\ldots`, `\vdots`, `\ddots`: what is not printed (more
    /// arguments, more blocks).
    Ellipsis,
    /// `-x`.
    Neg(Box<Expr>),
    /// `+x` (a line continuing a sum across displays starts so).
    Pos(Box<Expr>),
    /// `first ± … ± …`.
    Sum {
        /// The first term (a [`Expr::Neg`] when it is printed with a minus).
        first: Box<Expr>,
        /// The other terms with their signs.
        rest: Vec<(Sign, Expr)>,
    },
    /// `first op … op …`, implicit (juxtaposition) or explicit operators.
    Product {
        /// The first factor.
        first: Box<Expr>,
        /// The other factors, each with the operator before it.
        rest: Vec<(MulOp, Expr)>,
    },
    /// `\frac{num}{den}` (also `\dfrac`, `\tfrac`) that is no derivative.
    Fraction {
        /// The numerator.
        num: Box<Expr>,
        /// The denominator.
        den: Box<Expr>,
    },
    /// `\frac{\partial of}{\partial wrt}` or `\frac{d of}{d wrt}`: the
    /// derivative of `of` with respect to `wrt`.
    Derivative {
        /// Partial (`∂`) or total (`d`).
        kind: DerivativeKind,
        /// What is differentiated.
        of: Box<Expr>,
        /// With respect to what.
        wrt: Box<Expr>,
    },
    /// `\partial x` outside a derivative fraction (e.g. over a denominator
    /// printed without its `∂`).
    Differential(Box<Expr>),
    /// `\lim_{under} body`.
    Limit {
        /// The subscript, e.g. `δξ → 0`.
        under: Box<Expr>,
        /// What the limit is taken of (the rest of the product).
        body: Box<Expr>,
    },
    /// `\sqrt[index]{body}`.
    Sqrt {
        /// The root's index, if printed.
        index: Option<Box<Expr>>,
        /// The radicand.
        body: Box<Expr>,
    },
    /// `|x|` (single) or `\|x\|` (double).
    Norm {
        /// `\|…\|` rather than `|…|`.
        double: bool,
        /// The argument.
        body: Box<Expr>,
    },
    /// The skew-symmetric (cross-product) matrix `\lfloor x \rfloor_\times`
    /// or `[x]_\times`.
    Skew(Box<Expr>),
    /// `head(args…)`: a function applied to arguments, or a symbol followed
    /// directly by a parenthesised group (application or product: the symbol
    /// table decides).
    Apply {
        /// The function or symbol.
        head: Head,
        /// The comma-separated arguments.
        args: Vec<Expr>,
        /// Scripts printed on the closing parenthesis of a symbol's
        /// application (`R (R Q)^\top`, `T(ξ)^{-1}`, `C(q)'`): a chain of
        /// script nodes ([`Expr::Postfix`], [`Expr::Power`], …) whose
        /// innermost base is [`Expr::Placeholder`], the place of what they
        /// apply to. They apply to the application when the symbol is a
        /// function (`(J(β))^{-1}`) and to the parenthesised group when the
        /// application is a product (`R ((R Q)^\top)`): the symbol table
        /// decides, as it decides the application itself
        /// ([`Expr::with_scripts_of`] puts either in the place). Scripts
        /// after a function name's call (`\sin(x)^2`) wrap the call, and
        /// a group written around the application (`(R (R Q))^\top`) wraps
        /// it too: neither is here.
        scripts: Option<Box<Expr>>,
    },
    /// `base^{exponent}`: a negative or fractional exponent on a symbol, or
    /// any superscript on a non-symbol (`|y|^{\frac{3}{2}}`, `J(β)^{-1}`).
    Power {
        /// The base.
        base: Box<Expr>,
        /// The exponent.
        exponent: Box<Expr>,
    },
    /// A postfix operator: transpose, hat `^\wedge`, vee `^\vee`.
    Postfix {
        /// The operand.
        base: Box<Expr>,
        /// Which operator.
        op: PostfixOp,
    },
    /// A subscript on a non-symbol that is neither `\times` nor a shape.
    Indexed {
        /// The base.
        base: Box<Expr>,
        /// The subscript.
        index: Box<Expr>,
    },
    /// A shape annotation `(…)_{r \times c}` on a non-symbol.
    Shaped {
        /// The annotated expression.
        base: Box<Expr>,
        /// Rows as printed.
        rows: u32,
        /// Columns as printed.
        cols: u32,
    },
    /// Primes on a non-symbol (`1'` in `p_i^{1'}`); a symbol counts its own.
    Primed {
        /// The base.
        base: Box<Expr>,
        /// How many primes.
        primes: u32,
    },
    /// `(a, b, …)`, `[a, b]`, `\{a, b\}`: a comma-separated list of two or more.
    Tuple(Vec<Expr>),
    /// A matrix: `pmatrix`/`bmatrix`/`array` environments, a bracket group
    /// whose entries are separated by `\mid`, `|` or a wide space
    /// (`[\mathcal{K} \ 0]`), or a stacked fraction `\frac{R \mid t}{0 \mid 1}`.
    /// Rows may differ in length: the printed shape is kept.
    Matrix(Matrix),
    /// `\begin{cases} value & condition \\ … \end{cases}`.
    Cases(Vec<Case>),
    /// `\left. X \right|_{x = a}`, `X \Big\vert_{t = 0}`: `X` evaluated
    /// where the subscript says (one or more `name = value` bindings,
    /// comma-separated or in a `subarray`).
    At {
        /// What is evaluated.
        body: Box<Expr>,
        /// The subscript, as printed.
        at: Box<Expr>,
    },
    /// A relation chain inside an expression (`(φ = …)`, a `δξ → 0` under a
    /// limit, `φ_v ∈ R^3` in a matrix entry).
    Relation {
        /// The left-most side.
        first: Box<Expr>,
        /// The relations and right sides.
        rest: Vec<(Rel, Expr)>,
    },
}

/// A symbol: a letter or symbol command, with font, accent, increment
/// prefix, primes and scripts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Symbol {
    /// The letter or command.
    pub base: Base,
    /// Its font.
    pub font: Font,
    /// Its accent, if any.
    pub accent: Option<Accent>,
    /// `Some` for an increment `\delta x` (or `\boldsymbol{\delta} x`,
    /// `\Delta x`): the font of the `δ`.
    pub delta: Option<Font>,
    /// The increment's `δ` is a capital `\Delta`.
    pub capital_delta: bool,
    /// Primes printed on the symbol (`q'_4`, `\mathbf{q'}`, `Z'^2`, `x^\prime`).
    pub primes: u32,
    /// Primes printed at the end of its superscript (`p_i^{1'}`).
    pub sup_primes: u32,
    /// The subscript (an index: `R_j`, `C_{CB}`, `I_{3\times3}`).
    pub sub: Option<Box<Expr>>,
    /// The superscript that is not a postfix marker nor a negative or
    /// fractional exponent: an index (`R_w^c`) or a power (`P_z^2`).
    pub sup: Option<Box<Expr>>,
    /// A pre-subscript `{}_W x` (a frame).
    pub pre_sub: Option<Box<Expr>>,
    /// A pre-superscript `{}^w P`.
    pub pre_sup: Option<Box<Expr>>,
}

impl Symbol {
    /// A plain undecorated symbol.
    pub fn new(base: Base) -> Self {
        Symbol {
            base,
            font: Font::Plain,
            accent: None,
            delta: None,
            capital_delta: false,
            primes: 0,
            sup_primes: 0,
            sub: None,
            sup: None,
            pre_sub: None,
            pre_sup: None,
        }
    }

    /// Whether it is the bare letter `c` (no font, accent, scripts).
    pub fn is_letter(&self, c: char) -> bool {
        self.base == Base::Letter(c) && *self == Symbol::new(Base::Letter(c))
    }
}

/// What a symbol is a decorated version of.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Base {
    /// A letter (`x`, or any alphabetic character such as `ω`).
    Letter(char),
    /// A symbol command without its backslash (`omega`, `varepsilon`).
    Command(String),
}

/// A symbol's font.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Font {
    /// Math italic (the default).
    Plain,
    /// `\mathbf`, `\boldsymbol`, `\bm`.
    Bold,
    /// `\mathcal`.
    Calligraphic,
    /// `\bm{\mathcal{…}}`, `\boldsymbol{\mathcal{…}}`.
    BoldCalligraphic,
    /// `\mathbb`, `\mathds`, `\mathbbm`.
    Blackboard,
    /// `\mathrm`.
    Roman,
    /// `\mathsf`.
    SansSerif,
    /// `\mathfrak`.
    Fraktur,
}

/// An accent over a symbol.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Accent {
    /// `\hat`.
    Hat,
    /// `\tilde`.
    Tilde,
    /// `\bar`.
    Bar,
    /// `\dot`.
    Dot,
    /// `\ddot`.
    DDot,
    /// `\vec`.
    Vec,
    /// `\check`.
    Check,
    /// `\breve`.
    Breve,
}

/// What an [`Expr::Apply`] applies.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Head {
    /// A known function (`\sin`, `Exp`, `\cos^{-1}`).
    Function(Function),
    /// A symbol followed by a parenthesised group (`J_l(ω)`, `C_{WB}(…)`).
    Symbol(Symbol),
}

/// A function name with an optional power printed on it (`\cos^{-1}`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Function {
    /// The name as printed, without backslash (`sin`, `Exp`, `sinc`).
    pub name: String,
    /// The power on the name, if any.
    pub power: Option<Box<Expr>>,
    /// A subscript on the name (`Ad_T`, `\log_2`), if any.
    pub sub: Option<Box<Expr>>,
    /// Applied without parentheses, to the one factor after it (`\sin
    /// \theta x` is `\sin(\theta) x`; reading it `\sin(\theta x)` is
    /// the other choice a reader may have meant).
    pub bare: bool,
}

/// A matrix as printed: rows of entries (rows may differ in length).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Matrix {
    /// The rows.
    pub rows: Vec<Vec<Expr>>,
}

impl Matrix {
    /// `(rows, columns)` when every row has the same number of entries.
    pub fn shape(&self) -> Option<(usize, usize)> {
        let cols = self.rows.first()?.len();
        self.rows
            .iter()
            .all(|r| r.len() == cols)
            .then_some((self.rows.len(), cols))
    }

    /// The entry at `(row, col)`, if printed.
    pub fn entry(&self, row: usize, col: usize) -> Option<&Expr> {
        self.rows.get(row)?.get(col)
    }
}

/// One row of a `cases` environment.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Case {
    /// The value.
    pub value: Expr,
    /// The condition after `&`, if printed.
    pub condition: Option<Expr>,
}

/// Partial or total derivative.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DerivativeKind {
    /// `∂`.
    Partial,
    /// `d`.
    Total,
}

/// The sign of a term after the first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sign {
    /// `+`.
    Plus,
    /// `-`.
    Minus,
}

/// A product-level operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MulOp {
    /// Juxtaposition.
    Implicit,
    /// `\cdot`.
    Cdot,
    /// `\times`.
    Times,
    /// `\otimes`.
    Otimes,
    /// `\oplus`.
    Oplus,
    /// `\ominus`.
    Ominus,
    /// `\boxplus`.
    Boxplus,
    /// `\boxminus`.
    Boxminus,
    /// `\circ`.
    Circ,
    /// `\odot`.
    Odot,
    /// `\wedge` between two operands.
    Wedge,
    /// `*` or `\ast`.
    Star,
    /// `/`.
    Slash,
}

/// A postfix operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PostfixOp {
    /// `^T`, `^{T}`, `^\top`.
    Transpose,
    /// `^\wedge`: the hat (skew) map.
    Hat,
    /// `^\vee`: the vee map.
    Vee,
    /// Another operator printed as a superscript (`p^\odot`, `x^*`,
    /// `A^\dagger`, `A^+`): its command name without backslash, or the
    /// character. What it means is the symbols file's to say.
    Operator(&'static str),
}

/// A relation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rel {
    /// `=`.
    Eq,
    /// `\approx`.
    Approx,
    /// `\doteq`.
    Doteq,
    /// `\equiv`.
    Equiv,
    /// `\sim`.
    Sim,
    /// `\simeq`.
    Simeq,
    /// `\cong`.
    Cong,
    /// `\in`.
    In,
    /// `\notin`.
    NotIn,
    /// `\subset`.
    Subset,
    /// `\subseteq`.
    SubsetEq,
    /// `\leftarrow` (an update).
    LeftArrow,
    /// `\to`.
    To,
    /// `\Rightarrow` between two sides.
    Implies,
    /// `\Leftrightarrow`.
    Iff,
    /// `\mapsto`.
    MapsTo,
    /// `<`.
    Lt,
    /// `>`.
    Gt,
    /// `\leq`.
    Le,
    /// `\geq`.
    Ge,
    /// `\neq`.
    Neq,
    /// `\propto`.
    Propto,
    /// `\triangleq`, `:=`, `\coloneqq` (a definition).
    Define,
    /// `:` (set-builder "such that").
    Colon,
}

impl Rel {
    /// `\in`, `\notin`, `\subset`, `\subseteq`, `:`: a statement about a
    /// set, not a value.
    pub fn is_membership(self) -> bool {
        matches!(
            self,
            Rel::In | Rel::NotIn | Rel::Subset | Rel::SubsetEq | Rel::Colon
        )
    }
}

impl Expr {
    /// The symbol, if this is one.
    pub fn as_symbol(&self) -> Option<&Symbol> {
        match self {
            Expr::Symbol(s) => Some(s),
            _ => None,
        }
    }

    /// The matrix, if this is one (looking through a shape annotation).
    pub fn as_matrix(&self) -> Option<&Matrix> {
        match self {
            Expr::Matrix(m) => Some(m),
            Expr::Shaped { base, .. } => base.as_matrix(),
            _ => None,
        }
    }

    /// Whether a superscript of this form reads as an exponent rather than an
    /// index when written on a symbol: negative (`q^{-1}`), fractional
    /// (`|y|^{\frac{3}{2}}`) or a sum (`x^{n+1}`).
    pub fn reads_as_exponent(&self) -> bool {
        matches!(
            self,
            Expr::Neg(_) | Expr::Fraction { .. } | Expr::Sum { .. }
        )
    }

    /// `(r, c)` when this is a shape annotation `r \times c` of two integers.
    pub fn shape_annotation(&self) -> Option<(u32, u32)> {
        let Expr::Product { first, rest } = self else {
            return None;
        };
        let [(MulOp::Times, Expr::Number(c))] = rest.as_slice() else {
            return None;
        };
        let Expr::Number(r) = first.as_ref() else {
            return None;
        };
        Some((r.parse().ok()?, c.parse().ok()?))
    }

    /// `chain` (a chain of script nodes over [`Expr::Placeholder`], as in
    /// [`Expr::Apply`]'s `scripts`) with `base` in the placeholder's place.
    pub fn with_scripts_of(chain: &Expr, base: Expr) -> Expr {
        fn put(e: &Expr, base: Expr) -> Expr {
            let rebuilt = |inner: &Expr, base| Box::new(put(inner, base));
            match e {
                Expr::Placeholder => base,
                Expr::Postfix { base: b, op } => Expr::Postfix {
                    base: rebuilt(b, base),
                    op: *op,
                },
                Expr::Power { base: b, exponent } => Expr::Power {
                    base: rebuilt(b, base),
                    exponent: exponent.clone(),
                },
                Expr::Indexed { base: b, index } => Expr::Indexed {
                    base: rebuilt(b, base),
                    index: index.clone(),
                },
                Expr::Shaped {
                    base: b,
                    rows,
                    cols,
                } => Expr::Shaped {
                    base: rebuilt(b, base),
                    rows: *rows,
                    cols: *cols,
                },
                Expr::Primed { base: b, primes } => Expr::Primed {
                    base: rebuilt(b, base),
                    primes: *primes,
                },
                Expr::Skew(b) => Expr::Skew(rebuilt(b, base)),
                // Not a script chain: nothing to put in.
                other => other.clone(),
            }
        }
        put(chain, base)
    }

    /// The factors of a product (one factor for anything else).
    pub fn factors(&self) -> Vec<&Expr> {
        match self {
            Expr::Product { first, rest } => std::iter::once(first.as_ref())
                .chain(rest.iter().map(|(_, e)| e))
                .collect(),
            other => vec![other],
        }
    }

    /// The terms of a sum with their signs (the first term's sign is `Plus`
    /// unless it is a [`Expr::Neg`], whose operand is returned then).
    pub fn terms(&self) -> Vec<(Sign, &Expr)> {
        fn split(e: &Expr) -> (Sign, &Expr) {
            match e {
                Expr::Neg(x) => (Sign::Minus, x.as_ref()),
                other => (Sign::Plus, other),
            }
        }
        match self {
            Expr::Sum { first, rest } => std::iter::once(split(first))
                .chain(rest.iter().map(|(s, e)| (*s, e)))
                .collect(),
            other => vec![split(other)],
        }
    }
}
