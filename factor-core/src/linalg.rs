//! Small vector helpers that need only [`Scalar`] arithmetic (nalgebra's own
//! `norm` and `normalize` require `RealField`), and `f64` helpers for values
//! of any magnitude ([`scaled_norm`], [`unit_of`], [`norm_ratio`]).

use nalgebra::storage::RawStorage;
use nalgebra::{Dim, Matrix, Matrix3, SMatrix, SVector, Vector3};

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

/// `m v`, each entry a sum of products written out. nalgebra's product of
/// matrices over a scalar that is not a float goes through its general
/// `gemv`, which forms `1 · m_rc · v_c + 1 · y` for every entry: three
/// products where one is needed, each as wide as a dual number's
/// derivative. Traced, it gives an equal expression written differently
/// from nalgebra's product's (the checked-in kernels were regenerated).
#[inline]
pub fn mul<S: Scalar, const R: usize, const K: usize, const C: usize>(
    m: &SMatrix<S, R, K>,
    v: &SMatrix<S, K, C>,
) -> SMatrix<S, R, C> {
    SMatrix::from_fn(|r, c| {
        (1..K).fold(m[(r, 0)] * v[(0, c)], |acc, k| acc + m[(r, k)] * v[(k, c)])
    })
}

/// `mᵀ v`, as [`mul`] (no transposed copy).
#[inline]
pub fn tr_mul<S: Scalar, const K: usize, const R: usize, const C: usize>(
    m: &SMatrix<S, K, R>,
    v: &SMatrix<S, K, C>,
) -> SMatrix<S, R, C> {
    SMatrix::from_fn(|r, c| {
        (1..K).fold(m[(0, r)] * v[(0, c)], |acc, k| acc + m[(k, r)] * v[(k, c)])
    })
}

/// The rotation matrix of the quaternion `[x, y, z, w]` in its homogeneous
/// form, `|q|²` times the rotation of `q/|q|` (see
/// [`Quaternion::to_rotation_matrix`](crate::lie::Quaternion::to_rotation_matrix),
/// which is this).
pub fn homogeneous_rotation<S: Scalar>(x: S, y: S, z: S, w: S) -> Matrix3<S> {
    let two = S::from_f64(2.0);
    let (xx, yy, zz, ww) = (x * x, y * y, z * z, w * w);
    Matrix3::new(
        ww + xx - yy - zz,
        two * (x * y - z * w),
        two * (x * z + y * w),
        two * (x * y + z * w),
        ww - xx + yy - zz,
        two * (y * z - x * w),
        two * (x * z - y * w),
        two * (y * z + x * w),
        ww - xx - yy + zz,
    )
}

/// `c · v`, the scalar on the left so generic scalars need no `Mul<Matrix>`.
pub fn scale<S: Scalar, const R: usize, const C: usize>(
    c: S,
    v: &SMatrix<S, R, C>,
) -> SMatrix<S, R, C> {
    v.map(|x| c * x)
}

/// `v / ‖v‖` for an `f64` vector of any magnitude: scaled by its largest
/// magnitude first, so no square overflows or underflows (a plain norm is
/// infinite beyond about `1e154` and zero below `1e-162`). `None` for a zero
/// or non-finite vector.
pub fn unit_of<const R: usize>(v: &SVector<f64, R>) -> Option<SVector<f64, R>> {
    let largest = v.amax();
    if !(largest > 0.0 && largest.is_finite()) {
        return None;
    }
    let scaled = v / largest;
    Some(scaled / scaled.norm())
}

/// `‖v‖` for an `f64` array of any magnitude, scaled by its largest
/// magnitude first: infinite only when the norm itself exceeds `f64::MAX`,
/// zero only for a zero array.
pub fn scaled_norm<R: Dim, C: Dim, St: RawStorage<f64, R, C>>(v: &Matrix<f64, R, C, St>) -> f64 {
    let largest = v.amax();
    if largest > 0.0 && largest.is_finite() {
        largest * v.iter().map(|x| (x / largest).powi(2)).sum::<f64>().sqrt()
    } else {
        largest
    }
}

/// `‖a‖ / ‖b‖` for `f64` arrays of any magnitude: only the ratio itself can
/// overflow or underflow, not the norms. `0` when `a` is zero, infinite when
/// only `b` is.
pub fn norm_ratio<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
) -> f64 {
    let (ma, mb) = (a.amax(), b.amax());
    if ma == 0.0 {
        0.0
    } else if mb == 0.0 {
        f64::INFINITY
    } else {
        (ma / mb) * ((a / ma).norm() / (b / mb).norm())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector4;

    #[test]
    fn units_and_ratios_hold_over_the_whole_f64_range() {
        let v = Vector4::new(3.0, -4.0, 0.0, 12.0);
        let unit = Vector4::new(3.0, -4.0, 0.0, 12.0) / 13.0;
        let scales = (-300..=300)
            .step_by(20)
            .map(|e| 10f64.powi(e))
            .chain([1e-320]);
        for scale in scales {
            let exponent = scale.log10().round();
            let scaled = v * scale;
            let got = unit_of(&scaled).expect("non-zero");
            // Subnormal inputs hold fewer bits: their scaled copy less exactly.
            let tolerance = if scale * 3.0 < f64::MIN_POSITIVE {
                1e-3
            } else {
                1e-15
            };
            assert!((got - unit).amax() <= tolerance, "1e{exponent}: {got}");
            let ratio = norm_ratio(&scaled, &Vector4::new(0.0, 0.0, 5.0 * scale, 0.0));
            assert!(
                (ratio - 13.0 / 5.0).abs() <= 13.0 / 5.0 * tolerance,
                "1e{exponent}: {ratio}"
            );
            let norm = scaled_norm(&scaled);
            assert!(
                (norm / (13.0 * scale) - 1.0).abs() <= tolerance,
                "1e{exponent}: {norm}"
            );
        }
        assert_eq!(unit_of(&Vector4::<f64>::zeros()), None);
        assert_eq!(unit_of(&Vector4::new(1.0, f64::INFINITY, 0.0, 0.0)), None);
        assert_eq!(norm_ratio(&Vector4::zeros(), &v), 0.0);
        assert_eq!(norm_ratio(&v, &Vector4::zeros()), f64::INFINITY);
    }
}
