//! Scalar `Real`s to check lane kernels against: the scalar type with its
//! `sin`, `cos` and `atan2` (the operations that are not correctly rounded)
//! chosen by a marker type.

use core::cell::{Cell, RefCell};
use core::marker::PhantomData;
use core::ops::{Add, Div, Mul, Neg, Sub};

use super::lanes::Lanes;
use super::ulp::Ulp;
use crate::Real;

/// How a [`Scalar`] computes `sin`, `cos` and `atan2`.
pub trait Functions<S> {
    fn sin(x: S) -> S;
    fn cos(x: S) -> S;
    fn atan2(y: S, x: S) -> S;
}

/// The lane type `L`'s own functions, on a splat, read from lane 0: the
/// scalar counterpart of a lane kernel, which must then match it exactly.
pub struct ThroughLanes<L>(PhantomData<L>);

impl<L: Lanes + Real> Functions<L::S> for ThroughLanes<L> {
    fn sin(x: L::S) -> L::S {
        Real::sin(L::from_lanes(&vec![x; L::N])).lanes()[0]
    }
    fn cos(x: L::S) -> L::S {
        Real::cos(L::from_lanes(&vec![x; L::N])).lanes()[0]
    }
    fn atan2(y: L::S, x: L::S) -> L::S {
        Real::atan2(L::from_lanes(&vec![y; L::N]), L::from_lanes(&vec![x; L::N])).lanes()[0]
    }
}

/// `std`'s functions.
pub struct Std;

impl<S: Real> Functions<S> for Std {
    fn sin(x: S) -> S {
        x.sin()
    }
    fn cos(x: S) -> S {
        x.cos()
    }
    fn atan2(y: S, x: S) -> S {
        y.atan2(x)
    }
}

/// `std`'s `atan2` with its result moved [`set_atan2_steps`] representable
/// values (the kernels that use it have no `sin` or `cos`).
pub struct NudgedAtan2;

thread_local! {
    static ATAN2_STEPS: Cell<i64> = const { Cell::new(0) };
}

/// How many representable values [`NudgedAtan2`] moves `atan2` on this thread.
pub fn set_atan2_steps(steps: i64) {
    ATAN2_STEPS.with(|s| s.set(steps));
}

impl<S: Real + Ulp> Functions<S> for NudgedAtan2 {
    fn sin(x: S) -> S {
        x.sin()
    }
    fn cos(x: S) -> S {
        x.cos()
    }
    fn atan2(y: S, x: S) -> S {
        y.atan2(x).nudged(ATAN2_STEPS.with(Cell::get))
    }
}

/// The scalar `S` with the functions of `F`.
pub struct Scalar<S, F>(pub S, PhantomData<F>);

impl<S, F> Scalar<S, F> {
    pub fn new(s: S) -> Self {
        Scalar(s, PhantomData)
    }
}

impl<S: Copy, F> Clone for Scalar<S, F> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<S: Copy, F> Copy for Scalar<S, F> {}

macro_rules! scalar_op {
    ($trait:ident, $method:ident) => {
        impl<S: Real, F> $trait for Scalar<S, F> {
            type Output = Self;
            fn $method(self, rhs: Self) -> Self {
                Self::new($trait::$method(self.0, rhs.0))
            }
        }
    };
}

scalar_op!(Add, add);
scalar_op!(Sub, sub);
scalar_op!(Mul, mul);
scalar_op!(Div, div);

impl<S: Real, F> Neg for Scalar<S, F> {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.0)
    }
}

impl<S: Real + PartialOrd, F: Functions<S>> Real for Scalar<S, F> {
    fn constant(c: f64) -> Self {
        Self::new(S::constant(c))
    }
    fn sqrt(self) -> Self {
        Self::new(self.0.sqrt())
    }
    fn sin(self) -> Self {
        Self::new(F::sin(self.0))
    }
    fn cos(self) -> Self {
        Self::new(F::cos(self.0))
    }
    fn atan2(self, x: Self) -> Self {
        Self::new(F::atan2(self.0, x.0))
    }
    fn exp(self) -> Self {
        Self::new(self.0.exp())
    }
    fn ln(self) -> Self {
        Self::new(self.0.ln())
    }
    fn acos(self) -> Self {
        Self::new(self.0.acos())
    }
    fn asin(self) -> Self {
        Self::new(self.0.asin())
    }
    fn atan(self) -> Self {
        Self::new(self.0.atan())
    }
    fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
        SELECTIONS.with(|s| s.borrow_mut().push(lhs.0 < rhs.0));
        Self::new(S::select_lt(lhs.0, rhs.0, if_less.0, otherwise.0))
    }
}

thread_local! {
    /// Every `select_lt` a [`Scalar`] evaluated on this thread, in order:
    /// whether `lhs < rhs`.
    static SELECTIONS: RefCell<Vec<bool>> = const { RefCell::new(Vec::new()) };
}

/// The outcomes of the `select_lt`s evaluated on this thread since the last
/// call, in order.
pub fn take_selections() -> Vec<bool> {
    SELECTIONS.with(|s| s.take())
}
