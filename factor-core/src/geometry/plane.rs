//! Infinite planes as unit quaternions (Kaess, ICRA 2015; document 000 §IV).
//!
//! A plane `π = [a, b, c, d]` (`a x + b y + c z + d = 0`) is the unit
//! quaternion `q(π) = π / |π|` read in storage order `[x, y, z, w]`; `q` and
//! `−q` are the same plane. A pose `T` mapping world to camera sends a camera
//! plane back to the world as `π_w = Tᵀ π_c` (points map forward, planes by the
//! transpose).

use nalgebra::Vector4;

use crate::lie::Quaternion;
use crate::lie::Se3;
use crate::lie::so3::perturb_quaternion;
use crate::linalg::{dot, unit_of};
use crate::manifold::{Manifold, Perturbation};
use crate::scalar::Scalar;
use crate::storage::{Layout, Storage, StorageError};

/// An infinite plane stored as a unit quaternion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InfinitePlane<S> {
    /// `q(π)`.
    pub quaternion: Quaternion<S>,
}

impl<S: Scalar> InfinitePlane<S> {
    /// `q(π) = π / |π|`.
    pub fn from_coefficients(pi: &Vector4<S>) -> Self {
        InfinitePlane {
            quaternion: Quaternion::from_coords(*pi).normalized(),
        }
    }

    /// `[a, b, c, d]` with unit norm.
    pub fn coefficients(&self) -> Vector4<S> {
        self.quaternion.coords()
    }
}

/// `Tᵀ π` for `T = [R t; 0 1]`: `[Rᵀ n, tᵀ n + d]` with `π = [n, d]`, the plane
/// `π` of the frame `T` maps into, expressed in the frame `T` maps from
/// (document 000 §IV, `q(π_w) = T_wᶜᵀ q(π_c)`).
pub fn transpose_transform<S: Scalar>(pose: &Se3<S>, pi: &Vector4<S>) -> Vector4<S> {
    let n = pi.xyz();
    let n_from = pose.rotation.inverse_rotate(&n);
    Vector4::new(
        n_from.x,
        n_from.y,
        n_from.z,
        dot(&pose.translation, &n) + pi[3],
    )
}

/// Stored as the unit quaternion `q(π)`, named `[a, b, c, d]`; users give
/// any non-zero scale, normalised over the whole `f64` range
/// ([`crate::linalg::unit_of`]).
impl<S: Scalar> Storage<S> for InfinitePlane<S> {
    type With<T: Scalar> = InfinitePlane<T>;
    const SCALARS: usize = 4;
    fn layout() -> Layout {
        Layout::array(&["a", "b", "c", "d"])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> InfinitePlane<T> {
        InfinitePlane {
            quaternion: self.quaternion.map_scalars(f),
        }
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        InfinitePlane {
            quaternion: Quaternion::read_scalars(next),
        }
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        unit_of(&Vector4::from_column_slice(input))
            .map(|unit| unit.as_slice().to_vec())
            .ok_or_else(|| StorageError::new("plane vector [a, b, c, d] has zero norm"))
    }
}

/// Tangent `δω` (3). Left (document 000 §IV): `q ← exp(δω) ⊗ q`; right:
/// `q ← q ⊗ exp(δω)`, with the quaternion exponential.
impl<S: Scalar> Manifold<S> for InfinitePlane<S> {
    const DIM: usize = 3;
    fn retract(&self, delta: &[S], side: Perturbation) -> Self {
        InfinitePlane {
            quaternion: perturb_quaternion(&self.quaternion, delta, side, Quaternion::exp),
        }
    }
    fn retract_first_order(&self, delta: &[S], side: Perturbation) -> Self {
        InfinitePlane {
            quaternion: perturb_quaternion(
                &self.quaternion,
                delta,
                side,
                Quaternion::exp_first_order,
            ),
        }
    }
    fn tangent_description(side: Perturbation) -> &'static str {
        match side {
            Perturbation::Left => "left: q ← exp(δω) ⊗ q, columns [δω_x, δω_y, δω_z]",
            Perturbation::Right => "right: q ← q ⊗ exp(δω), columns [δω_x, δω_y, δω_z]",
        }
    }
}
