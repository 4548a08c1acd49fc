//! Small helpers the transcribed catalogues share: matrices in the audit's
//! dynamic form, and poses, vectors and quaternions read from (or written
//! to) a derivation's flat parameter list.

use nalgebra::{DMatrix, SMatrix, Vector3};

use factor_core::lie::{Quaternion, Se3, So3};
use factor_core::scalar::Scalar;

/// A fixed-size matrix as a `DMatrix`.
pub fn matrix<const R: usize, const C: usize>(m: SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

/// `x[0..3]` as a vector.
pub fn vec3<S: Scalar>(x: &[S]) -> Vector3<S> {
    Vector3::new(x[0], x[1], x[2])
}

/// `x[0..4]` as a quaternion `[x, y, z, w]`.
pub fn quaternion<S: Scalar>(x: &[S]) -> Quaternion<S> {
    Quaternion::new(x[0], x[1], x[2], x[3])
}

/// A pose from parameters `[qx, qy, qz, qw, tx, ty, tz]`.
pub fn pose_from<S: Scalar>(p: &[S]) -> Se3<S> {
    Se3::new(So3::from_quaternion(quaternion(p)), vec3(&p[4..7]))
}

/// A pose's parameters `[qx, qy, qz, qw, tx, ty, tz]`, named for LaTeX.
pub fn pose_parameters(pose: &Se3<f64>) -> Vec<(&'static str, f64)> {
    let q = pose.rotation.quaternion;
    let t = pose.translation;
    vec![
        ("q_x", q.x),
        ("q_y", q.y),
        ("q_z", q.z),
        ("q_w", q.w),
        ("t_x", t.x),
        ("t_y", t.y),
        ("t_z", t.z),
    ]
}
