//! Sim(3): similarity transforms `X ↦ s R X + t`, a composite variable
//! stored as its parts (rotation, translation, log-scale `σ = ln s`), as
//! monocular SLAM uses for loop closures, where the scale drifts.
//!
//! As a matrix `S = [[s R, t], [0, 1]]`; the tangent is `ξ = [ω, ρ, σ]`
//! (rotation first, as for SE(3)), `ξ^ = [[[ω]× + σ I, ρ], [0, 0]]`, and:
//!
//! - `Exp([ω, ρ, σ]) = (Exp(ω), W(ω, σ) ρ, σ)` with
//!   `W(ω, σ) = ∫₀¹ e^{tσ} Exp(tω) dt` ([`w_matrix()`]); `Log` its inverse for
//!   rotation angles `θ ≤ π`;
//! - `(R₁, t₁, σ₁)(R₂, t₂, σ₂) = (R₁ R₂, s₁ R₁ t₂ + t₁, σ₁ + σ₂)`,
//!   `S⁻¹ = (Rᵀ, −s⁻¹ Rᵀ t, −σ)`;
//! - `Ad_S = [[R, 0, 0], [t^ R, s R, −t], [0, 0, 1]]`:
//!   `S Exp(ξ) S⁻¹ = Exp(Ad_S ξ)`.
//!
//! The type does not implement `factor_core::lie::LieGroup`: that trait also
//! requires the left Jacobian and its inverse in closed form, whose
//! translation-rotation block for Sim(3) needs the derivatives of `W`'s three
//! coefficients in both `θ²` and `σ`, each with its own removable
//! singularities. Nothing on the way to a factor's Jacobian needs them: dual
//! numbers and the tracer differentiate the residual through [`Sim3::log`].

pub mod w_matrix;

use factor_core::lie::so3::hat;
use factor_core::lie::{Quaternion, So3};
use factor_core::linalg::cross;
use factor_core::manifold::NoLocal;
use factor_core::{Layout, Manifold, Perturbation, Scalar, Storage, StorageError};
use nalgebra::{Matrix3, Matrix4, SMatrix, SVector, Vector3};

pub use w_matrix::{w_matrix, w_matrix_inverse};

/// A Sim(3) tangent `[ω, ρ, σ]`.
pub type Sim3Tangent<S> = SVector<S, 7>;

/// A similarity transform `X ↦ e^σ R X + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sim3<S> {
    /// `R`.
    pub rotation: So3<S>,
    /// `t`.
    pub translation: Vector3<S>,
    /// `σ = ln s`: the scale `s = e^σ` is positive by construction.
    pub log_scale: S,
}

/// `(ω, ρ, σ)` of `ξ = [ω, ρ, σ]`.
fn split<S: Scalar>(xi: &[S]) -> (Vector3<S>, Vector3<S>, S) {
    (
        Vector3::new(xi[0], xi[1], xi[2]),
        Vector3::new(xi[3], xi[4], xi[5]),
        xi[6],
    )
}

impl<S: Scalar> Sim3<S> {
    /// From `R`, `t` and `σ = ln s`.
    pub fn new(rotation: So3<S>, translation: Vector3<S>, log_scale: S) -> Self {
        Sim3 {
            rotation,
            translation,
            log_scale,
        }
    }

    /// The identity.
    pub fn identity() -> Self {
        Self::new(So3::identity(), Vector3::zeros(), S::zero())
    }

    /// `s = e^σ`.
    pub fn scale(&self) -> S {
        self.log_scale.exp()
    }

    /// `s R X + t`.
    pub fn transform_point(&self, x: &Vector3<S>) -> Vector3<S> {
        let s = self.scale();
        self.rotation.rotate(x).map(|c| s * c) + self.translation
    }

    /// `self · rhs`.
    pub fn compose(&self, rhs: &Self) -> Self {
        Self::new(
            self.rotation.compose(&rhs.rotation),
            self.transform_point(&rhs.translation),
            self.log_scale + rhs.log_scale,
        )
    }

    /// `S⁻¹ = (Rᵀ, −s⁻¹ Rᵀ t, −σ)`.
    pub fn inverse(&self) -> Self {
        let r_inv = self.rotation.inverse();
        let s_inv = (-self.log_scale).exp();
        Self::new(
            r_inv,
            r_inv.rotate(&self.translation).map(|c| -(s_inv * c)),
            -self.log_scale,
        )
    }

    /// The exact exponential `Exp([ω, ρ, σ]) = (Exp(ω), W(ω, σ) ρ, σ)`.
    pub fn exp(xi: &Sim3Tangent<S>) -> Self {
        let (omega, rho, sigma) = split(xi.as_slice());
        Self::new(So3::exp(&omega), w_matrix(&omega, sigma) * rho, sigma)
    }

    /// `Log(S) = [ω, W(ω, σ)⁻¹ t, σ]`, `ω = Log(R)` (`θ ≤ π`).
    pub fn log(&self) -> Sim3Tangent<S> {
        let omega = self.rotation.log();
        let rho = w_matrix_inverse(&omega, self.log_scale) * self.translation;
        Sim3Tangent::from_column_slice(&[
            omega.x,
            omega.y,
            omega.z,
            rho.x,
            rho.y,
            rho.z,
            self.log_scale,
        ])
    }

    /// `Ad_S = [[R, 0, 0], [t^ R, s R, −t], [0, 0, 1]]`, rows and columns in
    /// the tangent order `[ω, ρ, σ]`.
    pub fn adjoint(&self) -> SMatrix<S, 7, 7> {
        let r = self.rotation.matrix();
        let s = self.scale();
        let mut ad = SMatrix::<S, 7, 7>::zeros();
        ad.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
        ad.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&(hat(&self.translation) * r));
        ad.fixed_view_mut::<3, 3>(3, 3).copy_from(&r.map(|x| s * x));
        ad.fixed_view_mut::<3, 1>(3, 6)
            .copy_from(&(-self.translation));
        ad[(6, 6)] = S::one();
        ad
    }

    /// The homogeneous 4×4 matrix `[[s R, t], [0, 1]]`.
    pub fn matrix(&self) -> Matrix4<S> {
        let s = self.scale();
        let sr: Matrix3<S> = self.rotation.matrix().map(|x| s * x);
        let mut m = Matrix4::identity();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&sr);
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.translation);
        m
    }
}

/// Stored as its parts, `{rotation: [qx, qy, qz, qw], translation: [x, y, z],
/// log_scale}`; from users, the rotation is checked as a quaternion.
impl<S: Scalar> Storage<S> for Sim3<S> {
    type With<T: Scalar> = Sim3<T>;
    const SCALARS: usize = 8;
    fn layout() -> Layout {
        Layout::Record(vec![
            ("rotation", So3::<S>::layout()),
            ("translation", Vector3::<S>::layout()),
            ("log_scale", Layout::Scalar),
        ])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Sim3<T> {
        // Fields in storage order: the closure sees the scalars in that order.
        let rotation = self.rotation.map_scalars(f);
        let translation = self.translation.map_scalars(f);
        Sim3::new(rotation, translation, f(self.log_scale))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        let rotation = So3::read_scalars(next);
        let translation = Vector3::read_scalars(next);
        Self::new(rotation, translation, next())
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        let mut stored = So3::<f64>::from_input(&input[..4]).map_err(|e| e.within("rotation"))?;
        stored.extend_from_slice(&input[4..]);
        Ok(stored)
    }
}

/// Tangent `[δω, δρ, δσ]` (7).
/// - Left: `S ← Exp(δ) S` with the exact exponential; to first order
///   `q ← [δω/2, 1] ⊗ q`, `t ← t + δω × t + δσ t + δρ`, `σ ← σ + δσ`.
/// - Right: `S ← S Exp(δ)`; to first order `q ← q ⊗ [δω/2, 1]`,
///   `t ← t + s R δρ`, `σ ← σ + δσ`.
/// - `local`: the logarithm of `S' S⁻¹` (left) or `S⁻¹ S'` (right), its
///   rotation by the quaternion logarithm on the whole sphere (`θ < 2π`, not
///   [`Sim3::log`]'s `θ ≤ π`), so that retracting by it gives back `S'`'s
///   own quaternion, not its negation (a solver's manifold, Ceres' `Minus`,
///   is generated from it).
impl<S: Scalar> Manifold<S> for Sim3<S> {
    const DIM: usize = 7;
    fn retract(&self, delta: &[S], side: Perturbation) -> Self {
        let step = Self::exp(&Sim3Tangent::from_column_slice(delta));
        match side {
            Perturbation::Left => step.compose(self),
            Perturbation::Right => self.compose(&step),
        }
    }
    fn retract_first_order(&self, delta: &[S], side: Perturbation) -> Self {
        let (omega, rho, sigma) = split(delta);
        let q = self.rotation.quaternion;
        let step = Quaternion::exp_first_order(&omega);
        let (q, t) = match side {
            Perturbation::Left => (
                step.mul(&q),
                self.translation
                    + cross(&omega, &self.translation)
                    + self.translation.map(|c| sigma * c)
                    + rho,
            ),
            Perturbation::Right => (
                q.mul(&step),
                self.translation + self.rotation.rotate(&rho).map(|c| self.scale() * c),
            ),
        };
        Self::new(So3::from_quaternion(q), t, self.log_scale + sigma)
    }
    fn tangent_description(side: Perturbation) -> &'static str {
        match side {
            Perturbation::Left => {
                "left: S ← Exp(δξ) S, columns δξ = [δω_x, δω_y, δω_z, δρ_x, δρ_y, δρ_z, δσ]"
            }
            Perturbation::Right => {
                "right: S ← S Exp(δξ), columns δξ = [δω_x, δω_y, δω_z, δρ_x, δρ_y, δρ_z, δσ]"
            }
        }
    }
    fn local(&self, other: &Self, side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        let step = match side {
            Perturbation::Left => other.compose(&self.inverse()),
            Perturbation::Right => self.inverse().compose(other),
        };
        let omega = step.rotation.quaternion.log();
        let rho = w_matrix_inverse(&omega, step.log_scale) * step.translation;
        delta[..3].copy_from_slice(omega.as_slice());
        delta[3..6].copy_from_slice(rho.as_slice());
        delta[6] = step.log_scale;
        Ok(())
    }
}
