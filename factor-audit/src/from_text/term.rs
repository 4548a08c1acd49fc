//! A formula lowered for evaluation: its symbols resolved to entries of a
//! context's symbol table, its notation to operations on [`super::value::Value`]s.

use super::functions::Builtin;
use super::stored::Kind;
use factor_core::manifold::Perturbation;

/// An entry of a context's symbol table.
pub type SymbolId = usize;

/// A product's operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Op {
    /// Juxtaposition, `*`: a product.
    Mul,
    /// `\cdot`: the scalar product of two columns of one length, else a
    /// product.
    Dot,
    /// `\times`: a cross product of 3-vectors, else a product.
    Cross,
    /// `\oplus`: a group composition, a pose acting on a point, or the
    /// product of two quaternions (JPL's in a file that states JPL
    /// quaternions).
    Oplus {
        /// JPL's quaternion product.
        jpl: bool,
    },
    /// `\otimes`: the product of two quaternions (JPL's when said), a
    /// group composition, or the Kronecker product of matrices.
    Otimes {
        /// JPL's quaternion product.
        jpl: bool,
    },
    /// `/`.
    Div,
}

/// A lowered formula.
#[derive(Debug, Clone, PartialEq)]
pub enum Term {
    /// A printed number.
    Number(f64),
    /// A symbol's value.
    Symbol(SymbolId),
    /// `−x`.
    Neg(Box<Term>),
    /// `± a ± b …` (`true` for a minus).
    Sum(Vec<(bool, Term)>),
    /// `a ∘ b ∘ …` (the first operator is ignored).
    Product(Vec<(Op, Term)>),
    /// `\frac{num}{den}`; with `stack`, the column `[num; den]`.
    Fraction {
        /// Above the bar.
        num: Box<Term>,
        /// Below the bar.
        den: Box<Term>,
        /// Read as a stack.
        stack: bool,
    },
    /// `x^p` for a number `p`.
    Power(Box<Term>, f64),
    /// `|x|`, `‖x‖`.
    Norm(Box<Term>),
    /// `x^∧`, `⌊x⌋×`.
    Hat(Box<Term>),
    /// `x^∨`.
    Vee(Box<Term>),
    /// `xᵀ`.
    Transpose(Box<Term>),
    /// A function applied.
    Call(Builtin, Vec<Term>),
    /// A matrix of blocks as printed.
    Blocks(Vec<Vec<Term>>),
    /// A printed `0` inside a matrix: a zero block of the size its place tells.
    Zero,
    /// A zero printed with a size inside a block matrix (`\mathbf{0}_3`,
    /// `0_{3 \times 1}`, `0_3^\top`): its block row and column size it,
    /// the printed rows and columns only where they do not (a single size
    /// `0_3` stands for a square block when nothing else tells).
    BlockZero(Option<usize>, Option<usize>),
    /// `I`, `I_3`, `I_{3×3}`.
    Identity(Option<usize>),
    /// `(…)_{r × c}`: the value, sized (and checked) by the annotation.
    Shaped(Box<Term>, (usize, usize)),
    /// `(a, b, …)`: the entries stacked in a column.
    Stack(Vec<Term>),
    /// `X / δξ`: the linear map `δξ ↦ X` (X affine in the tangent), as a
    /// matrix: its columns are X at each unit tangent minus X at zero.
    Quotient {
        /// `X`.
        numerator: Box<Term>,
        /// The tangent symbol `δξ`.
        tangent: SymbolId,
        /// Under `\lim_{δξ → 0}`: `X` need not be linear in `δξ`; the
        /// quotient is its derivative at zero (central differences,
        /// extrapolated).
        limit: bool,
    },
    /// A derivative in a chain rule: the printed formula of the claim of
    /// this file (by its index) that states it.
    Link(usize),
    /// A derivative in a chain rule that the document states in words: the
    /// true derivative of the context's link `k` ([`TruthLink`]).
    TruthLink(usize),
    /// An operator or function the symbols file defines by LaTeX over its
    /// arguments ([`Template`]), applied.
    Template(usize, Vec<Term>),
    /// `\left. X \right|_{x = a}`: `X` with symbols bound to values (what
    /// depends on them recomputed).
    At {
        /// `X`.
        body: Box<Term>,
        /// The symbols and their values.
        bindings: Vec<(SymbolId, Term)>,
    },
}

/// An operator or function defined by LaTeX over its arguments.
#[derive(Debug, Clone, PartialEq)]
pub struct Template {
    /// How it is written in the symbols file, normalised for lookups
    /// (`\\boxminus`, `^\\odot`, `H`: no braces or spaces).
    pub key: String,
    /// How it is written in the symbols file, for reports.
    pub written: String,
    /// Its arguments: symbols bound while its body is evaluated (the
    /// subscript's first, when it takes one).
    pub params: Vec<SymbolId>,
    /// Its printed subscript is its first argument (`\Phi_{R_0}(θ)`).
    pub subscripted: bool,
    /// Its body, lowered.
    pub body: Term,
}

/// A chain-rule link the document states only in words: the derivative of
/// `of` by `variable`, computed (by dual numbers) where it is used.
#[derive(Debug, Clone, PartialEq)]
pub struct TruthLink {
    /// The derivative as the chain rules print it (canonical LaTeX).
    pub key: String,
    /// The map.
    pub of: Term,
    /// The variable.
    pub variable: Variable,
    /// The local coordinates of a group-valued map.
    pub output: Option<Perturbation>,
    /// Why it cannot be evaluated, when a sample says so.
    pub broken: Option<String>,
    /// The scope of a derivative printed inside a formula
    /// (`R \frac{\partial}{\partial\omega}(e^{\omega^\wedge} p)`), read
    /// with that formula's symbols; `None` for a link the file states.
    pub inline: Option<Option<usize>>,
    /// The other arguments the partial derivative holds: symbols kept at
    /// their values while the variable moves, though they depend on it
    /// (`∂g/∂x` beside `∂g/∂r` in `∂g/∂x + ∂g/∂r ∂r/∂x`).
    pub holding: Vec<SymbolId>,
}

impl Term {
    /// Every sub-term (children first is not guaranteed).
    pub fn children(&self) -> Vec<&Term> {
        match self {
            Term::Number(_)
            | Term::Symbol(_)
            | Term::Zero
            | Term::BlockZero(..)
            | Term::Identity(_)
            | Term::Link(_)
            | Term::TruthLink(_) => Vec::new(),
            Term::Neg(x)
            | Term::Power(x, _)
            | Term::Norm(x)
            | Term::Hat(x)
            | Term::Vee(x)
            | Term::Transpose(x)
            | Term::Shaped(x, _) => vec![x],
            Term::Quotient { numerator, .. } => vec![numerator],
            Term::Sum(terms) => terms.iter().map(|(_, t)| t).collect(),
            Term::Product(factors) => factors.iter().map(|(_, t)| t).collect(),
            Term::Fraction { num, den, .. } => vec![num, den],
            Term::Call(_, args) | Term::Stack(args) | Term::Template(_, args) => {
                args.iter().collect()
            }
            Term::At { body, bindings } => std::iter::once(body.as_ref())
                .chain(bindings.iter().map(|(_, t)| t))
                .collect(),
            Term::Blocks(rows) => rows.iter().flatten().collect(),
        }
    }

    /// The claims this term links to (its chain rule's links), in order.
    pub fn links(&self) -> Vec<usize> {
        let mut out = Vec::new();
        let mut stack = vec![self];
        while let Some(t) = stack.pop() {
            if let Term::Link(k) = t {
                out.push(*k);
            }
            stack.extend(t.children().into_iter().rev());
        }
        out
    }
}

/// What a derivative is taken by, and how the input enters.
#[derive(Debug, Clone, PartialEq)]
pub enum Variable {
    /// A stored value (a field or a free variable), perturbed by a tangent
    /// on a side (added to, for an additive kind). `coordinates` are the
    /// tangent coordinates the input fills (the others stay zero).
    Stored {
        /// Its offset in the stored scalars.
        offset: usize,
        /// What it is.
        kind: Kind,
        /// The side (ignored for an additive kind).
        side: Perturbation,
        /// The tangent coordinates (0-based) the input fills.
        coordinates: Vec<usize>,
        /// Add the input to zero instead of the sampled value.
        at_zero: bool,
    },
    /// A defined symbol whose value the input is added to (an additive
    /// variable that is not stored: `u = log φ`, `P = R X + t`).
    Defined {
        /// The symbol.
        symbol: SymbolId,
        /// Its value's shape.
        shape: (usize, usize),
        /// Add the input to zero instead of the sampled value.
        at_zero: bool,
    },
    /// A symbol replaced by an update expression in it and a bound `δ`.
    Update {
        /// The symbol updated.
        symbol: SymbolId,
        /// The update.
        update: Term,
        /// The symbol the input binds.
        delta: SymbolId,
        /// The input's length.
        dim: usize,
    },
    /// Several variables together, the input their inputs one after another
    /// (a first-order claim in several small quantities: `x̃_{k+1} ≃ Φ x̃_k
    /// + G n`).
    Joint(Vec<Variable>),
}

impl Variable {
    /// Whether the variable is expanded about zero (all of it, for
    /// several).
    pub fn at_zero(&self) -> bool {
        match self {
            Variable::Stored { at_zero, .. } | Variable::Defined { at_zero, .. } => *at_zero,
            Variable::Joint(parts) => parts.iter().all(Variable::at_zero),
            Variable::Update { .. } => false,
        }
    }

    /// The input's length.
    pub fn dim(&self) -> usize {
        match self {
            Variable::Stored { coordinates, .. } => coordinates.len(),
            Variable::Defined { shape, .. } => shape.0 * shape.1,
            Variable::Update { dim, .. } => *dim,
            Variable::Joint(parts) => parts.iter().map(Variable::dim).sum(),
        }
    }
}

/// A symbol's meaning, resolved.
#[derive(Debug, Clone, PartialEq)]
pub enum Meaning {
    /// Stored scalars of the sample.
    Stored {
        /// Offset in the stored scalars.
        offset: usize,
        /// What they are.
        kind: Kind,
    },
    /// A definition.
    Definition(Term),
    /// Entry `index` (0-based) of another symbol's vector.
    Component {
        /// The vector's symbol.
        of: SymbolId,
        /// Which entry.
        index: usize,
    },
    /// A function symbol.
    Function(Builtin),
    /// A function symbol defined by LaTeX over its arguments (a template of
    /// the context, by index).
    Template(usize),
    /// A tangent: a perturbation of a stored value or a definition, and the
    /// symbols of its equal parts.
    Tangent {
        /// What a derivative by it perturbs.
        variable: Variable,
        /// Symbols of its equal slices (`δφ`, `δρ`), in order.
        parts: Vec<SymbolId>,
    },
    /// Components (0-based) of the factor's residual.
    Residual(Vec<usize>),
    /// A name bound only while a quotient or an update is evaluated
    /// (`δφ` of a difference quotient, `\delta` of an update).
    Bound,
    /// Not resolved yet (while the table is built).
    Pending,
    /// The symbols file's meaning cannot be read (why): the claims that use
    /// it are unread, the others audited.
    Broken(String),
}

/// One symbol.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// Its LaTeX, canonical (as `doc-latex` renders it).
    pub key: String,
    /// Its meaning.
    pub meaning: Meaning,
}

/// A context's symbols (and its claims' own readings).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Table {
    /// The entries; a [`SymbolId`] indexes them.
    pub entries: Vec<Entry>,
}

impl Table {
    /// A new entry with a pending meaning.
    pub fn add(&mut self, key: String) -> SymbolId {
        self.entries.push(Entry {
            key,
            meaning: Meaning::Pending,
        });
        self.entries.len() - 1
    }

    /// The LaTeX of a symbol.
    pub fn key(&self, id: SymbolId) -> &str {
        &self.entries[id].key
    }
}
