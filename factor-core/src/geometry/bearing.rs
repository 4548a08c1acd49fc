//! The bearing-vector measurement of document 001 §2.

use nalgebra::Vector3;

use crate::linalg::{cross, normalized};
use crate::scalar::Scalar;

/// `ñ = f₁ × f₂ / ‖f₁ × f₂‖`, the unit normal of the plane spanned by the
/// bearing vectors through a segment's endpoints. Undefined when the bearings
/// are parallel; factors using it reject that case in their validation.
pub fn bearing_plane_normal<S: Scalar>(f1: &Vector3<S>, f2: &Vector3<S>) -> Vector3<S> {
    normalized(&cross(f1, f2))
}
