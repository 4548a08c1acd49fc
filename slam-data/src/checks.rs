//! Checks of rotations and information matrices read from files, with their
//! tolerances; shared by the readers and the writers.

use nalgebra::{Cholesky, Matrix3, Matrix6, Rotation3, SMatrix, SymmetricEigen, UnitQuaternion};

use crate::input::all_in_range;

/// A 3×3 matrix is taken as a rotation when every entry of `RᵀR − I`, and
/// `det R − 1`, is within this of zero. Text with six significant digits
/// (the KITTI VO poses) is off by up to 1e-6.
pub const ROTATION_TOLERANCE: f64 = 1e-5;

/// A quaternion is taken as a rotation when its norm is within this of one
/// (and then renormalised). Text with six decimals (the g2o example) is off
/// by up to 1e-6.
pub const QUATERNION_TOLERANCE: f64 = 1e-5;

/// Fails unless `m` is a rotation within [`ROTATION_TOLERANCE`].
pub(crate) fn check_rotation_matrix(m: &Matrix3<f64>) -> Result<(), String> {
    let orthogonality = (m.transpose() * m - Matrix3::identity()).amax();
    let determinant = m.determinant();
    if orthogonality <= ROTATION_TOLERANCE && (determinant - 1.0).abs() <= ROTATION_TOLERANCE {
        Ok(())
    } else {
        Err(format!(
            "not a rotation matrix: max |RᵀR − I| = {orthogonality:.3e}, det R = {determinant:.6} \
             (tolerance {ROTATION_TOLERANCE:e})"
        ))
    }
}

/// The rotation nearest to `m`, a matrix that passed [`check_rotation_matrix`].
pub(crate) fn nearest_rotation(m: &Matrix3<f64>) -> Rotation3<f64> {
    // Müller et al.'s iteration from `m` itself: a few steps for a matrix
    // this close to a rotation; the cap keeps it bounded regardless.
    Rotation3::from_matrix_eps(m, f64::EPSILON, 64, Rotation3::from_matrix_unchecked(*m))
}

/// Fails unless the quaternion `[x, y, z, w]` has norm within
/// [`QUATERNION_TOLERANCE`] of one.
pub(crate) fn check_quaternion(q: &[f64; 4]) -> Result<(), String> {
    let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    if (norm - 1.0).abs() <= QUATERNION_TOLERANCE {
        Ok(())
    } else {
        Err(format!(
            "not a unit quaternion: norm {norm:.9} (tolerance {QUATERNION_TOLERANCE:e})"
        ))
    }
}

/// The unit quaternion of `[x, y, z, w]` (renormalised).
pub(crate) fn unit_quaternion(q: &[f64; 4]) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[3], q[0], q[1], q[2]))
}

/// Fails unless every entry of `m` is in range ([`crate::MAX_MAGNITUDE`])
/// and `m` is symmetric: what every information matrix must be.
fn check_symmetric_in_range<const N: usize>(m: &SMatrix<f64, N, N>) -> Result<(), String> {
    if !all_in_range(m.iter()) {
        return Err("non-finite or too large information entry".into());
    }
    if m != &m.transpose() {
        return Err("information matrix is not symmetric".into());
    }
    Ok(())
}

/// Fails unless `m` is in range ([`crate::MAX_MAGNITUDE`]), symmetric and
/// positive definite (its Cholesky factorisation exists).
pub(crate) fn check_information<const N: usize>(m: &SMatrix<f64, N, N>) -> Result<(), String> {
    check_symmetric_in_range(m)?;
    if Cholesky::new(*m).is_none() {
        return Err("information matrix is not positive definite".into());
    }
    Ok(())
}

/// Eigenvalues below this times the largest one are taken as zero by
/// [`check_semidefinite_information`] (rounding of a matrix written as
/// text).
const SEMIDEFINITE_TOLERANCE: f64 = 1e-12;

/// Fails unless `m` is in range, symmetric, positive semi-definite (no
/// eigenvalue below `−1e-12` times the largest) and not zero: the
/// information of a prior that constrains some directions only.
pub(crate) fn check_semidefinite_information(m: &Matrix6<f64>) -> Result<(), String> {
    check_symmetric_in_range(m)?;
    let eigenvalues = SymmetricEigen::new(*m).eigenvalues;
    let largest = eigenvalues.max();
    if largest <= 0.0 {
        return Err("information matrix has no positive eigenvalue".into());
    }
    if eigenvalues.min() < -SEMIDEFINITE_TOLERANCE * largest {
        return Err(format!(
            "information matrix is not positive semi-definite (eigenvalue {:.3e})",
            eigenvalues.min()
        ));
    }
    Ok(())
}
