//! Infinite planes as unit quaternions (Kaess, ICRA 2015; document 000 §IV).
//!
//! A plane `π = [a, b, c, d]` (`a x + b y + c z + d = 0`) is the unit
//! quaternion `q(π) = π / |π|` read in storage order `[x, y, z, w]`; `q` and
//! `−q` are the same plane. A pose `T` mapping world to camera sends a camera
//! plane back to the world as `π_w = Tᵀ π_c` (points map forward, planes by the
//! transpose).
//!
//! Sign convention: `π = [n, d]` is the plane `n · x + d = 0` (the
//! documents' and g2o's); [`InfinitePlane::from_normal_offset`] and
//! [`InfinitePlane::normal_offset`] convert from and to `(n, d)` with a
//! unit normal.

use nalgebra::{Vector3, Vector4};

use crate::dual::Dual;
use crate::lie::Quaternion;
use crate::lie::Se3;
use crate::lie::so3::{perturb_quaternion, quaternion_local, seeded_quaternion, write3};
use crate::linalg::{dot, norm, scale, unit_of};
use crate::manifold::{Manifold, NoLocal, Perturbation};
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

    /// The plane `n · x + d = 0` for a normal `n` (any non-zero length) and
    /// offset `d`: `q([n, d])`. With a unit `n` the plane is the points at
    /// signed distance `−d` from the origin along `n`, `n · x = −d` (the
    /// floor `z = −5` with `n = (0, 0, 1)` has `d = 5`). Unchecked; see
    /// [`InfinitePlane::try_from_normal_offset`].
    pub fn from_normal_offset(normal: &Vector3<S>, offset: S) -> Self {
        Self::from_coefficients(&Vector4::new(normal.x, normal.y, normal.z, offset))
    }

    /// `(n, d)` with `|n| = 1` and `n · x + d = 0`: `[a, b, c] / |[a, b, c]|`
    /// and `d / |[a, b, c]|`. The quaternion `−q` (the same plane) gives
    /// `(−n, −d)`. A plane at infinity (`a = b = c = 0`) has no normal.
    pub fn normal_offset(&self) -> (Vector3<S>, S) {
        let q = self.quaternion;
        let inv = norm(&q.vector()).recip();
        (scale(inv, &q.vector()), q.w * inv)
    }
}

impl InfinitePlane<f64> {
    /// [`InfinitePlane::from_normal_offset`], checked: `n` non-zero and
    /// everything finite (any scale of `[n, d]`, normalised over the whole
    /// `f64` range).
    pub fn try_from_normal_offset(
        normal: &Vector3<f64>,
        offset: f64,
    ) -> Result<Self, StorageError> {
        if !(normal.iter().all(|x| x.is_finite()) && offset.is_finite()) {
            return Err(StorageError::new(
                "the plane's normal or offset is not finite",
            ));
        }
        if normal.iter().all(|x| *x == 0.0) {
            return Err(StorageError::new("the plane's normal n is zero"));
        }
        let unit = unit_of(&Vector4::new(normal.x, normal.y, normal.z, offset))
            .expect("a non-zero finite vector");
        Ok(InfinitePlane {
            quaternion: Quaternion::from_coords(unit),
        })
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
/// ([`crate::linalg::unit_of`]), with a normal `[a, b, c]` that is not zero.
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
        let unit = unit_of(&Vector4::from_column_slice(input))
            .ok_or_else(|| StorageError::new("plane vector [a, b, c, d] has zero norm"))?;
        // `[0, 0, 0, d]` (or a normal below `d` by more than the range of
        // f64) is no plane: its normal has no direction.
        if unit.xyz() == Vector3::zeros() {
            return Err(StorageError::new(
                "plane vector [a, b, c, d] has a zero normal [a, b, c]: it is no plane",
            ));
        }
        Ok(unit.as_slice().to_vec())
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
    /// In closed form, as [`So3`](crate::lie::So3)'s (`seeded_quaternion`).
    #[inline(always)]
    fn seeded<const D: usize, const N: usize>(
        &self,
        side: Perturbation,
        offset: usize,
    ) -> <Self as Storage<S>>::With<Dual<N>>
    where
        S: Into<f64>,
    {
        InfinitePlane {
            quaternion: seeded_quaternion(&self.quaternion, side, offset),
        }
    }
    fn tangent_description(side: Perturbation) -> &'static str {
        match side {
            Perturbation::Left => "left: q ← exp(δω) ⊗ q, columns [δω_x, δω_y, δω_z]",
            Perturbation::Right => "right: q ← q ⊗ exp(δω), columns [δω_x, δω_y, δω_z]",
        }
    }
    fn local(&self, other: &Self, side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        write3(
            &quaternion_local(&self.quaternion, &other.quaternion, side),
            delta,
        );
        Ok(())
    }
}
