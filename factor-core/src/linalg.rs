//! Small vector helpers that need only [`Scalar`] arithmetic (nalgebra's own
//! `norm` and `normalize` require `RealField`).

use nalgebra::{SMatrix, Vector3};

use crate::scalar::Scalar;

/// Euclidean norm of a fixed-size vector or matrix (Frobenius).
pub fn norm<S: Scalar, const R: usize, const C: usize>(v: &SMatrix<S, R, C>) -> S {
    squared_norm(v).sqrt()
}

/// Sum of squared entries.
pub fn squared_norm<S: Scalar, const R: usize, const C: usize>(v: &SMatrix<S, R, C>) -> S {
    v.iter().fold(S::zero(), |acc, &x| acc + x * x)
}

/// `v / ‖v‖` (one reciprocal, `R·C` products).
pub fn normalized<S: Scalar, const R: usize, const C: usize>(
    v: &SMatrix<S, R, C>,
) -> SMatrix<S, R, C> {
    let inv = norm(v).recip();
    v.map(|x| x * inv)
}

/// `a × b`.
pub fn cross<S: Scalar>(a: &Vector3<S>, b: &Vector3<S>) -> Vector3<S> {
    Vector3::new(
        a.y * b.z - a.z * b.y,
        a.z * b.x - a.x * b.z,
        a.x * b.y - a.y * b.x,
    )
}

/// `a · b`.
pub fn dot<S: Scalar, const R: usize>(a: &SMatrix<S, R, 1>, b: &SMatrix<S, R, 1>) -> S {
    a.iter()
        .zip(b.iter())
        .fold(S::zero(), |acc, (&x, &y)| acc + x * y)
}

/// `c · v`, the scalar on the left so generic scalars need no `Mul<Matrix>`.
pub fn scale<S: Scalar, const R: usize, const C: usize>(
    c: S,
    v: &SMatrix<S, R, C>,
) -> SMatrix<S, R, C> {
    v.map(|x| c * x)
}
