//! Sampled configurations of the point and plane kernels, as the kernels'
//! inputs concatenated in field order.

use core::f64::consts::PI;

use factor_core::Storage;
use factor_core::lie::Quaternion;
use factor_testing::samples::Sampler;
use nalgebra::Vector3;

/// The stored scalars of `value`, in storage order.
pub fn scalars<V: Storage<f64>>(value: &V) -> Vec<f64> {
    value.to_scalars()
}

/// A realistic point-reprojection configuration: intrinsics (4), observed
/// (2), pose (7), point (3).
pub fn point(sampler: &mut Sampler) -> Vec<f64> {
    let f = sampler.point_reprojection();
    [
        scalars(&f.intrinsics),
        scalars(&f.observed),
        scalars(&f.pose),
        scalars(&f.point),
    ]
    .concat()
}

/// A plane configuration, measured (4), pose (7), plane (4), whose measured
/// plane is the exact one rotated by `angle` radians about a random axis on
/// the quaternion sphere: the residual's angle is then `angle`, and the
/// kernel's branch variable `tan²(angle/2)`.
pub fn plane_at_angle(sampler: &mut Sampler, angle: f64) -> Vec<f64> {
    let f = sampler.plane_with_error(0.0);
    let axis = sampler.rotation().rotate(&Vector3::z());
    let measured = Quaternion::exp(&(axis * angle))
        .mul(&Quaternion::from_coords(f.measured.normalize()))
        .coords()
        * f.measured.norm();
    [scalars(&measured), scalars(&f.pose), scalars(&f.plane)].concat()
}

/// The angle at which the plane kernel switches to its small-angle series:
/// `tan²(θ/2) = 10⁻⁶`.
pub fn plane_series_threshold() -> f64 {
    2.0 * 1e-3f64.atan()
}

/// `value · (1 ± u)`, `u` log-uniform in `[10⁻¹², 10⁻²]`, either sign.
pub fn near(sampler: &mut Sampler, value: f64) -> f64 {
    let u = sampler.uniform(1e-12f64.ln(), 1e-2f64.ln()).exp();
    if sampler.uniform(0.0, 1.0) < 0.5 {
        value * (1.0 - u)
    } else {
        value * (1.0 + u)
    }
}

/// The angle where the plane kernel's other branch switches (`w = 0`).
pub const PLANE_W_ZERO: f64 = PI;
