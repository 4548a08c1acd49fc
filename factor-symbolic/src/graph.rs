//! The expression DAG: hash-consed nodes in a thread-local arena.
//!
//! Structurally equal nodes are interned once, so an [`Expr`] is a `Copy`
//! handle (a node index) and equality of handles is structural equality. The
//! arena lives in a thread-local slot that a [`Tracer`] installs and takes
//! back; every [`Expr`] refers to the graph of the tracer active when it was
//! made.

use std::cell::RefCell;
use std::collections::HashMap;
use std::fmt;

/// A handle to an interned node. Ids grow with creation, and a node is created
/// after its children, so id order is a topological order.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Expr(pub(crate) u32);

impl Expr {
    /// The node index.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Debug for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "t{}", self.0)
    }
}

/// An `f64` compared and hashed by its bits, with `−0.0` folded into `0.0`.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Real(u64);

impl Real {
    /// Wraps a finite or non-finite value.
    pub fn new(value: f64) -> Self {
        Real(if value == 0.0 {
            0.0_f64.to_bits()
        } else {
            value.to_bits()
        })
    }
    /// The value.
    pub fn get(self) -> f64 {
        f64::from_bits(self.0)
    }
    /// The bit pattern (after folding `−0.0`).
    pub fn bits(self) -> u64 {
        self.0
    }
}

impl fmt::Debug for Real {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.get())
    }
}

/// One node. `Add` and `Mul` are n-ary canonical forms (see
/// [`crate::algebra`] for their invariants).
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub enum Node {
    /// A literal.
    Const(Real),
    /// Input slot `i` of the traced function.
    Input(u32),
    /// `constant + Σ coefficient · term`, terms sorted by id, coefficients
    /// non-zero, the first one equal to 1, no term an `Add` or a `Const`.
    Add {
        /// The constant part.
        constant: Real,
        /// `(term, coefficient)` pairs.
        terms: Box<[(Expr, Real)]>,
    },
    /// `coefficient · Π base^exponent`, bases sorted by id, exponents non-zero,
    /// no base a `Mul` or a `Const`.
    Mul {
        /// The numeric factor.
        coefficient: Real,
        /// `(base, exponent)` pairs.
        factors: Box<[(Expr, i32)]>,
    },
    /// `√x`.
    Sqrt(Expr),
    /// `sin x`.
    Sin(Expr),
    /// `cos x`.
    Cos(Expr),
    /// `atan2(y, x)`.
    Atan2(Expr, Expr),
    /// `eˣ`.
    Exp(Expr),
    /// `ln x`.
    Ln(Expr),
    /// `acos x`.
    Acos(Expr),
    /// `asin x`.
    Asin(Expr),
    /// `atan x`.
    Atan(Expr),
    /// `if lhs < rhs { if_less } else { otherwise }`.
    Select {
        /// Left side of the comparison.
        lhs: Expr,
        /// Right side of the comparison.
        rhs: Expr,
        /// Value when `lhs < rhs`.
        if_less: Expr,
        /// Value otherwise.
        otherwise: Expr,
    },
}

impl Node {
    /// The node's direct children, in a fixed order.
    pub fn children(&self) -> Vec<Expr> {
        match self {
            Node::Const(_) | Node::Input(_) => Vec::new(),
            Node::Add { terms, .. } => terms.iter().map(|(t, _)| *t).collect(),
            Node::Mul { factors, .. } => factors.iter().map(|(b, _)| *b).collect(),
            Node::Sqrt(x)
            | Node::Sin(x)
            | Node::Cos(x)
            | Node::Exp(x)
            | Node::Ln(x)
            | Node::Acos(x)
            | Node::Asin(x)
            | Node::Atan(x) => vec![*x],
            Node::Atan2(y, x) => vec![*y, *x],
            Node::Select {
                lhs,
                rhs,
                if_less,
                otherwise,
            } => vec![*lhs, *rhs, *if_less, *otherwise],
        }
    }
}

/// The arena: nodes by id and the interning table.
#[derive(Default, Clone)]
pub struct Graph {
    nodes: Vec<Node>,
    index: HashMap<Node, Expr>,
}

impl fmt::Debug for Graph {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Graph({} nodes)", self.nodes.len())
    }
}

impl Graph {
    /// The node behind a handle.
    pub fn node(&self, e: Expr) -> &Node {
        &self.nodes[e.index()]
    }

    /// Number of interned nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the graph is empty.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    fn intern(&mut self, node: Node) -> Expr {
        if let Some(&e) = self.index.get(&node) {
            return e;
        }
        let e = Expr(u32::try_from(self.nodes.len()).expect("fewer than 2³² nodes"));
        self.nodes.push(node.clone());
        self.index.insert(node, e);
        e
    }
}

thread_local! {
    static ACTIVE: RefCell<Option<Graph>> = const { RefCell::new(None) };
}

/// Interns a node in the active graph. Panics when no [`Tracer`] is active:
/// symbolic values exist only inside a trace.
pub(crate) fn intern(node: Node) -> Expr {
    ACTIVE.with(|g| {
        g.borrow_mut()
            .as_mut()
            .expect("symbolic expression built outside an active Tracer")
            .intern(node)
    })
}

/// A copy of the node behind a handle in the active graph.
pub(crate) fn node(e: Expr) -> Node {
    ACTIVE.with(|g| {
        g.borrow()
            .as_ref()
            .expect("symbolic expression read outside an active Tracer")
            .node(e)
            .clone()
    })
}

/// Installs a fresh graph for this thread while alive; [`Tracer::finish`]
/// returns it. One tracer per thread at a time.
pub struct Tracer {
    _not_send: std::marker::PhantomData<*const ()>,
}

impl Tracer {
    /// Starts a trace. Panics if another tracer is active on this thread.
    #[allow(clippy::new_without_default)]
    pub fn new() -> Self {
        ACTIVE.with(|g| {
            let mut g = g.borrow_mut();
            assert!(g.is_none(), "a Tracer is already active on this thread");
            *g = Some(Graph::default());
        });
        Tracer {
            _not_send: std::marker::PhantomData,
        }
    }

    /// A snapshot of the graph built so far.
    pub fn graph(&self) -> Graph {
        ACTIVE.with(|g| g.borrow().as_ref().expect("active").clone())
    }

    /// Ends the trace and returns its graph.
    pub fn finish(self) -> Graph {
        let graph = ACTIVE.with(|g| g.borrow_mut().take().expect("active"));
        std::mem::forget(self);
        graph
    }
}

impl Drop for Tracer {
    fn drop(&mut self) {
        ACTIVE.with(|g| g.borrow_mut().take());
    }
}
