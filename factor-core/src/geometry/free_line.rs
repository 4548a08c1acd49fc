//! The free line `l = [q_WL, d_L]` of document 001 §1: a frame `L` with its
//! x axis along the line, its origin on the line at distance `d_L` from the
//! world origin, and its z axis pointing away from the origin.

use nalgebra::Vector3;

use crate::dual::Dual;
use crate::lie::Quaternion;
use crate::lie::so3::{perturb_quaternion, quaternion_local, seeded_quaternion, write3};
use crate::linalg::scale;
use crate::manifold::{Manifold, NoLocal, Perturbation};
use crate::scalar::Scalar;
use crate::storage::{Layout, Storage, StorageError};

/// `[q_WL, d_L]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeLine<S> {
    /// `q_WL`, the orientation of the line frame in the world (unit).
    pub rotation: Quaternion<S>,
    /// `d_L`, the distance of the anchor from the world origin.
    pub distance: S,
}

impl<S: Scalar> FreeLine<S> {
    /// From `q_WL` (unit) and `d_L`.
    pub fn new(rotation: Quaternion<S>, distance: S) -> Self {
        FreeLine { rotation, distance }
    }

    /// The anchor `_W P_L = R(q_WL) [0, 0, d_L]` (001 (1.2)).
    pub fn anchor(&self) -> Vector3<S> {
        let z = S::zero();
        scale(
            self.distance,
            &self.rotation.rotate(&Vector3::new(z, z, S::one())),
        )
    }

    /// The direction `_W x_L = R(q_WL) [1, 0, 0]` (001 (1.3)).
    pub fn direction(&self) -> Vector3<S> {
        let z = S::zero();
        self.rotation.rotate(&Vector3::new(S::one(), z, z))
    }
}

/// Stored `{rotation: [qx, qy, qz, qw], distance}` (`q_WL`, `d_L`).
impl<S: Scalar> Storage<S> for FreeLine<S> {
    type With<T: Scalar> = FreeLine<T>;
    const SCALARS: usize = 5;
    fn layout() -> Layout {
        Layout::Record(vec![
            ("rotation", <Quaternion<S> as Storage<S>>::layout()),
            ("distance", Layout::Scalar),
        ])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> FreeLine<T> {
        FreeLine::new(self.rotation.map_scalars(f), f(self.distance))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        let rotation = Quaternion::read_scalars(next);
        FreeLine::new(rotation, next())
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        let mut stored = <Quaternion<f64> as Storage<f64>>::from_input(&input[..4])
            .map_err(|e| e.within("rotation"))?;
        stored.push(input[4]);
        Ok(stored)
    }
}

/// Tangent `[δθ, δd]` (4). Left (as the specification pins it):
/// `q_WL ← exp(δθ) ⊗ q_WL`; right: `q_WL ← q_WL ⊗ exp(δθ)`; always
/// `d_L ← d_L + δd`.
impl<S: Scalar> Manifold<S> for FreeLine<S> {
    const DIM: usize = 4;
    fn retract(&self, delta: &[S], side: Perturbation) -> Self {
        Self::new(
            perturb_quaternion(&self.rotation, delta, side, Quaternion::exp),
            self.distance + delta[3],
        )
    }
    fn retract_first_order(&self, delta: &[S], side: Perturbation) -> Self {
        Self::new(
            perturb_quaternion(&self.rotation, delta, side, Quaternion::exp_first_order),
            self.distance + delta[3],
        )
    }
    /// In closed form: `q_WL` as [`So3`](crate::lie::So3)'s
    /// (`seeded_quaternion`), `d_L` additive at `offset + 3`.
    #[inline(always)]
    fn seeded<const D: usize, const N: usize>(
        &self,
        side: Perturbation,
        offset: usize,
    ) -> <Self as Storage<S>>::With<Dual<N>>
    where
        S: Into<f64>,
    {
        FreeLine::new(
            seeded_quaternion(&self.rotation, side, offset),
            Dual::variable(self.distance.into(), offset + 3),
        )
    }
    fn tangent_description(side: Perturbation) -> &'static str {
        match side {
            Perturbation::Left => {
                "left: q_WL ← exp(δθ) ⊗ q_WL, d_L ← d_L + δd, columns [δθ_x, δθ_y, δθ_z, δd]"
            }
            Perturbation::Right => {
                "right: q_WL ← q_WL ⊗ exp(δθ), d_L ← d_L + δd, columns [δθ_x, δθ_y, δθ_z, δd]"
            }
        }
    }
    fn local(&self, other: &Self, side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        write3(
            &quaternion_local(&self.rotation, &other.rotation, side),
            delta,
        );
        delta[3] = other.distance - self.distance;
        Ok(())
    }
}
