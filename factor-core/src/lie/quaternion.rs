//! Quaternions `[x, y, z, w]` with the Hamilton product, generic over the scalar.
//!
//! Document 000 (§I) writes `q = (q_v, q_4)` and `q ⊕ q'` for what is the
//! Hamilton product `q ⊗ q'` here. Its quaternion `exp` and `log` are defined
//! on the whole sphere: [`Quaternion::log`] does not identify `q` with `−q`
//! (an infinite plane or the plane factor's error needs the full sphere, with
//! `log(exp(ω)) = ω` for `|ω| < 2π`); [`crate::lie::So3::log`] does.

use nalgebra::{Matrix3, Vector3, Vector4};

use crate::lie::SMALL_ANGLE_SQUARED;
use crate::linalg::{cross, dot, homogeneous_rotation, scale, scaled_norm, squared_norm};
use crate::scalar::Scalar;
use crate::storage::{Layout, QUATERNION_NORM_TOLERANCE, Storage, StorageError};
use crate::validation::magnitude_text;

/// A quaternion `x i + y j + z k + w`, stored vector part first.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quaternion<S> {
    /// `i` coefficient.
    pub x: S,
    /// `j` coefficient.
    pub y: S,
    /// `k` coefficient.
    pub z: S,
    /// Real part.
    pub w: S,
}

impl<S: Scalar> Quaternion<S> {
    /// From coefficients in storage order `[x, y, z, w]`.
    pub fn new(x: S, y: S, z: S, w: S) -> Self {
        Quaternion { x, y, z, w }
    }

    /// The identity rotation `[0, 0, 0, 1]`.
    pub fn identity() -> Self {
        Self::new(S::zero(), S::zero(), S::zero(), S::one())
    }

    /// From vector part and real part.
    pub fn from_parts(vector: Vector3<S>, w: S) -> Self {
        Self::new(vector.x, vector.y, vector.z, w)
    }

    /// From `[x, y, z, w]`.
    pub fn from_coords(c: Vector4<S>) -> Self {
        Self::new(c[0], c[1], c[2], c[3])
    }

    /// `[x, y, z, w]`.
    pub fn coords(&self) -> Vector4<S> {
        Vector4::new(self.x, self.y, self.z, self.w)
    }

    /// The vector part `[x, y, z]`.
    pub fn vector(&self) -> Vector3<S> {
        Vector3::new(self.x, self.y, self.z)
    }

    /// Hamilton product `self ⊗ rhs`:
    /// `[w₁ v₂ + w₂ v₁ + v₁ × v₂, w₁ w₂ − v₁ · v₂]`.
    pub fn mul(&self, rhs: &Self) -> Self {
        let (a, b) = (self.vector(), rhs.vector());
        let v = scale(self.w, &b) + scale(rhs.w, &a) + cross(&a, &b);
        Self::from_parts(v, self.w * rhs.w - dot(&a, &b))
    }

    /// Conjugate `[−v, w]`, the inverse of a unit quaternion (document 000 §I).
    pub fn conjugate(&self) -> Self {
        Self::new(-self.x, -self.y, -self.z, self.w)
    }

    /// `−q`, the same rotation on the other sheet of the double cover.
    pub fn negated(&self) -> Self {
        Self::new(-self.x, -self.y, -self.z, -self.w)
    }

    /// `x² + y² + z² + w²`.
    pub fn squared_norm(&self) -> S {
        squared_norm(&self.coords())
    }

    /// Inverse `q* / |q|²`, for any non-zero quaternion.
    pub fn inverse(&self) -> Self {
        let inv = self.squared_norm().recip();
        Self::from_coords(scale(inv, &self.conjugate().coords()))
    }

    /// `q / |q|`.
    pub fn normalized(&self) -> Self {
        Self::from_coords(crate::linalg::normalized(&self.coords()))
    }

    /// The quaternion exponential of a rotation vector (half-angle form):
    /// `exp(ω) = [sin(θ/2) ω/θ, cos(θ/2)]`, `θ = |ω|`, a unit quaternion
    /// representing the rotation `Exp(ω)`.
    ///
    /// Document 000 §I prints the vector part as `½ sinc(θ/2) ω̂`, which equals
    /// `sin(θ/2)/θ · ω̂`, not `sin(θ/2) ω̂`; the derivation audit reports it.
    pub fn exp(omega: &Vector3<S>) -> Self {
        let theta2 = squared_norm(omega);
        // sin(θ/2)/θ = 1/2 − θ²/48 + θ⁴/3840;  cos(θ/2) = 1 − θ²/8 + θ⁴/384.
        let series_k =
            S::from_f64(0.5) - theta2 / S::from_f64(48.0) + theta2 * theta2 / S::from_f64(3840.0);
        let series_w = S::one() - theta2 / S::from_f64(8.0) + theta2 * theta2 / S::from_f64(384.0);
        let theta = theta2.sqrt();
        let half = theta * S::from_f64(0.5);
        let exact_k = half.sin() / theta;
        let exact_w = half.cos();
        let small = S::from_f64(SMALL_ANGLE_SQUARED);
        let k = S::select_lt(theta2, small, series_k, exact_k);
        let w = S::select_lt(theta2, small, series_w, exact_w);
        Self::from_parts(scale(k, omega), w)
    }

    /// First-order exponential `[ω/2, 1]`: equal to [`Quaternion::exp`] up to
    /// `O(|ω|²)`, used by first-order retractions.
    pub fn exp_first_order(omega: &Vector3<S>) -> Self {
        Self::from_parts(scale(S::from_f64(0.5), omega), S::one())
    }

    /// The quaternion logarithm `2 atan2(|v|, w) v / |v|` (document 000 §I writes
    /// `2 cos⁻¹(w) v / |v|`, equal on unit quaternions): the inverse of
    /// [`Quaternion::exp`] on the whole sphere, `|log q| < 2π`.
    ///
    /// Both forms below are homogeneous of degree 0: `log(λ q) = log(q)` for
    /// every `λ > 0`, so a caller may pass an unnormalised quaternion with a
    /// positive scale and save the normalisation (the plane factor does).
    ///
    /// Near the identity (`r = |v|²/w² <` [`SMALL_ANGLE_SQUARED`] and `w > 0`)
    /// the series `2/w (1 − r/3 + r²/5) v` is used: the expansion of
    /// `2 atan(s/w)/s`, `s = |v|`, which equals `2 atan2(s, w)/s` only for
    /// `w > 0`; near `q = −1` (`w < 0`, angle near 2π) the exact form is kept.
    /// At `q = [0, 0, 0, −1]` (angle 2π) the logarithm has no direction: callers
    /// that can meet it reject it first.
    pub fn log(&self) -> Vector3<S> {
        let v = self.vector();
        let s2 = squared_norm(&v);
        let w = self.w;
        let r = s2 / (w * w);
        let series =
            S::from_f64(2.0) / w * (S::one() - r / S::from_f64(3.0) + r * r / S::from_f64(5.0));
        let s = s2.sqrt();
        let exact = S::from_f64(2.0) * s.atan2(w) / s;
        let small = S::select_lt(r, S::from_f64(SMALL_ANGLE_SQUARED), series, exact);
        let k = S::select_lt(S::zero(), w, small, exact);
        scale(k, &v)
    }

    /// Rotates `v` by a unit quaternion, `q ⊗ [v, 0] ⊗ q⁻¹ = R(q) v`
    /// ([`Quaternion::to_rotation_matrix`] times `v`, or the number type's
    /// own [`Scalar::rotate_by_quaternion`]).
    pub fn rotate(&self, v: &Vector3<S>) -> Vector3<S> {
        match S::rotate_by_quaternion(&[self.x, self.y, self.z, self.w], &[v.x, v.y, v.z], false) {
            Some(r) => Vector3::from(r),
            None => crate::linalg::mul(&self.to_rotation_matrix(), v),
        }
    }

    /// `R(q)ᵀ v`, the inverse rotation of a unit quaternion (as
    /// [`Quaternion::rotate`]).
    pub fn inverse_rotate(&self, v: &Vector3<S>) -> Vector3<S> {
        match S::rotate_by_quaternion(&[self.x, self.y, self.z, self.w], &[v.x, v.y, v.z], true) {
            Some(r) => Vector3::from(r),
            None => crate::linalg::tr_mul(&self.to_rotation_matrix(), v),
        }
    }

    /// The rotation matrix `R(q)` of a unit quaternion, in the homogeneous
    /// form `R = (w² − |u|²) I + 2 u uᵀ + 2 w [u]×` (diagonal
    /// `w² + x² − y² − z²`, ...), which equals `|q|²` times the rotation of
    /// `q/|q|` for any `q`. So `R(a ⊗ b) = R(a) R(b)` holds as a polynomial
    /// identity, not only on the unit sphere, and a traced derivative such as
    /// `∂R(exp(δ) ⊗ q)/∂δ_z = [e_z]× R(q)` comes out as the entries of `R`
    /// themselves: the symbolic engine shares them instead of emitting new
    /// polynomials.
    pub fn to_rotation_matrix(&self) -> Matrix3<S> {
        homogeneous_rotation(self.x, self.y, self.z, self.w)
    }

    /// The unit quaternion of a rotation matrix, by Shepperd's method: the
    /// largest of `4w², 4x², 4y², 4z²` is taken as the pivot, so the result
    /// is accurate for every rotation, including half-turns. Returns the
    /// representative the pivot makes positive.
    pub fn from_rotation_matrix(m: &Matrix3<S>) -> Self {
        let quarter = S::from_f64(0.25);
        let one = S::one();
        let trace = m[(0, 0)] + m[(1, 1)] + m[(2, 2)];
        // Each candidate divides by 4·pivot; pivot = √(1 + ...) / 2.
        let candidate = |pivot2: S, make: &dyn Fn(S, S) -> Quaternion<S>| {
            let p = pivot2.sqrt() * S::from_f64(0.5);
            make(p, quarter / p)
        };
        let by_w = candidate(one + trace, &|p, k| {
            Self::new(
                (m[(2, 1)] - m[(1, 2)]) * k,
                (m[(0, 2)] - m[(2, 0)]) * k,
                (m[(1, 0)] - m[(0, 1)]) * k,
                p,
            )
        });
        let by_x = candidate(one + m[(0, 0)] - m[(1, 1)] - m[(2, 2)], &|p, k| {
            Self::new(
                p,
                (m[(0, 1)] + m[(1, 0)]) * k,
                (m[(0, 2)] + m[(2, 0)]) * k,
                (m[(2, 1)] - m[(1, 2)]) * k,
            )
        });
        let by_y = candidate(one - m[(0, 0)] + m[(1, 1)] - m[(2, 2)], &|p, k| {
            Self::new(
                (m[(0, 1)] + m[(1, 0)]) * k,
                p,
                (m[(1, 2)] + m[(2, 1)]) * k,
                (m[(0, 2)] - m[(2, 0)]) * k,
            )
        });
        let by_z = candidate(one - m[(0, 0)] - m[(1, 1)] + m[(2, 2)], &|p, k| {
            Self::new(
                (m[(0, 2)] + m[(2, 0)]) * k,
                (m[(1, 2)] + m[(2, 1)]) * k,
                p,
                (m[(1, 0)] - m[(0, 1)]) * k,
            )
        });
        let (d0, d1, d2) = (m[(0, 0)], m[(1, 1)], m[(2, 2)]);
        let xy = Self::select(d0, d1, &by_y, &by_x);
        let key_xy = S::select_lt(d0, d1, d1, d0);
        let xyz = Self::select(key_xy, d2, &by_z, &xy);
        let key_xyz = S::select_lt(key_xy, d2, d2, key_xy);
        Self::select(key_xyz, trace, &by_w, &xyz)
    }

    /// Component-wise `if lhs < rhs { a } else { b }`.
    pub fn select(lhs: S, rhs: S, a: &Self, b: &Self) -> Self {
        Self::new(
            S::select_lt(lhs, rhs, a.x, b.x),
            S::select_lt(lhs, rhs, a.y, b.y),
            S::select_lt(lhs, rhs, a.z, b.z),
            S::select_lt(lhs, rhs, a.w, b.w),
        )
    }
}

/// Stored `[qx, qy, qz, qw]` (vector part first); from users, a norm within
/// [`QUATERNION_NORM_TOLERANCE`] of 1, re-normalised.
impl<S: Scalar> Storage<S> for Quaternion<S> {
    type With<T: Scalar> = Quaternion<T>;
    const SCALARS: usize = 4;
    fn layout() -> Layout {
        Layout::array(&["qx", "qy", "qz", "qw"])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Quaternion<T> {
        Quaternion::new(f(self.x), f(self.y), f(self.z), f(self.w))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        Quaternion::new(next(), next(), next(), next())
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        // Computed without overflow or underflow, so a message never shows
        // `inf` or `0` for a finite, non-zero input.
        let norm = scaled_norm(&Vector4::from_column_slice(input));
        if (norm - 1.0).abs() <= QUATERNION_NORM_TOLERANCE {
            Ok(input.iter().map(|x| x / norm).collect())
        } else {
            Err(StorageError::new(format!(
                "quaternion [x, y, z, w] has norm {}, expected 1 \
                 (within {QUATERNION_NORM_TOLERANCE:e})",
                magnitude_text(norm)
            )))
        }
    }
}

impl Quaternion<f64> {
    /// Largest absolute coordinate difference, for tests and validation.
    pub fn max_abs_diff(&self, other: &Self) -> f64 {
        (self.coords() - other.coords()).amax()
    }
}
