//! [`Dual`]: forward-mode dual numbers whose derivative is a plain array on
//! the stack, the number type of every dual-number linearization.
//!
//! `Dual<N>` is a value `re` and its derivative `eps` w.r.t. `N` tangent
//! coordinates, `[f64; N]`: the layout of Ceres' `Jet<double, N>`. Every
//! operation is a loop over `N` known at compile time, inlined, so the
//! compiler keeps the derivative in vector registers and emits no call and
//! no branch per operation.
//!
//! Why not num-dual's `DualSVec64<N>` (which this crate used before, and
//! whose [`Scalar`] impl stays for code that uses it): its derivative is an
//! `Option<SVector<f64, N>>`, `None` for a constant. Every operation then
//! matches the two options (four cases), its operators are not marked
//! `#[inline]` and were called out of line, and the option's tag makes each
//! value 8 bytes wider and every move a `memcpy`. Profiled on the Snavely
//! reprojection (callgrind, 4 096 observations, `linearize_dual`), 14% of
//! the instructions were `Derivative::add` alone and 11% `memcpy`: about
//! 17 000 instructions per linearization, 20× Ceres' `Jet` on the same
//! residual. The sparsity the option tracks (constants carry no derivative)
//! saves nothing once the variables are seeded: almost every intermediate
//! depends on a variable.
//!
//! With `target_feature = "fma"` (a build for the machine, `-C
//! target-cpu=native`), products added to a derivative are fused
//! multiply-adds, as GCC and Clang contract Ceres' `Jet` arithmetic.
//!
//! Rotating a vector by a quaternion, the operation the factors spend most
//! of their dual arithmetic on, is not traced through the rotation matrix's
//! dual entries: [`Scalar::rotate_by_quaternion`] computes the value and
//! the derivatives w.r.t. the quaternion in `f64` and applies the chain
//! rule per coordinate (about 2.3× fewer operations; profiled, it took
//! half of the point and free-line factors' time before).

use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use num_traits::{One, Zero};

use nalgebra::Vector3;

use crate::linalg::{cross, dot, homogeneous_rotation};
use crate::scalar::Scalar;

/// A dual number: a value and its derivative w.r.t. `N` coordinates.
///
/// ```
/// use factor_core::Scalar;
/// use factor_core::dual::Dual;
///
/// // d/dx and d/dy of √(x² + y²) at (3, 4).
/// let (x, y) = (Dual::<2>::variable(3.0, 0), Dual::<2>::variable(4.0, 1));
/// let r = (x * x + y * y).sqrt();
/// assert_eq!(r.re, 5.0);
/// assert!((r.eps[0] - 0.6).abs() < 1e-15 && (r.eps[1] - 0.8).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dual<const N: usize> {
    /// The value.
    pub re: f64,
    /// The derivative w.r.t. each coordinate.
    pub eps: [f64; N],
}

/// `a · b + c`, fused where the target has FMA (one rounding, as compilers
/// contract Ceres' `Jet` arithmetic), else a product and a sum.
#[inline(always)]
fn mul_add(a: f64, b: f64, c: f64) -> f64 {
    #[cfg(target_feature = "fma")]
    {
        a.mul_add(b, c)
    }
    #[cfg(not(target_feature = "fma"))]
    {
        a * b + c
    }
}

impl<const N: usize> Dual<N> {
    /// A constant: derivative zero.
    #[inline(always)]
    pub const fn constant(re: f64) -> Self {
        Dual { re, eps: [0.0; N] }
    }

    /// Coordinate `k` itself at the value `re`: derivative `e_k`.
    ///
    /// # Panics
    ///
    /// If `k >= N`.
    #[inline(always)]
    pub fn variable(re: f64, k: usize) -> Self {
        let mut eps = [0.0; N];
        eps[k] = 1.0;
        Dual { re, eps }
    }

    /// The same number with its derivative placed at coordinates
    /// `offset..offset + N` of `M` (the others zero): a variable's own
    /// tangent inside a factor's stacked tangent.
    ///
    /// # Panics
    ///
    /// If `offset + N > M`.
    #[inline(always)]
    pub fn widen<const M: usize>(self, offset: usize) -> Dual<M> {
        let mut eps = [0.0; M];
        eps[offset..offset + N].copy_from_slice(&self.eps);
        Dual { re: self.re, eps }
    }

    /// `f(x)` from `f(re)` and `f'(re)`: the chain rule.
    #[inline(always)]
    fn chain(self, value: f64, slope: f64) -> Self {
        Dual {
            re: value,
            eps: self.eps.map(|e| e * slope),
        }
    }

    /// `a · self + b · other` on the derivatives, `re` given.
    #[inline(always)]
    fn combine(re: f64, a: f64, x: &[f64; N], b: f64, y: &[f64; N]) -> Self {
        let mut eps = [0.0; N];
        for i in 0..N {
            eps[i] = mul_add(a, x[i], b * y[i]);
        }
        Dual { re, eps }
    }
}

impl<const N: usize> Add for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, rhs: Self) -> Self {
        self += rhs;
        self
    }
}

impl<const N: usize> AddAssign for Dual<N> {
    #[inline(always)]
    fn add_assign(&mut self, rhs: Self) {
        self.re += rhs.re;
        for i in 0..N {
            self.eps[i] += rhs.eps[i];
        }
    }
}

impl<const N: usize> Sub for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, rhs: Self) -> Self {
        self -= rhs;
        self
    }
}

impl<const N: usize> SubAssign for Dual<N> {
    #[inline(always)]
    fn sub_assign(&mut self, rhs: Self) {
        self.re -= rhs.re;
        for i in 0..N {
            self.eps[i] -= rhs.eps[i];
        }
    }
}

impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    /// `(a b)' = a b' + b a'`.
    #[inline(always)]
    fn mul(self, rhs: Self) -> Self {
        Self::combine(self.re * rhs.re, self.re, &rhs.eps, rhs.re, &self.eps)
    }
}

impl<const N: usize> MulAssign for Dual<N> {
    #[inline(always)]
    fn mul_assign(&mut self, rhs: Self) {
        *self = *self * rhs;
    }
}

impl<const N: usize> Div for Dual<N> {
    type Output = Self;
    /// `(a/b)' = (a' − (a/b) b')/b`: one division, then products.
    #[inline(always)]
    fn div(self, rhs: Self) -> Self {
        let inverse = 1.0 / rhs.re;
        let re = self.re * inverse;
        let eps = std::array::from_fn(|i| mul_add(-re, rhs.eps[i], self.eps[i]) * inverse);
        Dual { re, eps }
    }
}

impl<const N: usize> DivAssign for Dual<N> {
    #[inline(always)]
    fn div_assign(&mut self, rhs: Self) {
        *self = *self / rhs;
    }
}

impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Dual {
            re: -self.re,
            eps: self.eps.map(|e| -e),
        }
    }
}

impl<const N: usize> Zero for Dual<N> {
    #[inline(always)]
    fn zero() -> Self {
        Self::constant(0.0)
    }
    fn is_zero(&self) -> bool {
        self.re == 0.0 && self.eps.iter().all(|e| *e == 0.0)
    }
}

impl<const N: usize> One for Dual<N> {
    #[inline(always)]
    fn one() -> Self {
        Self::constant(1.0)
    }
}

/// A branch compares real parts and returns the chosen arm whole, so the
/// derivative is the derivative of the branch that holds at the point.
impl<const N: usize> Scalar for Dual<N> {
    #[inline(always)]
    fn from_f64(value: f64) -> Self {
        Self::constant(value)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        let root = self.re.sqrt();
        self.chain(root, 0.5 / root)
    }
    #[inline(always)]
    fn sin(self) -> Self {
        let (sin, cos) = self.re.sin_cos();
        self.chain(sin, cos)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        let (sin, cos) = self.re.sin_cos();
        self.chain(cos, -sin)
    }
    /// `atan2` with the derivative `(x dy − y dx) / (x² + y²)`, finite where
    /// `x = 0` (the quaternion logarithm at an angle of exactly π).
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        let inverse = 1.0 / (self.re * self.re + x.re * x.re);
        Self::combine(
            self.re.atan2(x.re),
            x.re * inverse,
            &self.eps,
            -self.re * inverse,
            &x.eps,
        )
    }
    #[inline(always)]
    fn exp(self) -> Self {
        let e = self.re.exp();
        self.chain(e, e)
    }
    #[inline(always)]
    fn ln(self) -> Self {
        self.chain(self.re.ln(), 1.0 / self.re)
    }
    /// `acos` with the derivative `−1/√((1 − x)(1 + x))`: `1 − x` and
    /// `1 + x` are exact near `|x| = 1`, where `1 − x²` loses up to 2e-9 of
    /// relative accuracy. At `x = ±1` the derivative is infinite: seeded
    /// directions get `∓∞`, unseeded ones `0 · ∞ = NaN`.
    #[inline(always)]
    fn acos(self) -> Self {
        let x = self.re;
        self.chain(x.acos(), -((1.0 - x) * (1.0 + x)).sqrt().recip())
    }
    /// `asin` with the derivative `1/√((1 − x)(1 + x))`, written out for the
    /// reason given for `acos`.
    #[inline(always)]
    fn asin(self) -> Self {
        let x = self.re;
        self.chain(x.asin(), ((1.0 - x) * (1.0 + x)).sqrt().recip())
    }
    #[inline(always)]
    fn atan(self) -> Self {
        let x = self.re;
        self.chain(x.atan(), 1.0 / (1.0 + x * x))
    }
    #[inline(always)]
    fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
        if lhs.re < rhs.re { if_less } else { otherwise }
    }
    #[inline(always)]
    fn recip(self) -> Self {
        let inverse = 1.0 / self.re;
        self.chain(inverse, -inverse * inverse)
    }
    #[inline(always)]
    fn known_value(self) -> Option<f64> {
        Some(self.re)
    }
    #[inline(always)]
    fn rotate_by_quaternion(q: &[Self; 4], v: &[Self; 3], transpose: bool) -> Option<[Self; 3]> {
        Some(rotate(q, v, transpose))
    }
}

/// `R(q) v`, or `R(q)ᵀ v` when `transpose`, `R` the homogeneous rotation
/// matrix of `q = [x, y, z, w]`, by the chain rule: the value, `R` and the
/// 3 × 4 derivative `∂(R v)/∂q` in `f64`, then per coordinate
/// `d(R v) = ∂(R v)/∂q · dq + R dv`: 21 multiply-adds per coordinate, where
/// the matrix's entries on dual numbers and their product with `v` take
/// about 96 operations per coordinate.
///
/// With `q = [u, w]`, `R v = (w² − u·u) v + 2 (u·v) u + 2 w (u × v)`, so
/// `∂(R v)/∂u = 2 ((u·v) I + u vᵀ − v uᵀ − w [v]×)` and
/// `∂(R v)/∂w = 2 (w v + u × v)`. `R(q)ᵀ = R(q̄)`, `q̄ = [−u, w]`: the
/// transpose rotates by `q̄`, and its derivative w.r.t. `u` changes sign.
#[inline(always)]
fn rotate<const N: usize>(q: &[Dual<N>; 4], v: &[Dual<N>; 3], transpose: bool) -> [Dual<N>; 3] {
    let sign = if transpose { -1.0 } else { 1.0 };
    let u = [sign * q[0].re, sign * q[1].re, sign * q[2].re];
    let w = q[3].re;
    let p = [v[0].re, v[1].re, v[2].re];
    let r = homogeneous_rotation(u[0], u[1], u[2], w);
    let (u_vector, p_vector) = (Vector3::from(u), Vector3::from(p));
    let up = dot(&u_vector, &p_vector);
    let u_cross_p = cross(&u_vector, &p_vector);
    let p_cross = [[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]];
    let mut out = [Dual::constant(0.0); 3];
    for (i, out) in out.iter_mut().enumerate() {
        let mut j = [0.0; 4];
        for (k, jk) in j.iter_mut().take(3).enumerate() {
            let diagonal = if i == k { up } else { 0.0 };
            *jk = 2.0 * sign * (diagonal + u[i] * p[k] - p[i] * u[k] - w * p_cross[i][k]);
        }
        j[3] = 2.0 * (w * p[i] + u_cross_p[i]);
        let row = [r[(i, 0)], r[(i, 1)], r[(i, 2)]];
        out.re = row[0] * p[0] + row[1] * p[1] + row[2] * p[2];
        for (n, e) in out.eps.iter_mut().enumerate() {
            let d = j[0] * q[0].eps[n];
            let d = mul_add(j[1], q[1].eps[n], d);
            let d = mul_add(j[2], q[2].eps[n], d);
            let d = mul_add(j[3], q[3].eps[n], d);
            let d = mul_add(row[0], v[0].eps[n], d);
            let d = mul_add(row[1], v[1].eps[n], d);
            *e = mul_add(row[2], v[2].eps[n], d);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::{mul, tr_mul};

    /// The chain-rule rotation against the homogeneous matrix multiplied out
    /// on dual numbers, for unit and non-unit quaternions, every input
    /// seeded on its own coordinates and on shared ones.
    #[test]
    fn rotation_by_the_chain_rule_is_the_matrix_product() {
        let quaternions = [
            [0.3, -0.5, 0.1, 0.8],
            [1.7, 0.2, -2.4, 0.6],
            [0.0, 0.0, 0.0, 1.0],
        ];
        let vectors = [[1.5, -2.0, 0.7], [-0.2, 0.0, 3.3]];
        for q in quaternions {
            for p in vectors {
                // Seeds: q on coordinates 0–3, v on 4–6, and coordinate 7 on all.
                let q: [Dual<8>; 4] = std::array::from_fn(|k| {
                    let mut d = Dual::variable(q[k], k);
                    d.eps[7] = 0.25 * (k as f64 + 1.0);
                    d
                });
                let v: [Dual<8>; 3] = std::array::from_fn(|k| {
                    let mut d = Dual::variable(p[k], 4 + k);
                    d.eps[7] = -0.5 * (k as f64) + 0.3;
                    d
                });
                let r = homogeneous_rotation(q[0], q[1], q[2], q[3]);
                let vector = Vector3::new(v[0], v[1], v[2]);
                for (transpose, reference) in
                    [(false, mul(&r, &vector)), (true, tr_mul(&r, &vector))]
                {
                    let ours = Dual::rotate_by_quaternion(&q, &v, transpose).unwrap();
                    for i in 0..3 {
                        let scale = 1.0 + reference[i].re.abs();
                        assert!((ours[i].re - reference[i].re).abs() < 1e-14 * scale);
                        for n in 0..8 {
                            let scale = 1.0 + reference[i].eps[n].abs();
                            assert!(
                                (ours[i].eps[n] - reference[i].eps[n]).abs() < 1e-13 * scale,
                                "q {q:?} v {p:?} transpose {transpose}: entry {i}, coordinate {n}: \
                                 {} against {}",
                                ours[i].eps[n],
                                reference[i].eps[n]
                            );
                        }
                    }
                }
            }
        }
    }

    fn d1(x: f64) -> Dual<1> {
        Dual::variable(x, 0)
    }

    #[test]
    fn the_known_value_is_the_real_part() {
        assert_eq!(Dual::<2>::variable(3.0, 1).known_value(), Some(3.0));
    }

    #[test]
    fn arithmetic_follows_the_rules_of_differentiation() {
        let (a, b) = (Dual::<2>::variable(3.0, 0), Dual::<2>::variable(-2.0, 1));
        assert_eq!(
            a + b,
            Dual {
                re: 1.0,
                eps: [1.0, 1.0]
            }
        );
        assert_eq!(
            a - b,
            Dual {
                re: 5.0,
                eps: [1.0, -1.0]
            }
        );
        assert_eq!(
            a * b,
            Dual {
                re: -6.0,
                eps: [-2.0, 3.0]
            }
        );
        // d(a/b) = (1/b, −a/b²).
        assert_eq!(
            a / b,
            Dual {
                re: -1.5,
                eps: [-0.5, -0.75]
            }
        );
        assert_eq!(
            -a,
            Dual {
                re: -3.0,
                eps: [-1.0, 0.0]
            }
        );
        assert_eq!(
            a.recip(),
            Dual {
                re: 1.0 / 3.0,
                eps: [-1.0 / 9.0, 0.0]
            }
        );
    }

    /// The derivatives of the library functions against forms independent of
    /// the implementation: `sin' = cos`, `exp' = exp`, `ln' = 1/x`,
    /// `acos' = −asin' = −1/sin(acos |x|)`, `atan' = cos²(atan x)`,
    /// `√' = 1/(2√x)`. Near `|x| = 1` `acos'` and `asin'` keep full relative
    /// accuracy.
    #[test]
    fn library_functions_have_exact_derivatives() {
        let near_one = [1e-6_f64.cos(), 1.0 - 1.3e-8];
        let inside = [-0.9, -0.3, 0.0, 0.2, 0.7];
        for x in inside
            .into_iter()
            .chain(near_one.iter().flat_map(|x| [*x, -x]))
        {
            let root = x.abs().acos().sin();
            let cases = [
                ("acos", Scalar::acos(d1(x)), x.acos(), -1.0 / root),
                ("asin", Scalar::asin(d1(x)), x.asin(), 1.0 / root),
                (
                    "atan",
                    Scalar::atan(d1(x)),
                    x.atan(),
                    x.atan().cos().powi(2),
                ),
                ("exp", Scalar::exp(d1(x)), x.exp(), x.exp()),
                ("sin", Scalar::sin(d1(x)), x.sin(), x.cos()),
                ("cos", Scalar::cos(d1(x)), x.cos(), -x.sin()),
            ];
            for (name, y, value, slope) in cases {
                assert_eq!(y.re, value, "{name}({x})");
                let error = (y.eps[0] - slope).abs() / slope.abs().max(1e-300);
                assert!(error < 4e-16, "{name}'({x}): relative error {error:e}");
            }
            if x > 0.0 {
                let (ln, sqrt) = (Scalar::ln(d1(x)), Scalar::sqrt(d1(x)));
                assert_eq!((ln.re, sqrt.re), (x.ln(), x.sqrt()));
                assert!((ln.eps[0] * x - 1.0).abs() < 4e-16);
                assert!((sqrt.eps[0] * 2.0 * x.sqrt() - 1.0).abs() < 4e-16);
            }
        }
    }

    #[test]
    fn atan2_is_differentiable_where_x_is_zero() {
        for (y, x) in [(1.5, 0.0), (-0.5, 0.0), (0.3, -2.0), (2.0, 1.0)] {
            let a = Scalar::atan2(Dual::<2>::variable(y, 0), Dual::<2>::variable(x, 1));
            let r2 = x * x + y * y;
            assert_eq!(a.re, f64::atan2(y, x));
            assert!((a.eps[0] - x / r2).abs() < 1e-15 && (a.eps[1] + y / r2).abs() < 1e-15);
        }
    }

    #[test]
    fn acos_and_asin_have_infinite_slopes_at_the_ends() {
        for x in [1.0, -1.0] {
            assert_eq!(Scalar::acos(d1(x)).eps[0], f64::NEG_INFINITY);
            assert_eq!(Scalar::asin(d1(x)).eps[0], f64::INFINITY);
        }
    }

    #[test]
    fn select_returns_the_branch_that_holds_with_its_derivative() {
        let y = d1(-2.0).abs();
        assert_eq!((y.re, y.eps[0]), (2.0, -1.0));
        let tie = Dual::<1>::select_lt(d1(1.0), d1(1.0), d1(5.0), -d1(7.0));
        assert_eq!(tie.re, -7.0);
    }

    #[test]
    fn widening_places_the_derivative_at_its_offset() {
        let x = Dual::<2> {
            re: 1.5,
            eps: [2.0, 3.0],
        };
        assert_eq!(
            x.widen::<5>(2),
            Dual {
                re: 1.5,
                eps: [0.0, 0.0, 2.0, 3.0, 0.0]
            }
        );
    }
}
