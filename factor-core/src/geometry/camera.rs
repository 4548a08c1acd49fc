//! The pinhole camera `K = [f_u, f_v, c_u, c_v]` and its line projection matrix.

use nalgebra::{Matrix3, Vector2, Vector3};

use crate::scalar::Scalar;
use crate::storage::{Layout, Storage, StorageError};

/// Pinhole intrinsics; pixel `= [f_u X/Z + c_u, f_v Y/Z + c_v]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Intrinsics<S> {
    /// Focal length along `u`.
    pub fu: S,
    /// Focal length along `v`.
    pub fv: S,
    /// Principal point `u`.
    pub cu: S,
    /// Principal point `v`.
    pub cv: S,
}

impl<S: Scalar> Intrinsics<S> {
    /// From `[f_u, f_v, c_u, c_v]`.
    pub fn new(fu: S, fv: S, cu: S, cv: S) -> Self {
        Intrinsics { fu, fv, cu, cv }
    }

    /// The pixel of a camera-frame point (document 000 (2)). `Z ≠ 0` is the
    /// caller's to check.
    pub fn project(&self, p: &Vector3<S>) -> Vector2<S> {
        let inv_z = p.z.recip();
        Vector2::new(
            self.fu * p.x * inv_z + self.cu,
            self.fv * p.y * inv_z + self.cv,
        )
    }

    /// The line projection matrix `𝒦 = [[f_v, 0, 0], [0, f_u, 0],
    /// [−f_v c_u, −f_u c_v, f_u f_v]]` of document 000 §III: the image line of a
    /// camera-frame Plücker line is `l = 𝒦 n_c` (up to scale).
    pub fn line_projection_matrix(&self) -> Matrix3<S> {
        let z = S::zero();
        Matrix3::new(
            self.fv,
            z,
            z,
            z,
            self.fu,
            z,
            -self.fv * self.cu,
            -self.fu * self.cv,
            self.fu * self.fv,
        )
    }

    /// `𝒦 n_c`, without forming the zeros of `𝒦`.
    pub fn project_line(&self, n_c: &Vector3<S>) -> Vector3<S> {
        let l1 = self.fv * n_c.x;
        let l2 = self.fu * n_c.y;
        Vector3::new(
            l1,
            l2,
            self.fu * self.fv * n_c.z - self.cu * l1 - self.cv * l2,
        )
    }
}

/// Stored `[fu, fv, cu, cv]`; from users, non-zero focal lengths.
impl<S: Scalar> Storage<S> for Intrinsics<S> {
    type With<T: Scalar> = Intrinsics<T>;
    const SCALARS: usize = 4;
    fn layout() -> Layout {
        Layout::array(&["fu", "fv", "cu", "cv"])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Intrinsics<T> {
        Intrinsics::new(f(self.fu), f(self.fv), f(self.cu), f(self.cv))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        Intrinsics::new(next(), next(), next(), next())
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        for (i, name) in [(0, "f_u"), (1, "f_v")] {
            if input[i] == 0.0 {
                return Err(StorageError::new(format!("focal length {name} is zero"))
                    .within(&format!("[{i}]")));
            }
        }
        Ok(input.to_vec())
    }
}
