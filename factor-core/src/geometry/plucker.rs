//! Plücker lines `L = [n, v]` (document 000 §III): `n` is the normal of the
//! plane through the line and the origin, `v` the direction; `n · v = 0` and
//! the distance to the origin is `|n| / |v|`.

use nalgebra::{Matrix3, Matrix6, Vector3};

use crate::dual::Dual;
use crate::lie::Se3;
use crate::lie::so3::hat;
use crate::linalg::cross;
use crate::manifold::{Manifold, NoLocal, Perturbation};
use crate::scalar::Scalar;
use crate::storage::{Layout, Storage, StorageError};

/// A line `[n, v]`, defined up to a non-zero scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PluckerLine<S> {
    /// Moment `n`.
    pub normal: Vector3<S>,
    /// Direction `v`.
    pub direction: Vector3<S>,
}

impl<S: Scalar> PluckerLine<S> {
    /// From `n` and `v`.
    pub fn new(normal: Vector3<S>, direction: Vector3<S>) -> Self {
        PluckerLine { normal, direction }
    }

    /// The line through Euclidean points `P` and `Q` (homogeneous weights 1):
    /// `n = P × Q`, `v = Q − P`.
    pub fn from_points(p: &Vector3<S>, q: &Vector3<S>) -> Self {
        Self::new(cross(p, q), q - p)
    }

    /// The line in the frame a pose maps into: `n' = R n + t × (R v)`,
    /// `v' = R v`, i.e. `H L` with [`PluckerLine::transform_matrix`].
    pub fn transform(&self, pose: &Se3<S>) -> Self {
        let rv = pose.rotation.rotate(&self.direction);
        let n = pose.rotation.rotate(&self.normal) + cross(&pose.translation, &rv);
        Self::new(n, rv)
    }

    /// The 6×6 line motion matrix `H = [[R, [t]× R], [0, R]]` of document 000 (8).
    pub fn transform_matrix(pose: &Se3<S>) -> Matrix6<S> {
        let r: Matrix3<S> = pose.rotation.matrix();
        let tr = hat(&pose.translation) * r;
        let mut h = Matrix6::zeros();
        h.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
        h.fixed_view_mut::<3, 3>(0, 3).copy_from(&tr);
        h.fixed_view_mut::<3, 3>(3, 3).copy_from(&r);
        h
    }
}

/// Stored `{normal: [x, y, z], direction: [x, y, z]}`; from users, a
/// non-zero direction (the normal may be zero: a line through the origin).
impl<S: Scalar> Storage<S> for PluckerLine<S> {
    type With<T: Scalar> = PluckerLine<T>;
    const SCALARS: usize = 6;
    fn layout() -> Layout {
        let xyz = <Vector3<S> as Storage<S>>::layout;
        Layout::Record(vec![("normal", xyz()), ("direction", xyz())])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> PluckerLine<T> {
        PluckerLine::new(self.normal.map_scalars(f), self.direction.map_scalars(f))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        let normal = Vector3::read_scalars(next);
        PluckerLine::new(normal, Vector3::read_scalars(next))
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        if input[3..].iter().all(|x| *x == 0.0) {
            return Err(StorageError::new("line direction v has zero norm").within("direction"));
        }
        Ok(input.to_vec())
    }
}

/// Plücker coordinates as an over-parametrised 6-vector: additive
/// `[n, v] ← [n, v] + δ`, columns `[δn, δv]`. The 4-dof alternative is
/// [`crate::geometry::OrthonormalLine`].
impl<S: Scalar> Manifold<S> for PluckerLine<S> {
    const DIM: usize = 6;
    fn retract(&self, delta: &[S], _side: Perturbation) -> Self {
        Self::new(
            self.normal + Vector3::new(delta[0], delta[1], delta[2]),
            self.direction + Vector3::new(delta[3], delta[4], delta[5]),
        )
    }
    /// In closed form, each vector as a vector space's.
    #[inline(always)]
    fn seeded<const D: usize, const N: usize>(
        &self,
        side: Perturbation,
        offset: usize,
    ) -> <Self as Storage<S>>::With<Dual<N>>
    where
        S: Into<f64>,
    {
        PluckerLine::new(
            self.normal.seeded::<3, N>(side, offset),
            self.direction.seeded::<3, N>(side, offset + 3),
        )
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "additive: [n, v] ← [n, v] + δ, columns [δn_x, δn_y, δn_z, δv_x, δv_y, δv_z]"
    }
    fn local(&self, other: &Self, _side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        let (n, v) = (other.normal - self.normal, other.direction - self.direction);
        delta[..3].copy_from_slice(n.as_slice());
        delta[3..6].copy_from_slice(v.as_slice());
        Ok(())
    }
}
