//! A high-precision reference: a factor's residual and Jacobians evaluated
//! in double-double arithmetic (crate `twofloat`: about 32 significant
//! digits for arithmetic and square roots, about 20 for the trigonometric,
//! exponential and logarithmic functions) from the same `f64` inputs, then
//! rounded to `f64`.
//!
//! It measures how accurate an `f64` evaluation is: the inputs are exact
//! binary numbers, so the reference is what an exact evaluation of the same
//! formula at the same inputs gives, to about `1e-19` relative or better
//! (less near a cancellation the reference itself meets). The derivatives are carried
//! forward by [`Precise`], a dual number over double-doubles, one tangent
//! direction at a time (num-dual's dual numbers are over `f32`/`f64` only).
//! The range is that of `f64`: inputs whose products overflow or underflow
//! there do so in the reference too.
//!
//! Only `twofloat` 0.8's arithmetic, square root, sine and cosine are used:
//! its division and the functions built on it (`atan2`, `atan`, `asin`,
//! `acos`) are accurate to about `f64` precision only (its reciprocal drops
//! the low word of `1 − b·(1/b)`), and its exponential and logarithm are off
//! by up to 1e-11 at some arguments (`e^−3`, `ln 0.357`). [`Precise`]
//! divides by long division, computes `atan2` by a Newton step on the sine
//! and cosine (the inverse functions through it), the exponential by its
//! Taylor series after reduction by `ln 2`, and the logarithm by a Newton
//! step on that; the unit tests hold every function to 1e-19 against
//! 50-digit values.

use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use factor_core::Scalar;
use factor_core::factor::{DynLinearization, Factor};
use nalgebra::{DMatrix, DVector};
use num_traits::{One, Zero};
use twofloat::TwoFloat;

/// A double-double value with its derivative along one direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Precise {
    /// The value.
    pub value: TwoFloat,
    /// Its derivative.
    pub derivative: TwoFloat,
}

impl Precise {
    /// A constant.
    pub fn constant(value: f64) -> Self {
        Precise {
            value: TwoFloat::from(value),
            derivative: TwoFloat::from(0.0),
        }
    }

    /// The variable of differentiation at `value`.
    pub fn variable(value: f64) -> Self {
        Precise {
            value: TwoFloat::from(value),
            derivative: TwoFloat::from(1.0),
        }
    }

    /// `f(self)` given `f(value)` and `f'(value)`.
    fn chain(self, value: TwoFloat, slope: TwoFloat) -> Self {
        Precise {
            value,
            derivative: slope * self.derivative,
        }
    }
}

impl Add for Precise {
    type Output = Self;
    fn add(self, rhs: Self) -> Self {
        Precise {
            value: self.value + rhs.value,
            derivative: self.derivative + rhs.derivative,
        }
    }
}

impl Sub for Precise {
    type Output = Self;
    fn sub(self, rhs: Self) -> Self {
        Precise {
            value: self.value - rhs.value,
            derivative: self.derivative - rhs.derivative,
        }
    }
}

impl Mul for Precise {
    type Output = Self;
    fn mul(self, rhs: Self) -> Self {
        Precise {
            value: self.value * rhs.value,
            derivative: self.derivative * rhs.value + self.value * rhs.derivative,
        }
    }
}

/// `a / b` to double-double accuracy: three quotient digits of long
/// division, each remainder formed exactly (`twofloat`'s product by an
/// `f64` is exact to the low word).
fn divide(a: TwoFloat, b: TwoFloat) -> TwoFloat {
    let q1 = a.hi() / b.hi();
    let r = a - b * q1;
    let q2 = r.hi() / b.hi();
    let r = r - b * q2;
    let q3 = r.hi() / b.hi();
    TwoFloat::new_add(q1, q2) + q3
}

/// `atan2(y, x)` to double-double accuracy: the `f64` angle corrected by
/// one Newton step, `θ + (y cos θ − x sin θ) / (x cos θ + y sin θ)`.
fn arctangent(y: TwoFloat, x: TwoFloat) -> TwoFloat {
    let theta = TwoFloat::from(y.hi().atan2(x.hi()));
    let (sin, cos) = theta.sin_cos();
    theta + divide(y * cos - x * sin, x * cos + y * sin)
}

/// `e^x` to double-double accuracy: `x = k ln 2 + r` with `|r| ≤ ln 2 / 2`,
/// `e^r` by its Taylor series to 30 terms (the next is below 1e-40), then
/// scaled by `2^k` exactly.
fn exponential(x: TwoFloat) -> TwoFloat {
    let k = (x.hi() / std::f64::consts::LN_2).round();
    let r = x - twofloat::consts::LN_2 * k;
    let (mut sum, mut term) = (TwoFloat::from(1.0), TwoFloat::from(1.0));
    for n in 1..30 {
        term = divide(term * r, TwoFloat::from(f64::from(n)));
        sum += term;
    }
    // 2^k by halves, so that neither factor overflows before the product.
    let half = 2.0_f64.powi((k / 2.0).trunc() as i32);
    let rest = 2.0_f64.powi((k - (k / 2.0).trunc()) as i32);
    sum * half * rest
}

/// `ln x` to double-double accuracy: the `f64` logarithm corrected by one
/// Newton step on the exponential, `y + x e^(−y) − 1`.
fn logarithm(x: TwoFloat) -> TwoFloat {
    let y = TwoFloat::from(x.hi().ln());
    y + divide(x, exponential(y)) - 1.0
}

impl Div for Precise {
    type Output = Self;
    fn div(self, rhs: Self) -> Self {
        let value = divide(self.value, rhs.value);
        Precise {
            value,
            derivative: divide(self.derivative - value * rhs.derivative, rhs.value),
        }
    }
}

impl Neg for Precise {
    type Output = Self;
    fn neg(self) -> Self {
        Precise {
            value: -self.value,
            derivative: -self.derivative,
        }
    }
}

macro_rules! assign {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for Precise {
            fn $method(&mut self, rhs: Self) {
                *self = *self $op rhs;
            }
        }
    };
}
assign!(AddAssign, add_assign, +);
assign!(SubAssign, sub_assign, -);
assign!(MulAssign, mul_assign, *);
assign!(DivAssign, div_assign, /);

impl Zero for Precise {
    fn zero() -> Self {
        Precise::constant(0.0)
    }
    fn is_zero(&self) -> bool {
        self.value == 0.0 && self.derivative == 0.0
    }
}

impl One for Precise {
    fn one() -> Self {
        Precise::constant(1.0)
    }
}

impl Scalar for Precise {
    fn from_f64(value: f64) -> Self {
        Precise::constant(value)
    }
    fn sqrt(self) -> Self {
        let root = self.value.sqrt();
        self.chain(root, divide(TwoFloat::from(0.5), root))
    }
    fn sin(self) -> Self {
        let (sin, cos) = self.value.sin_cos();
        self.chain(sin, cos)
    }
    fn cos(self) -> Self {
        let (sin, cos) = self.value.sin_cos();
        self.chain(cos, -sin)
    }
    fn atan2(self, x: Self) -> Self {
        let (y, xv) = (self.value, x.value);
        Precise {
            value: arctangent(y, xv),
            derivative: divide(xv * self.derivative - y * x.derivative, xv * xv + y * y),
        }
    }
    fn exp(self) -> Self {
        let e = exponential(self.value);
        self.chain(e, e)
    }
    fn ln(self) -> Self {
        let x = self.value;
        self.chain(logarithm(x), divide(TwoFloat::from(1.0), x))
    }
    fn acos(self) -> Self {
        let x = self.value;
        let root = ((1.0 - x) * (1.0 + x)).sqrt();
        self.chain(arctangent(root, x), -divide(TwoFloat::from(1.0), root))
    }
    fn asin(self) -> Self {
        let x = self.value;
        let root = ((1.0 - x) * (1.0 + x)).sqrt();
        self.chain(arctangent(x, root), divide(TwoFloat::from(1.0), root))
    }
    fn atan(self) -> Self {
        let x = self.value;
        self.chain(
            arctangent(x, TwoFloat::from(1.0)),
            divide(TwoFloat::from(1.0), 1.0 + x * x),
        )
    }
    fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
        if lhs.value < rhs.value {
            if_less
        } else {
            otherwise
        }
    }
}

/// The factor's residual and Jacobian blocks evaluated in double-double
/// arithmetic (see the module documentation), rounded to `f64`.
pub fn reference_linearization<F: Factor>(factor: &F) -> DynLinearization {
    let stored: Vec<Precise> = factor
        .to_scalars()
        .iter()
        .map(|&x| Precise::constant(x))
        .collect();
    let mut delta = vec![Precise::constant(0.0); F::TANGENT_DIM];
    let residual = F::perturbed_residual_over(&stored, &delta);
    let mut jacobians = Vec::new();
    let mut column = 0;
    for variable in F::variables() {
        let mut block = DMatrix::zeros(F::RESIDUAL_DIM, variable.tangent_dim);
        for k in 0..variable.tangent_dim {
            delta[column] = Precise::variable(0.0);
            let perturbed = F::perturbed_residual_over(&stored, &delta);
            for (row, entry) in perturbed.iter().enumerate() {
                block[(row, k)] = entry.derivative.hi();
            }
            delta[column] = Precise::constant(0.0);
            column += 1;
        }
        jacobians.push(block);
    }
    DynLinearization {
        residual: DVector::from_iterator(residual.len(), residual.iter().map(|r| r.value.hi())),
        jacobians,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each function's value and derivative at `x = 0.7` (`atan2(0.7, −0.3)`
    /// for `atan2`, differentiated in `y`) against 50-digit values from
    /// mpmath, written as double-doubles `(hi, lo)`: agreement to 1e-19
    /// (measured: 0 to 6e-33 for the square root, the derivatives of the
    /// inverse functions and of `atan2`; 4e-22 to 1.4e-21 for values through
    /// the sine and cosine).
    #[test]
    fn functions_and_derivatives_are_double_double_accurate() {
        type Pair = (f64, f64);
        let x = Precise::variable(0.7);
        let cases: [(&str, Precise, Pair, Pair); 9] = [
            (
                "sqrt",
                x.sqrt(),
                (0.8366600265340756, -4.12265279558505e-17),
                (0.5976143046671969, -5.497539789636644e-17),
            ),
            (
                "atan2",
                x.atan2(Precise::constant(-0.3)),
                (1.9756881130799802, -1.0502421050460647e-16),
                (-0.5172413793103449, -7.788722764908949e-18),
            ),
            (
                "sin",
                x.sin(),
                (0.644217687237691, 2.8740567927338755e-18),
                (0.7648421872844885, -4.013780434022238e-17),
            ),
            (
                "cos",
                x.cos(),
                (0.7648421872844885, -4.013780434022238e-17),
                (-0.644217687237691, -2.8740567927338755e-18),
            ),
            (
                "exp",
                x.exp(),
                (2.0137527074704766, -2.0058243549764793e-16),
                (2.0137527074704766, -2.0058243549764793e-16),
            ),
            (
                "ln",
                x.ln(),
                (-0.35667494393873245, 4.82556379937662e-18),
                (1.4285714285714286, 5.890979314337566e-17),
            ),
            (
                "acos",
                x.acos(),
                (0.7953988301841436, 2.7282065511033407e-17),
                (-1.4002800840280096, -8.756291299229982e-17),
            ),
            (
                "asin",
                x.asin(),
                (0.775397496610753, 3.395027444633425e-17),
                (1.4002800840280096, 8.756291299229982e-17),
            ),
            (
                "atan",
                x.atan(),
                (0.6107259643892086, 2.2418914462967458e-17),
                (0.6711409395973155, -2.545396691744537e-18),
            ),
        ];
        for (name, got, value, derivative) in cases {
            for (what, got, (hi, lo)) in [
                ("value", got.value, value),
                ("derivative", got.derivative, derivative),
            ] {
                let error = (got - TwoFloat::new_add(hi, lo)).hi().abs() / hi.abs();
                assert!(error < 1e-19, "{name} {what}: relative error {error:e}");
            }
        }
    }

    /// `sin`, `cos`, `exp`, `ln |x|` and `atan2(x, 0.4)` at seven arguments
    /// against 50-digit mpmath values: agreement to 1e-19 relative
    /// (measured: 8e-21 at worst, `sin(−3)`).
    #[test]
    fn transcendental_values_are_accurate_to_1e_19() {
        type Pair = (f64, f64);
        let cases: [(f64, [Pair; 5]); 7] = [
            (
                0.7,
                [
                    (0.644217687237691, 2.8740567927338755e-18),
                    (0.7648421872844885, -4.013780434022238e-17),
                    (2.0137527074704766, -2.0058243549764793e-16),
                    (-0.35667494393873245, 4.82556379937662e-18),
                    (1.0516502125483735, 7.429789493534895e-17),
                ],
            ),
            (
                -0.357,
                [
                    (-0.3494649617827292, 2.1721412859821433e-17),
                    (0.9369494332599789, -2.785892742557161e-17),
                    (0.699772497734611, -1.2364919083266131e-17),
                    (-1.030019497202498, 5.987147534481843e-17),
                    (-0.728655968691273, 1.6942959033150357e-17),
                ],
            ),
            (
                2.5,
                [
                    (0.5984721441039565, -5.521403334082375e-17),
                    (-0.8011436155469337, -1.8674742705085553e-17),
                    (12.182493960703473, 2.0334002173348147e-16),
                    (0.9162907318741551, -4.141195369011963e-17),
                    (1.4121410646084953, -1.0439815710108828e-16),
                ],
            ),
            (
                0.001,
                [
                    (0.0009999998333333417, 5.670638989736153e-21),
                    (0.9999995000000417, -7.831485455398128e-18),
                    (1.0010005001667084, -4.290842058948394e-17),
                    (-6.907755278982137, -2.1613487097372872e-16),
                    (0.0024999947916861977, 6.674336033108658e-20),
                ],
            ),
            (
                0.999,
                [
                    (0.8409302618566215, -4.9060276199915334e-17),
                    (0.5411435065615721, -2.6927459041151263e-17),
                    (2.715564905318567, -1.8351063088557945e-16),
                    (-0.0010005003335835344, -2.5644777003677798e-20),
                    (1.1899448245883828, 8.860953732306232e-17),
                ],
            ),
            (
                -3.0,
                [
                    (-0.1411200080598672, -8.577269787017502e-18),
                    (-0.9899924966004454, -4.2060261566099734e-17),
                    (0.049787068367863944, -1.4831389691394365e-18),
                    (1.0986122886681098, -9.07129723500153e-17),
                    (-1.4382447944982226, 3.2202402320714365e-17),
                ],
            ),
            (
                12.0,
                [
                    (-0.5365729180004349, -3.19871738204447e-17),
                    (0.8438539587324921, -3.295262919928604e-17),
                    (162754.79141900392, 5.30065881322063e-12),
                    (2.4849066497880004, -4.433203607308931e-17),
                    (1.5374753309166493, 7.932026798659384e-17),
                ],
            ),
        ];
        for (a, expected) in cases {
            let x = Precise::constant(a);
            let got = [
                x.sin(),
                x.cos(),
                x.exp(),
                Precise::constant(a.abs()).ln(),
                x.atan2(Precise::constant(0.4)),
            ];
            for (name, (got, (hi, lo))) in ["sin", "cos", "exp", "ln", "atan2"]
                .iter()
                .zip(got.into_iter().zip(expected))
            {
                let error = (got.value - TwoFloat::new_add(hi, lo)).hi().abs() / hi.abs();
                assert!(error < 1e-19, "{name}({a}): relative error {error:e}");
            }
        }
    }
}
