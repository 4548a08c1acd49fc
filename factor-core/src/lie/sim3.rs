//! Sim(3): similarities `p ↦ s R p + t` (a rotation, a translation and a
//! positive scale), with `Exp`/`Log`, the adjoint and the left and right
//! Jacobians and their inverses, generic over the scalar.
//!
//! Tangents are `τ = [ω, ρ, σ]` (rotation, translation, log-scale), rotation
//! first as for SE(3) here. With `A = hat(ω) + σ I`:
//! - `Exp(τ) = (Exp(ω), W ρ, e^σ)` with `W = Σₖ Aᵏ/(k+1)!`
//!   (`∫₀¹ e^{σu} Exp(uω) du`);
//! - `Log` inverts it (`ρ = W⁻¹ t`);
//! - `Ad_X = [[R, 0, 0], [t^ R, s R, −t], [0, 0, 1]]`;
//! - `ad_τ = [[ω^, 0, 0], [ρ^, ω^ + σ I, −ρ], [0, 0, 0]]` and
//!   `Jl(τ) = Σₖ ad_τᵏ/(k+1)!`, `Jr(τ) = Jl(−τ)`; `Jl⁻¹` by blocks.
//!
//! The series are summed to [`SERIES_TERMS`] terms in Horner form, without
//! branches (so dual numbers and the symbolic tracer go through them): for
//! `θ ≤ π`, `|σ| ≤ 2` and `|ρ| ≤ 10³` the first omitted term is below
//! `10⁻¹⁸` relative. The property tests check every Jacobian against dual
//! numbers.

use nalgebra::{Matrix3, Matrix4, SMatrix, SVector, Vector3};

use crate::lie::so3::hat;
use crate::lie::{LieGroup, So3};
use crate::scalar::Scalar;

/// Terms summed of the series `Σ Xᵏ/(k+1)!`.
pub const SERIES_TERMS: usize = 40;

/// A Sim(3) tangent `[ω, ρ, σ]`.
pub type Sim3Tangent<S> = SVector<S, 7>;
/// A 7 × 7 matrix in the `[ω, ρ, σ]` order.
pub type Sim3Matrix<S> = SMatrix<S, 7, 7>;

/// A similarity `p ↦ s R p + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sim3<S> {
    /// `R`.
    pub rotation: So3<S>,
    /// `t`.
    pub translation: Vector3<S>,
    /// `s > 0`.
    pub scale: S,
}

/// `Σₖ₌₀ᴺ Xᵏ/(k+1)!` in Horner form, for a square matrix `X`.
fn phi_series<S: Scalar, const N: usize>(x: &SMatrix<S, N, N>) -> SMatrix<S, N, N> {
    let identity = SMatrix::<S, N, N>::identity();
    let mut p = identity;
    for k in (1..=SERIES_TERMS).rev() {
        let scaled = (x * p).map(|v| v / S::from_f64((k + 1) as f64));
        p = identity + scaled;
    }
    p
}

/// The inverse of a 3 × 3 matrix by its adjugate (no branch).
fn inverse3<S: Scalar>(a: &Matrix3<S>) -> Matrix3<S> {
    let c = |i: usize, j: usize| {
        let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
        let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
        a[(r0, c0)] * a[(r1, c1)] - a[(r0, c1)] * a[(r1, c0)]
    };
    let det = a[(0, 0)] * c(0, 0) + a[(0, 1)] * c(0, 1) + a[(0, 2)] * c(0, 2);
    let inv = det.recip();
    Matrix3::from_fn(|i, j| c(j, i) * inv)
}

/// `(ω, ρ, σ)` of a tangent.
fn split<S: Scalar>(tau: &Sim3Tangent<S>) -> (Vector3<S>, Vector3<S>, S) {
    (
        Vector3::new(tau[0], tau[1], tau[2]),
        Vector3::new(tau[3], tau[4], tau[5]),
        tau[6],
    )
}

/// `W = Σ (ω^ + σ I)ᵏ/(k+1)!`, which maps `ρ` to the translation of `Exp`.
fn translation_jacobian<S: Scalar>(w: &Vector3<S>, sigma: S) -> Matrix3<S> {
    phi_series(&(hat(w) + Matrix3::<S>::identity().map(|v| v * sigma)))
}

impl<S: Scalar> Sim3<S> {
    /// `(R, t, s)`.
    pub fn new(rotation: So3<S>, translation: Vector3<S>, scale: S) -> Self {
        Sim3 {
            rotation,
            translation,
            scale,
        }
    }

    /// The 4 × 4 matrix `[[s R, t], [0, 1]]`.
    pub fn matrix(&self) -> Matrix4<S> {
        let mut m = Matrix4::identity();
        let sr = self.rotation.matrix().map(|v| v * self.scale);
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&sr);
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.translation);
        m
    }

    /// `ad_τ`, the adjoint of the algebra: `ad_τ₁ τ₂ = [τ₁, τ₂]`.
    pub fn small_adjoint(tau: &Sim3Tangent<S>) -> Sim3Matrix<S> {
        let (w, rho, sigma) = split(tau);
        let mut m = Sim3Matrix::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&hat(&w));
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&hat(&rho));
        m.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(hat(&w) + Matrix3::<S>::identity().map(|v| v * sigma)));
        m.fixed_view_mut::<3, 1>(3, 6).copy_from(&(-rho));
        m
    }
}

impl<S: Scalar> LieGroup<S> for Sim3<S> {
    const DOF: usize = 7;
    type Tangent = Sim3Tangent<S>;
    type Jacobian = Sim3Matrix<S>;
    type Point = Vector3<S>;

    fn identity() -> Self {
        Sim3::new(So3::identity(), Vector3::zeros(), S::one())
    }
    /// `(R₁ R₂, s₁ R₁ t₂ + t₁, s₁ s₂)`.
    fn compose(&self, rhs: &Self) -> Self {
        Sim3::new(
            self.rotation.compose(&rhs.rotation),
            self.rotation
                .rotate(&rhs.translation)
                .map(|v| v * self.scale)
                + self.translation,
            self.scale * rhs.scale,
        )
    }
    /// `(Rᵀ, −Rᵀ t / s, 1/s)`.
    fn inverse(&self) -> Self {
        let inv_scale = self.scale.recip();
        let r = self.rotation.inverse();
        Sim3::new(
            r,
            -r.rotate(&self.translation).map(|v| v * inv_scale),
            inv_scale,
        )
    }
    /// `s R p + t`.
    fn act(&self, point: &Vector3<S>) -> Vector3<S> {
        self.rotation.rotate(point).map(|v| v * self.scale) + self.translation
    }
    fn exp(tau: &Sim3Tangent<S>) -> Self {
        let (w, rho, sigma) = split(tau);
        Sim3::new(
            So3::exp(&w),
            translation_jacobian(&w, sigma) * rho,
            sigma.exp(),
        )
    }
    fn log(&self) -> Sim3Tangent<S> {
        let w = self.rotation.log();
        let sigma = self.scale.ln();
        let rho = inverse3(&translation_jacobian(&w, sigma)) * self.translation;
        let mut tau = Sim3Tangent::zeros();
        tau.fixed_view_mut::<3, 1>(0, 0).copy_from(&w);
        tau.fixed_view_mut::<3, 1>(3, 0).copy_from(&rho);
        tau[6] = sigma;
        tau
    }
    /// `[[R, 0, 0], [t^ R, s R, −t], [0, 0, 1]]`.
    fn adjoint(&self) -> Sim3Matrix<S> {
        let r = self.rotation.matrix();
        let mut m = Sim3Matrix::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
        m.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&(hat(&self.translation) * r));
        m.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&r.map(|v| v * self.scale));
        m.fixed_view_mut::<3, 1>(3, 6)
            .copy_from(&(-self.translation));
        m[(6, 6)] = S::one();
        m
    }
    /// `Σ ad_τᵏ/(k+1)!`.
    fn left_jacobian(tau: &Sim3Tangent<S>) -> Sim3Matrix<S> {
        phi_series(&Sim3::small_adjoint(tau))
    }
    /// The block inverse of `[[J, 0, 0], [C, D, e], [0, 0, 1]]`.
    fn left_jacobian_inverse(tau: &Sim3Tangent<S>) -> Sim3Matrix<S> {
        let jl = Self::left_jacobian(tau);
        let j_inv = inverse3(&jl.fixed_view::<3, 3>(0, 0).into_owned());
        let d_inv = inverse3(&jl.fixed_view::<3, 3>(3, 3).into_owned());
        let c = jl.fixed_view::<3, 3>(3, 0).into_owned();
        let e = jl.fixed_view::<3, 1>(3, 6).into_owned();
        let mut m = Sim3Matrix::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&j_inv);
        m.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&(-(d_inv * c * j_inv)));
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(&d_inv);
        m.fixed_view_mut::<3, 1>(3, 6).copy_from(&(-(d_inv * e)));
        m[(6, 6)] = S::one();
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::DualSVec64;

    type D = DualSVec64<7>;

    fn tangents() -> Vec<Sim3Tangent<f64>> {
        [
            [0.3, -0.2, 0.5, 1.0, -2.0, 0.5, 0.4],
            [-1.2, 2.0, 0.7, -0.3, 0.8, 2.5, -0.9],
            [0.01, 0.02, -0.01, 3.0, 1.0, -1.0, 1.5],
        ]
        .iter()
        .map(|t| Sim3Tangent::from_row_slice(t))
        .collect()
    }

    fn lift(x: &Sim3<f64>) -> Sim3<D> {
        let q = x.rotation.quaternion;
        Sim3::new(
            So3::from_quaternion(crate::lie::Quaternion::new(
                D::from_re(q.x),
                D::from_re(q.y),
                D::from_re(q.z),
                D::from_re(q.w),
            )),
            x.translation.map(D::from_re),
            D::from_re(x.scale),
        )
    }

    /// The Jacobian at `δ = 0` of `f`, by dual numbers.
    fn jacobian(f: impl Fn(&Sim3Tangent<D>) -> Sim3Tangent<D>) -> Sim3Matrix<f64> {
        let delta = Sim3Tangent::<D>::from_fn(|i, _| D::from_re(0.0).derivative(i));
        let y = f(&delta);
        Sim3Matrix::from_fn(|r, c| y[r].eps.0.map_or(0.0, |e| e[c]))
    }

    fn close(a: &Sim3Matrix<f64>, b: &Sim3Matrix<f64>) {
        let e = (a - b).norm() / b.norm().max(1.0);
        assert!(e < 1e-12, "{e:e}\n{a}\n{b}");
    }

    #[test]
    fn exp_and_log_are_inverse_and_compose_like_matrices() {
        for tau in tangents() {
            let x = Sim3::exp(&tau);
            assert!((x.log() - tau).norm() < 1e-12);
            let y = Sim3::exp(&(tau * 0.5));
            let product = x.compose(&y).matrix();
            assert!((product - x.matrix() * y.matrix()).norm() < 1e-12);
            let id = x.compose(&x.inverse()).matrix();
            assert!((id - Matrix4::identity()).norm() < 1e-12);
            let p = Vector3::new(0.3, -1.0, 2.0);
            let h = x.matrix() * p.push(1.0);
            assert!((x.act(&p) - h.xyz()).norm() < 1e-12);
        }
    }

    #[test]
    fn jacobians_and_adjoint_match_dual_numbers() {
        for tau in tangents() {
            let x = Sim3::exp(&tau);
            let (xd, taud) = (lift(&x), tau.map(D::from_re));
            // Exp(τ + δ) Exp(τ)⁻¹ = Exp(Jl δ).
            let left = jacobian(|d| {
                Sim3::exp(&(taud + d))
                    .compose(&Sim3::exp(&taud).inverse())
                    .log()
            });
            close(&Sim3::left_jacobian(&tau), &left);
            // Exp(τ)⁻¹ Exp(τ + δ) = Exp(Jr δ).
            let right = jacobian(|d| {
                Sim3::exp(&taud)
                    .inverse()
                    .compose(&Sim3::exp(&(taud + d)))
                    .log()
            });
            close(&Sim3::right_jacobian(&tau), &right);
            // X Exp(δ) X⁻¹ = Exp(Ad δ).
            let adjoint = jacobian(|d| xd.compose(&Sim3::exp(d)).compose(&xd.inverse()).log());
            close(&x.adjoint(), &adjoint);
            close(
                &(Sim3::left_jacobian(&tau) * Sim3::left_jacobian_inverse(&tau)),
                &Sim3Matrix::identity(),
            );
            close(
                &(Sim3::right_jacobian(&tau) * Sim3::right_jacobian_inverse(&tau)),
                &Sim3Matrix::identity(),
            );
        }
    }
}
