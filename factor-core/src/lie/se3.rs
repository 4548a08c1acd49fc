//! SE(3): rigid transforms `T = [R t; 0 1]`, tangent `ξ = [ω, ρ]` (rotation first).
//!
//! With `W = [ω]×`, `P = [ρ]×`, `θ = |ω|`:
//! - `Exp([ω, ρ]) = [Exp(ω), Jl(ω) ρ]`, `Log` its inverse;
//! - `Ad_T = [[R, 0], [t^ R, R]]`, from `T ξ^ T⁻¹ = [[(Rω)^, t^ R ω + R ρ], [0, 0]]`
//!   (`R ω^ Rᵀ = (Rω)^` and `−(Rω)^ t = t^ R ω`);
//! - `Jl([ω, ρ]) = Σₖ adᵏ/(k+1)! = [[Jl(ω), 0], [Q(ω, ρ), Jl(ω)]]` with
//!   `ad = [[W, 0], [P, W]]`, and `Jl⁻¹ = [[Jl⁻¹(ω), 0], [−Jl⁻¹(ω) Q Jl⁻¹(ω),
//!   Jl⁻¹(ω)]]`; `Jr(ξ) = Jl(−ξ)`. `Q` is Barfoot's (T. D. Barfoot and P. T.
//!   Furgale, "Associating Uncertainty With Three-Dimensional Poses for Use
//!   in Estimation Problems", IEEE T-RO 30(3), 2014, eq. (102), also in his
//!   book *State Estimation for Robotics*), whose `[ρ, φ]` ordering puts it
//!   in the upper-right block: see [`jacobian_coupling`].
//!
//! Document 000 uses `T` for the world-to-camera map `X_c = R X_w + t`;
//! document 001 names its body pose `T_BW` (`X_B = C_BW X_W + t_BW`). Both are
//! this type; which frames it maps between is the factor's business.

use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3, Vector6};

use crate::dual::Dual;
use crate::lie::so3::{
    angle_coefficient, hat, left_jacobian, left_jacobian_inverse, perturb_quaternion,
    quaternion_local, seeded_quaternion, theta_minus_sin_over_theta3, write3,
};
use crate::lie::{LieGroup, Quaternion, So3};
use crate::linalg::{cross, squared_norm};
use crate::manifold::{Manifold, NoLocal, Perturbation};
use crate::scalar::Scalar;
use crate::storage::{Layout, Storage, StorageError};

/// A rigid transform `X ↦ R X + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Se3<S> {
    /// `R`.
    pub rotation: So3<S>,
    /// `t`.
    pub translation: Vector3<S>,
}

impl<S: Scalar> Se3<S> {
    /// From `R` and `t`.
    pub fn new(rotation: So3<S>, translation: Vector3<S>) -> Self {
        Se3 {
            rotation,
            translation,
        }
    }

    /// The identity.
    pub fn identity() -> Self {
        Self::new(So3::identity(), Vector3::zeros())
    }

    /// The exact exponential `Exp([ω, ρ]) = [Exp(ω), Jl(ω) ρ]`.
    pub fn exp(xi: &Vector6<S>) -> Self {
        let w = Vector3::new(xi[0], xi[1], xi[2]);
        let rho = Vector3::new(xi[3], xi[4], xi[5]);
        Self::new(So3::exp(&w), left_jacobian(&w) * rho)
    }

    /// `Log(T) = [ω, Jl(ω)⁻¹ t]`, `ω = Log(R)`.
    pub fn log(&self) -> Vector6<S> {
        let w = self.rotation.log();
        let rho = left_jacobian_inverse(&w) * self.translation;
        Vector6::new(w[0], w[1], w[2], rho[0], rho[1], rho[2])
    }

    /// `R X + t`.
    pub fn transform_point(&self, x: &Vector3<S>) -> Vector3<S> {
        self.rotation.rotate(x) + self.translation
    }

    /// `T⁻¹ = [Rᵀ, −Rᵀ t]`.
    pub fn inverse(&self) -> Self {
        let r_inv = self.rotation.inverse();
        Self::new(r_inv, -r_inv.rotate(&self.translation))
    }

    /// `self · rhs`.
    pub fn compose(&self, rhs: &Self) -> Self {
        Self::new(
            self.rotation.compose(&rhs.rotation),
            self.rotation.rotate(&rhs.translation) + self.translation,
        )
    }

    /// The homogeneous 4×4 matrix.
    pub fn matrix(&self) -> Matrix4<S> {
        let r: Matrix3<S> = self.rotation.matrix();
        let t = self.translation;
        let (z, o) = (S::zero(), S::one());
        Matrix4::new(
            r[(0, 0)],
            r[(0, 1)],
            r[(0, 2)],
            t.x,
            r[(1, 0)],
            r[(1, 1)],
            r[(1, 2)],
            t.y,
            r[(2, 0)],
            r[(2, 1)],
            r[(2, 2)],
            t.z,
            z,
            z,
            z,
            o,
        )
    }
}

/// `c₂ = (θ² + 2 cos θ − 2)/(2θ⁴)` (see [`jacobian_coupling`]).
fn coupling_coefficient_2<S: Scalar>(theta2: S) -> S {
    angle_coefficient(theta2, coupling_series_2, coupling_exact_2)
}

/// `c₂ ≈ 1/24 − θ²/720 + θ⁴/40320` (next term `−θ⁶/3628800`).
fn coupling_series_2<S: Scalar>(t2: S) -> S {
    S::from_f64(1.0 / 24.0) - t2 / S::from_f64(720.0) + t2 * t2 / S::from_f64(40320.0)
}

/// `c₂` written `(½ − (1 − cos θ)/θ²)/θ²` with `1 − cos θ = 2 sin²(θ/2)`:
/// the cancellation then costs `ε` on a quantity of order 1 divided by `θ²`,
/// instead of `4ε` divided by `2θ⁴`.
fn coupling_exact_2<S: Scalar>(t: S) -> S {
    let s = (t * S::from_f64(0.5)).sin();
    let t2 = t * t;
    (S::from_f64(0.5) - S::from_f64(2.0) * s * s / t2) / t2
}

/// `c₃ = (2θ − 3 sin θ + θ cos θ)/(2θ⁵)` (see [`jacobian_coupling`]).
fn coupling_coefficient_3<S: Scalar>(theta2: S) -> S {
    angle_coefficient(theta2, coupling_series_3, coupling_exact_3)
}

/// `c₃ ≈ 1/120 − θ²/2520 + θ⁴/120960` (next term `−θ⁶/9979200`).
fn coupling_series_3<S: Scalar>(t2: S) -> S {
    S::from_f64(1.0 / 120.0) - t2 / S::from_f64(2520.0) + t2 * t2 / S::from_f64(120960.0)
}

/// `c₃` written `(3 (θ − sin θ)/θ³ − (1 − cos θ)/θ²)/(2θ²)`.
fn coupling_exact_3<S: Scalar>(t: S) -> S {
    let t2 = t * t;
    let s = (t * S::from_f64(0.5)).sin();
    let c1 = (t - t.sin()) / (t2 * t);
    let b = S::from_f64(2.0) * s * s / t2;
    (S::from_f64(3.0) * c1 - b) / (S::from_f64(2.0) * t2)
}

/// `Q(ω, ρ)`, the lower-left block of `Jl([ω, ρ])` (Barfoot and Furgale
/// 2014, (102)), with `W = [ω]×`, `P = [ρ]×`:
///
/// `Q = ½ P + c₁ (WP + PW + WPW) + c₂ (W²P + PW² − 3 WPW) + c₃ (WPW² + W²PW)`,
///
/// `c₁ = (θ − sin θ)/θ³`, `c₂ = (θ² + 2 cos θ − 2)/(2θ⁴)`,
/// `c₃ = (2θ − 3 sin θ + θ cos θ)/(2θ⁵)`; below the small-angle threshold
/// their series `1/6 − θ²/120 + θ⁴/5040`, `1/24 − θ²/720 + θ⁴/40320`,
/// `1/120 − θ²/2520 + θ⁴/120960` (first omitted terms `O(θ⁶)`, below `1e-19`
/// relative there). Above the threshold `c₁` and `c₃` cancel as the SO(3)
/// coefficients do, so the absolute error of `Q` grows like `ε |ρ| / θ`
/// towards the threshold. Measured against the series `Σ adᵏ/(k+1)!` (both
/// `Jl` and `Jl⁻¹`, several axes and `ρ`): at most `3e-14 |ρ|` for
/// `θ ∈ [1e-3, 1e-2]`, `6e-16 |ρ|` for `θ ∈ [0.1, 3]`, `2e-16 |ρ|` below the
/// threshold.
pub fn jacobian_coupling<S: Scalar>(w: &Vector3<S>, rho: &Vector3<S>) -> Matrix3<S> {
    let t2 = squared_norm(w);
    let (ww, p) = (hat(w), hat(rho));
    let (wp, pw) = (ww * p, p * ww);
    let wpw = wp * ww;
    let scaled = |c: S, m: Matrix3<S>| m.map(|x| c * x);
    scaled(S::from_f64(0.5), p)
        + scaled(theta_minus_sin_over_theta3(t2), wp + pw + wpw)
        + scaled(
            coupling_coefficient_2(t2),
            ww * wp + pw * ww - scaled(S::from_f64(3.0), wpw),
        )
        + scaled(coupling_coefficient_3(t2), wpw * ww + ww * wpw)
}

/// `[[diagonal, 0], [lower, diagonal]]`, the shape of the adjoint and of the
/// Jacobians in the `[ω, ρ]` order.
fn lower_block_triangular<S: Scalar>(diagonal: &Matrix3<S>, lower: &Matrix3<S>) -> Matrix6<S> {
    let mut m = Matrix6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(diagonal);
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(diagonal);
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(lower);
    m
}

/// `(ω, ρ)` of `ξ = [ω, ρ]`.
fn split<S: Scalar>(xi: &Vector6<S>) -> (Vector3<S>, Vector3<S>) {
    (
        Vector3::new(xi[0], xi[1], xi[2]),
        Vector3::new(xi[3], xi[4], xi[5]),
    )
}

/// SE(3) in the [`LieGroup`] vocabulary (see the module documentation for
/// the formulas): tangent `[ω, ρ]`, acting on points by `R p + t`.
impl<S: Scalar> LieGroup<S> for Se3<S> {
    const DOF: usize = 6;
    type Tangent = Vector6<S>;
    type Jacobian = Matrix6<S>;
    type Point = Vector3<S>;

    fn identity() -> Self {
        Se3::identity()
    }
    fn compose(&self, rhs: &Self) -> Self {
        Se3::compose(self, rhs)
    }
    fn inverse(&self) -> Self {
        Se3::inverse(self)
    }
    fn act(&self, point: &Vector3<S>) -> Vector3<S> {
        self.transform_point(point)
    }
    fn exp(tau: &Vector6<S>) -> Self {
        Se3::exp(tau)
    }
    fn log(&self) -> Vector6<S> {
        Se3::log(self)
    }
    /// `[[R, 0], [t^ R, R]]`.
    fn adjoint(&self) -> Matrix6<S> {
        let r = self.rotation.matrix();
        lower_block_triangular(&r, &(hat(&self.translation) * r))
    }
    /// `[[Jl(ω), 0], [Q(ω, ρ), Jl(ω)]]`.
    fn left_jacobian(tau: &Vector6<S>) -> Matrix6<S> {
        let (w, rho) = split(tau);
        lower_block_triangular(&left_jacobian(&w), &jacobian_coupling(&w, &rho))
    }
    /// `[[Jl⁻¹(ω), 0], [−Jl⁻¹(ω) Q(ω, ρ) Jl⁻¹(ω), Jl⁻¹(ω)]]`, the block
    /// inverse of [`LieGroup::left_jacobian`].
    fn left_jacobian_inverse(tau: &Vector6<S>) -> Matrix6<S> {
        let (w, rho) = split(tau);
        let inverse = left_jacobian_inverse(&w);
        let lower = -(inverse * jacobian_coupling(&w, &rho) * inverse);
        lower_block_triangular(&inverse, &lower)
    }
}

/// Stored `{rotation: [qx, qy, qz, qw], translation: [x, y, z]}`.
impl<S: Scalar> Storage<S> for Se3<S> {
    type With<T: Scalar> = Se3<T>;
    const SCALARS: usize = 7;
    fn layout() -> Layout {
        Layout::Record(vec![
            ("rotation", <So3<S> as Storage<S>>::layout()),
            ("translation", <Vector3<S> as Storage<S>>::layout()),
        ])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Se3<T> {
        Se3::new(
            self.rotation.map_scalars(f),
            self.translation.map_scalars(f),
        )
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        let rotation = So3::read_scalars(next);
        Se3::new(rotation, Vector3::read_scalars(next))
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        let mut stored = <So3<f64> as Storage<f64>>::from_input(&input[..4])
            .map_err(|e| e.within("rotation"))?;
        stored.extend_from_slice(&input[4..]);
        Ok(stored)
    }
}

/// `pose` over `Dual<N>` seeded as [`Se3`]'s `retract_first_order` perturbs
/// it, the rotation's tangent at `rotation_offset` and the translation's at
/// `translation_offset` ([`Manifold::seeded`] in closed form): the
/// quaternion as [`seeded_quaternion`], and `t + δω × t + δρ` (left,
/// `∂t/∂δω_k = e_k × t`, `∂t/∂δρ_k = e_k`) or `t + R δρ` (right,
/// `∂t/∂δρ_k = R e_k`).
#[inline(always)]
pub(crate) fn seeded_se3<const N: usize>(
    pose: &Se3<f64>,
    side: Perturbation,
    rotation_offset: usize,
    translation_offset: usize,
) -> Se3<Dual<N>> {
    let rotation = seeded_quaternion(&pose.rotation.quaternion, side, rotation_offset);
    let t = pose.translation;
    let mut translation = t.map(Dual::constant);
    match side {
        Perturbation::Left => {
            for k in 0..3 {
                let mut axis = Vector3::zeros();
                axis[k] = 1.0;
                let turned = cross(&axis, &t);
                for i in 0..3 {
                    translation[i].eps[rotation_offset + k] = turned[i];
                }
                translation[k].eps[translation_offset + k] = 1.0;
            }
        }
        Perturbation::Right => {
            let r = pose.rotation.matrix();
            for k in 0..3 {
                for i in 0..3 {
                    translation[i].eps[translation_offset + k] = r[(i, k)];
                }
            }
        }
    }
    Se3::new(So3::from_quaternion(rotation), translation)
}

/// Tangent `[δω, δρ]`.
/// - Left (document 000): `T ← Exp(δξ) T` with the exact SE(3) exponential:
///   `R ← Exp(δω) R`, `t ← Exp(δω) t + Jl(δω) δρ`.
/// - Right (document 001, (4.1)–(4.2)): `R ← R Exp(δω)`, `t ← t + R δρ`. This
///   agrees with `T Exp(δξ)` to first order, so the Jacobians are the same.
///
/// `local` inverts both with the rotation on the quaternion sphere
/// (`|δω| < 2π`): left `δω = log(q' ⊗ q*)`, `δρ = Jl(δω)⁻¹ (t' − R(δω) t)`;
/// right `δω = log(q* ⊗ q')`, `δρ = Rᵀ (t' − t)`.
impl<S: Scalar> Manifold<S> for Se3<S> {
    const DIM: usize = 6;
    fn retract(&self, delta: &[S], side: Perturbation) -> Self {
        let q = perturb_quaternion(&self.rotation.quaternion, delta, side, Quaternion::exp);
        let rho = Vector3::new(delta[3], delta[4], delta[5]);
        let t = match side {
            Perturbation::Left => {
                let w = Vector3::new(delta[0], delta[1], delta[2]);
                So3::exp(&w).rotate(&self.translation) + left_jacobian(&w) * rho
            }
            Perturbation::Right => self.translation + self.rotation.rotate(&rho),
        };
        Self::new(So3::from_quaternion(q), t)
    }
    fn retract_first_order(&self, delta: &[S], side: Perturbation) -> Self {
        let q = perturb_quaternion(
            &self.rotation.quaternion,
            delta,
            side,
            Quaternion::exp_first_order,
        );
        let w = Vector3::new(delta[0], delta[1], delta[2]);
        let rho = Vector3::new(delta[3], delta[4], delta[5]);
        let t = match side {
            Perturbation::Left => self.translation + cross(&w, &self.translation) + rho,
            Perturbation::Right => self.translation + self.rotation.rotate(&rho),
        };
        Self::new(So3::from_quaternion(q), t)
    }
    /// In closed form (`seeded_se3`).
    #[inline(always)]
    fn seeded<const D: usize, const N: usize>(
        &self,
        side: Perturbation,
        offset: usize,
    ) -> <Self as Storage<S>>::With<Dual<N>>
    where
        S: Into<f64>,
    {
        seeded_se3(
            &self.map_scalars(&mut |s| s.into()),
            side,
            offset,
            offset + 3,
        )
    }
    fn tangent_description(side: Perturbation) -> &'static str {
        match side {
            Perturbation::Left => {
                "left: T ← Exp(δξ) T, columns δξ = [δω_x, δω_y, δω_z, δρ_x, δρ_y, δρ_z]"
            }
            Perturbation::Right => {
                "right: R ← R Exp(δω), t ← t + R δρ, columns [δω_x, δω_y, δω_z, δρ_x, δρ_y, δρ_z]"
            }
        }
    }
    fn local(&self, other: &Self, side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        let (q, p) = (&self.rotation.quaternion, &other.rotation.quaternion);
        let w = quaternion_local(q, p, side);
        let rho = match side {
            Perturbation::Left => {
                let turned = p.mul(&q.conjugate()).rotate(&self.translation);
                left_jacobian_inverse(&w) * (other.translation - turned)
            }
            Perturbation::Right => self
                .rotation
                .inverse_rotate(&(other.translation - self.translation)),
        };
        write3(&w, &mut delta[..3]);
        write3(&rho, &mut delta[3..]);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The series and the rewritten closed forms of `c₂` and `c₃` against
    /// Barfoot's closed forms, at θ = 0.25 … 0.4 where those are accurate
    /// (their cancellation costs below 1e-13 there): the series differ by
    /// their truncation only (below twice the first omitted terms
    /// `θ⁶/3628800`, `θ⁶/9979200`; at θ = 0.4 a `θ⁴` coefficient wrong by 1%
    /// would exceed that), the rewritten closed forms by rounding.
    #[test]
    fn coupling_coefficients_match_barfoot() {
        for theta in [0.25_f64, 0.3, 0.4] {
            let t2 = theta * theta;
            let t6 = t2 * t2 * t2;
            let c2 = (t2 + 2.0 * theta.cos() - 2.0) / (2.0 * t2 * t2);
            let c3 =
                (2.0 * theta - 3.0 * theta.sin() + theta * theta.cos()) / (2.0 * t2 * t2 * theta);
            let e2 = (coupling_series_2(t2) - c2).abs();
            assert!(e2 < 2.0 * t6 / 3628800.0, "c₂({theta}): {e2:e}");
            let e3 = (coupling_series_3(t2) - c3).abs();
            assert!(e3 < 2.0 * t6 / 9979200.0, "c₃({theta}): {e3:e}");
            assert!((coupling_exact_2(theta) - c2).abs() < 1e-13, "c₂({theta})");
            assert!((coupling_exact_3(theta) - c3).abs() < 1e-12, "c₃({theta})");
        }
    }
}
