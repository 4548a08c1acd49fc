//! The few Eigen 3.3 operations g2o's errors are made of, reproduced to
//! rounding: g2o keeps poses as `Isometry3` matrices built from quaternions
//! as written (not normalised), and its results depend on the branch and
//! sign Eigen's matrix-to-quaternion conversion takes.

use nalgebra::{Matrix3, Vector3};

use factor_core::Scalar;
use factor_core::lie::{Quaternion, Se3};
use factor_core::linalg::{cross, norm, scale, squared_norm};

/// Eigen's `Quaternion::toRotationMatrix` of `q = [x, y, z, w]`, which does
/// not normalise: `I + 2 w [v]× + 2 [v]×²`, i.e. diagonal `1 − 2(y² + z²)`, …
/// For a unit quaternion this is its rotation; otherwise it is not
/// orthogonal (g2o reads quaternions with six significant digits into it).
pub fn rotation_matrix<S: Scalar>(q: &Quaternion<S>) -> Matrix3<S> {
    let two = S::from_f64(2.0);
    let (tx, ty, tz) = (two * q.x, two * q.y, two * q.z);
    let (twx, twy, twz) = (tx * q.w, ty * q.w, tz * q.w);
    let (txx, txy, txz) = (tx * q.x, ty * q.x, tz * q.x);
    let (tyy, tyz, tzz) = (ty * q.y, tz * q.y, tz * q.z);
    let one = S::one();
    Matrix3::new(
        one - (tyy + tzz),
        txy - twz,
        txz + twy,
        txy + twz,
        one - (txx + tzz),
        tyz - twx,
        txz - twy,
        tyz + twx,
        one - (txx + tyy),
    )
}

/// Eigen 3.3's `Quaternion(const Matrix3&)` of any 3×3 matrix, up to a
/// positive factor: Eigen takes the trace branch when the trace is positive
/// (`w = t/2`, the rest divided by `2t`, `t = √(trace + 1)`), else
/// [`pivot_quaternion`]. Multiplied by `2t`, each branch is a polynomial of
/// the entries (the trace branch `[m₂₁ − m₁₂, m₀₂ − m₂₀, m₁₀ − m₀₁,
/// trace + 1]`): g2o normalises the quaternion next, which the factor does
/// not change, and a kernel needs no square root per branch.
pub fn quaternion_of<S: Scalar>(m: &Matrix3<S>) -> Quaternion<S> {
    let trace = m[(0, 0)] + m[(1, 1)] + m[(2, 2)];
    let by_trace = Quaternion::from_parts(antisymmetric_part(m), trace + S::one());
    Quaternion::select(S::zero(), trace, &by_trace, &pivot_quaternion(m))
}

/// `[m₂₁ − m₁₂, m₀₂ − m₂₀, m₁₀ − m₀₁]`.
fn antisymmetric_part<S: Scalar>(m: &Matrix3<S>) -> Vector3<S> {
    Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    )
}

/// The branch of [`quaternion_of`] for a trace that is not positive, up to
/// the same positive factor `2t`: from the largest diagonal entry `m_ii`
/// (ties to the first, as Eigen picks it), `q_i = t² = 2 m_ii − trace + 1`,
/// `q_j = m_ji + m_ij`, `q_k = m_ki + m_ik`, `w = m_kj − m_jk` (`j = i + 1`,
/// `k = i + 2` mod 3), so `q_i > 0`. The pivot's entries are selected
/// before one formula is applied, so a kernel differentiates one formula,
/// not three.
pub fn pivot_quaternion<S: Scalar>(m: &Matrix3<S>) -> Quaternion<S> {
    let (d0, d1, d2) = (m[(0, 0)], m[(1, 1)], m[(2, 2)]);
    let trace = d0 + d1 + d2;
    let (s01, s02, s12) = (
        m[(0, 1)] + m[(1, 0)],
        m[(0, 2)] + m[(2, 0)],
        m[(1, 2)] + m[(2, 1)],
    );
    let a = antisymmetric_part(m);
    // `i = 0; if m₁₁ > m₀₀ { i = 1 }; if m₂₂ > m_ii { i = 2 }`: each value
    // is chosen as (i = 0, i = 1) first, then against i = 2.
    let largest = S::select_lt(d0, d1, d1, d0);
    let pick = |of_0: S, of_1: S, of_2: S| {
        let of_01 = S::select_lt(d0, d1, of_1, of_0);
        S::select_lt(largest, d2, of_2, of_01)
    };
    let t2 = S::from_f64(2.0) * pick(d0, d1, d2) - trace + S::one();
    Quaternion::new(
        pick(t2, s01, s02),
        pick(s01, t2, s12),
        pick(s02, s12, t2),
        pick(a.x, a.y, a.z),
    )
}

/// `q / |q|` (Eigen's `normalize`, no sign change).
pub fn normalized<S: Scalar>(q: &Quaternion<S>) -> Quaternion<S> {
    let inv = norm(&q.coords()).recip();
    Quaternion::from_coords(scale(inv, &q.coords()))
}

/// An `Isometry3` as g2o computes with it: a linear part that is a rotation
/// only up to how its quaternion was written, and a translation. Products
/// and inverses are Eigen's for the isometry mode (the inverse transposes
/// the linear part).
#[derive(Debug, Clone, Copy)]
pub struct Isometry<S> {
    /// The linear part `L`.
    pub linear: Matrix3<S>,
    /// The translation `t`.
    pub translation: Vector3<S>,
}

impl<S: Scalar> Isometry<S> {
    /// g2o's pose of a `VERTEX_SE3:QUAT`: [`rotation_matrix`] of the stored
    /// quaternion as it is, and the translation.
    pub fn from_pose(pose: &Se3<S>) -> Self {
        Isometry {
            linear: rotation_matrix(&pose.rotation.quaternion),
            translation: pose.translation,
        }
    }

    /// `self · rhs`: `[L₁ L₂, L₁ t₂ + t₁]`.
    pub fn compose(&self, rhs: &Self) -> Self {
        Isometry {
            linear: self.linear * rhs.linear,
            translation: self.linear * rhs.translation + self.translation,
        }
    }

    /// `L p + t`.
    pub fn apply(&self, p: &Vector3<S>) -> Vector3<S> {
        self.linear * p + self.translation
    }

    /// Eigen's isometry inverse `[Lᵀ, −Lᵀ t]`.
    pub fn inverse(&self) -> Self {
        let linear = self.linear.transpose();
        Isometry {
            linear,
            translation: -(linear * self.translation),
        }
    }
}

/// The rotation of the polar decomposition of [`rotation_matrix`]`(q)`, as a
/// quaternion up to a non-zero factor (either sign): what Eigen 3.3's
/// `Transform::rotation()` returns (by an SVD) for an `Isometry3` read from
/// `q`. (Eigen 3.4 returns the linear part itself for an isometry.)
///
/// For `q = s u` (`u` unit, rotation by `θ` about `a`), Eigen's matrix is
/// `(1 − s²) I + s² R(u)`: the same axis, and in the plane about it the
/// complex number `λ = (1 − s²) + s² e^{iθ} = (1 − 2|v|²) + i 2w|v|`. Its
/// rotation turns by `arg λ`, whose half-angle quaternion is `[a b̂, |λ| +
/// α]` with `α = 1 − 2|v|²`, `a b̂ = 2w v`, or, where `α < 0` (near a
/// half-turn), the equivalent `[â (|λ| − α), 2w|v|]`. One square root; no
/// matrix decomposition.
///
/// The polar factor of a product of two such matrices is the product of
/// theirs up to `O(ε²)`, `ε = s² − 1`: about 1e-12 for the six-digit
/// quaternions of g2o's files, below what their cost can show.
pub fn polar_quaternion<S: Scalar>(q: &Quaternion<S>) -> Quaternion<S> {
    let (v, w) = (q.vector(), q.w);
    let vv = squared_norm(&v);
    let two = S::from_f64(2.0);
    let alpha = S::one() - two * vv;
    let lambda = (alpha * alpha + S::from_f64(4.0) * w * w * vv).sqrt();
    let near_identity = Quaternion::from_parts(scale(two * w, &v), lambda + alpha);
    let v_norm = vv.sqrt();
    let near_half_turn =
        Quaternion::from_parts(scale((lambda - alpha) / v_norm, &v), two * w * v_norm);
    Quaternion::select(alpha, S::zero(), &near_half_turn, &near_identity)
}

/// `[w, d] ↦ [L w + [t]× L d, L d]`, g2o's `Isometry3 * Line3D` (the 6×6
/// line motion matrix with the linear part as it is).
pub fn transform_line<S: Scalar>(
    isometry: &Isometry<S>,
    moment: &Vector3<S>,
    direction: &Vector3<S>,
) -> (Vector3<S>, Vector3<S>) {
    let ld = isometry.linear * direction;
    (
        isometry.linear * moment + cross(&isometry.translation, &ld),
        ld,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    use factor_core::lie::So3;

    /// Rotations whose matrices take each of Eigen's four branches.
    fn rotations() -> Vec<So3<f64>> {
        let mut out = Vec::new();
        for axis in [
            Vector3::new(0.3, -0.5, 0.8),
            Vector3::new(-0.9, 0.2, 0.1),
            Vector3::new(0.1, 0.95, -0.2),
            Vector3::new(0.2, -0.1, -0.97),
        ] {
            for angle in [0.0, 0.4, 2.0, 2.5, 3.0, std::f64::consts::PI] {
                out.push(So3::exp(&(axis.normalize() * angle)));
            }
        }
        out
    }

    /// On rotation matrices, the normalised result is the rotation's
    /// quaternion with Eigen's sign: `w > 0` when the trace is positive,
    /// else positive at the largest diagonal entry.
    #[test]
    fn quaternion_of_a_rotation_is_its_quaternion_with_eigens_sign() {
        for r in rotations() {
            let m = r.matrix();
            let q = normalized(&quaternion_of(&m));
            let expected = r.quaternion.coords();
            let same = (q.coords() - expected)
                .amax()
                .min((q.coords() + expected).amax());
            assert!(same <= 1e-15, "{m}: {q:?}");
            let positive = if m.trace() > 0.0 {
                q.w
            } else {
                let i = (0..3).fold(0, |i, k| if m[(k, k)] > m[(i, i)] { k } else { i });
                q.coords()[i]
            };
            assert!(positive > 0.0, "{m}: {q:?}");
        }
    }

    /// The polar factor of Eigen's matrix of a non-unit quaternion, against
    /// Newton's iteration `X ← (X + X⁻ᵀ) / 2` run to convergence.
    #[test]
    fn polar_quaternion_is_the_polar_factor() {
        for r in rotations() {
            for scale in [1.0, 1.0 + 1e-6, 1.0 - 1e-6, 1.001, 0.999] {
                let q = Quaternion::from_coords(r.quaternion.coords() * scale);
                let mut x = rotation_matrix(&q);
                for _ in 0..50 {
                    x = (x + x.try_inverse().unwrap().transpose()) * 0.5;
                }
                let p = normalized(&polar_quaternion(&q));
                let error = (p.to_rotation_matrix() - x).amax();
                assert!(error <= 1e-15, "{q:?}: {error:e}");
            }
        }
    }
}
