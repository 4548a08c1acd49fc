//! Smart constructors: every node is built in canonical form, so algebraic
//! identities hold by construction and equal expressions are one node.
//!
//! - Sums are flattened into `constant + Σ cᵢ tᵢ`: like terms are collected
//!   (`x − x = 0`, `x + x = 2x`), constants folded (`x + 0 = x`), terms sorted
//!   by id. A sum is stored with its first coefficient 1 and the common factor
//!   outside (`−2x − 2y` is `−2 · (x + y)`), so a sum and its multiples share
//!   one node: the derivative `−2(xy + zw)` of one rotation-matrix entry *is*
//!   the node of another, `2(xy + zw)`, negated.
//! - Products are flattened into `c · Π bᵢ^kᵢ` with integer exponents:
//!   `x · 1 = x`, `x · 0 = 0`, `x · x⁻¹ = 1`, `−(−x) = x`, `√x · √x = x`.
//! - Functions of constants are folded where they are defined (`√` of a
//!   non-negative, `ln` of a positive, `acos`/`asin` of a constant in
//!   `[−1, 1]`; outside, the node is kept and evaluates to NaN as `f64`
//!   does); `select` with equal arms is its arm.

use std::collections::BTreeMap;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::graph::{Expr, Node, Real, intern, node};

impl Expr {
    /// A literal.
    pub fn constant(value: f64) -> Expr {
        intern(Node::Const(Real::new(value)))
    }

    /// Input slot `i`.
    pub fn input(i: u32) -> Expr {
        intern(Node::Input(i))
    }

    /// The literal's value, if this is a constant.
    pub fn as_constant(self) -> Option<f64> {
        match node(self) {
            Node::Const(c) => Some(c.get()),
            _ => None,
        }
    }

    /// `c · self`.
    pub fn scale(self, c: f64) -> Expr {
        let mut product = Product::default();
        product.push(self, 1);
        product.coefficient *= c;
        product.build()
    }

    /// `selfⁿ`.
    pub fn powi(self, n: i32) -> Expr {
        let mut product = Product::default();
        product.push(self, n);
        product.build()
    }

    /// `1 / self`.
    pub fn recip(self) -> Expr {
        self.powi(-1)
    }

    /// `√self`.
    pub fn sqrt(self) -> Expr {
        match self.as_constant() {
            Some(c) if c >= 0.0 => Expr::constant(c.sqrt()),
            _ => intern(Node::Sqrt(self)),
        }
    }

    /// `sin self`.
    pub fn sin(self) -> Expr {
        match self.as_constant() {
            Some(c) => Expr::constant(c.sin()),
            None => intern(Node::Sin(self)),
        }
    }

    /// `cos self`.
    pub fn cos(self) -> Expr {
        match self.as_constant() {
            Some(c) => Expr::constant(c.cos()),
            None => intern(Node::Cos(self)),
        }
    }

    /// `e^self`.
    pub fn exp(self) -> Expr {
        match self.as_constant() {
            Some(c) => Expr::constant(c.exp()),
            None => intern(Node::Exp(self)),
        }
    }

    /// `ln self` (folded for a positive constant only, as [`Expr::sqrt`] is
    /// for a non-negative one).
    pub fn ln(self) -> Expr {
        match self.as_constant() {
            Some(c) if c > 0.0 => Expr::constant(c.ln()),
            _ => intern(Node::Ln(self)),
        }
    }

    /// `acos self` (folded for a constant in `[−1, 1]` only).
    pub fn acos(self) -> Expr {
        match self.as_constant() {
            Some(c) if c.abs() <= 1.0 => Expr::constant(c.acos()),
            _ => intern(Node::Acos(self)),
        }
    }

    /// `asin self` (folded for a constant in `[−1, 1]` only).
    pub fn asin(self) -> Expr {
        match self.as_constant() {
            Some(c) if c.abs() <= 1.0 => Expr::constant(c.asin()),
            _ => intern(Node::Asin(self)),
        }
    }

    /// `atan self`.
    pub fn atan(self) -> Expr {
        match self.as_constant() {
            Some(c) => Expr::constant(c.atan()),
            None => intern(Node::Atan(self)),
        }
    }

    /// `atan2(self, x)`.
    pub fn atan2(self, x: Expr) -> Expr {
        match (self.as_constant(), x.as_constant()) {
            (Some(y), Some(x)) => Expr::constant(y.atan2(x)),
            _ => intern(Node::Atan2(self, x)),
        }
    }

    /// `if lhs < rhs { if_less } else { otherwise }`.
    pub fn select_lt(lhs: Expr, rhs: Expr, if_less: Expr, otherwise: Expr) -> Expr {
        if if_less == otherwise {
            return if_less;
        }
        match (lhs.as_constant(), rhs.as_constant()) {
            (Some(l), Some(r)) => {
                if l < r {
                    if_less
                } else {
                    otherwise
                }
            }
            _ => intern(Node::Select {
                lhs,
                rhs,
                if_less,
                otherwise,
            }),
        }
    }
}

/// `lhs + coefficient · rhs` through the canonical sum.
fn sum(lhs: Expr, rhs: Expr, coefficient: f64) -> Expr {
    let mut sum = Sum::default();
    sum.push(lhs, 1.0);
    sum.push(rhs, coefficient);
    sum.build()
}

/// `lhs · rhs^exponent` through the canonical product.
fn product(lhs: Expr, rhs: Expr, exponent: i32) -> Expr {
    let mut product = Product::default();
    product.push(lhs, 1);
    product.push(rhs, exponent);
    product.build()
}

macro_rules! operator {
    ($trait:ident, $method:ident, $assign_trait:ident, $assign_method:ident, |$a:ident, $b:ident| $body:expr) => {
        impl $trait for Expr {
            type Output = Expr;
            fn $method(self, rhs: Expr) -> Expr {
                let ($a, $b) = (self, rhs);
                $body
            }
        }
        impl $assign_trait for Expr {
            fn $assign_method(&mut self, rhs: Expr) {
                *self = $trait::$method(*self, rhs);
            }
        }
    };
}

operator!(Add, add, AddAssign, add_assign, |a, b| sum(a, b, 1.0));
operator!(Sub, sub, SubAssign, sub_assign, |a, b| sum(a, b, -1.0));
operator!(Mul, mul, MulAssign, mul_assign, |a, b| product(a, b, 1));
operator!(Div, div, DivAssign, div_assign, |a, b| product(a, b, -1));

impl Neg for Expr {
    type Output = Expr;
    fn neg(self) -> Expr {
        self.scale(-1.0)
    }
}

/// A sum being collected.
#[derive(Default)]
struct Sum {
    constant: f64,
    terms: BTreeMap<Expr, f64>,
}

impl Sum {
    /// Adds `scale · e`, flattening sums and pulling coefficients out of products.
    fn push(&mut self, e: Expr, scale: f64) {
        match node(e) {
            Node::Const(c) => self.constant += scale * c.get(),
            Node::Add { constant, terms } => {
                self.constant += scale * constant.get();
                for (t, c) in terms.iter() {
                    *self.terms.entry(*t).or_insert(0.0) += scale * c.get();
                }
            }
            Node::Mul {
                coefficient,
                factors,
            } if coefficient.get() != 1.0 => {
                // c · Π  →  term Π with coefficient c (a scaled sum is flattened).
                let unit = Product {
                    coefficient: 1.0,
                    factors: factors.iter().copied().collect(),
                }
                .build();
                self.push(unit, scale * coefficient.get());
            }
            _ => *self.terms.entry(e).or_insert(0.0) += scale,
        }
    }

    fn build(mut self) -> Expr {
        self.terms.retain(|_, c| *c != 0.0);
        let mut terms = self.terms.into_iter();
        let Some((first, lead)) = terms.next() else {
            return Expr::constant(self.constant);
        };
        let rest: Vec<(Expr, f64)> = terms.collect();
        if rest.is_empty() && self.constant == 0.0 {
            return first.scale(lead);
        }
        let normalized = intern(Node::Add {
            constant: Real::new(self.constant / lead),
            terms: std::iter::once((first, Real::new(1.0)))
                .chain(rest.iter().map(|(t, c)| (*t, Real::new(c / lead))))
                .collect(),
        });
        if lead == 1.0 {
            normalized
        } else {
            normalized.scale(lead)
        }
    }
}

/// A product being collected.
struct Product {
    coefficient: f64,
    factors: BTreeMap<Expr, i32>,
}

impl Default for Product {
    fn default() -> Self {
        Product {
            coefficient: 1.0,
            factors: BTreeMap::new(),
        }
    }
}

impl Product {
    /// Multiplies by `e^exponent`, flattening products.
    fn push(&mut self, e: Expr, exponent: i32) {
        match node(e) {
            Node::Const(c) => self.coefficient *= c.get().powi(exponent),
            Node::Mul {
                coefficient,
                factors,
            } => {
                self.coefficient *= coefficient.get().powi(exponent);
                for (b, k) in factors.iter() {
                    *self.factors.entry(*b).or_insert(0) += k * exponent;
                }
            }
            _ => *self.factors.entry(e).or_insert(0) += exponent,
        }
    }

    /// Rewrites `(√x)^k` with `|k| ≥ 2` into powers of `x`.
    fn reduce_square_roots(&mut self) {
        loop {
            let found = self.factors.iter().find_map(|(b, k)| match node(*b) {
                Node::Sqrt(x) if k.abs() >= 2 => Some((*b, *k, x)),
                _ => None,
            });
            let Some((root, k, radicand)) = found else {
                return;
            };
            let whole = k / 2; // truncates toward zero: the remainder keeps k's sign
            self.factors.insert(root, k - 2 * whole);
            self.push(radicand, whole);
        }
    }

    fn build(mut self) -> Expr {
        self.reduce_square_roots();
        self.factors.retain(|_, k| *k != 0);
        if self.coefficient == 0.0 || self.factors.is_empty() {
            return Expr::constant(self.coefficient);
        }
        if self.coefficient == 1.0 && self.factors.len() == 1 {
            let (&b, &k) = self.factors.iter().next().expect("one factor");
            if k == 1 {
                return b;
            }
        }
        intern(Node::Mul {
            coefficient: Real::new(self.coefficient),
            factors: self.factors.into_iter().collect(),
        })
    }
}
