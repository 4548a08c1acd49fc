//! [`Expr`] implements [`Scalar`]: residuals and geometry are traced exactly
//! as they are written for `f64` and dual numbers (the arithmetic operators
//! are the canonical constructors of [`crate::algebra`]).

use num_traits::{One, Zero};

use crate::graph::Expr;
use factor_core::Scalar;

impl Zero for Expr {
    fn zero() -> Expr {
        Expr::constant(0.0)
    }
    fn is_zero(&self) -> bool {
        self.as_constant() == Some(0.0)
    }
}

impl One for Expr {
    fn one() -> Expr {
        Expr::constant(1.0)
    }
}

impl Scalar for Expr {
    fn from_f64(value: f64) -> Expr {
        Expr::constant(value)
    }
    fn sqrt(self) -> Expr {
        Expr::sqrt(self)
    }
    fn sin(self) -> Expr {
        Expr::sin(self)
    }
    fn cos(self) -> Expr {
        Expr::cos(self)
    }
    fn atan2(self, x: Expr) -> Expr {
        Expr::atan2(self, x)
    }
    fn exp(self) -> Expr {
        Expr::exp(self)
    }
    fn ln(self) -> Expr {
        Expr::ln(self)
    }
    fn acos(self) -> Expr {
        Expr::acos(self)
    }
    fn asin(self) -> Expr {
        Expr::asin(self)
    }
    fn atan(self) -> Expr {
        Expr::atan(self)
    }
    fn select_lt(lhs: Expr, rhs: Expr, if_less: Expr, otherwise: Expr) -> Expr {
        Expr::select_lt(lhs, rhs, if_less, otherwise)
    }
    fn recip(self) -> Expr {
        Expr::recip(self)
    }
}
