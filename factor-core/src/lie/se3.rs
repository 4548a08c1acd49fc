//! SE(3): rigid transforms `T = [R t; 0 1]`, tangent `ξ = [ω, ρ]` (rotation first).
//!
//! Document 000 uses `T` for the world-to-camera map `X_c = R X_w + t`;
//! document 001 names its body pose `T_BW` (`X_B = C_BW X_W + t_BW`). Both are
//! this type; which frames it maps between is the factor's business.

use nalgebra::{Matrix3, Matrix4, Vector3, Vector6};

use crate::lie::so3::{left_jacobian, left_jacobian_inverse, perturb_quaternion};
use crate::lie::{Quaternion, So3};
use crate::linalg::cross;
use crate::manifold::{Manifold, Perturbation};
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

/// Tangent `[δω, δρ]`.
/// - Left (document 000): `T ← Exp(δξ) T` with the exact SE(3) exponential:
///   `R ← Exp(δω) R`, `t ← Exp(δω) t + Jl(δω) δρ`.
/// - Right (document 001, (4.1)–(4.2)): `R ← R Exp(δω)`, `t ← t + R δρ`. This
///   agrees with `T Exp(δξ)` to first order, so the Jacobians are the same.
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
}
