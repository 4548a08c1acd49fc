//! Sampled configurations of the point and plane kernels, as the kernels'
//! inputs concatenated in field order.

use factor_core::Storage;
use factor_testing::branch_points;
use factor_testing::samples::Sampler;

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

/// A plane configuration, measured (4), pose (7), plane (4), whose residual
/// has norm `angle` ([`branch_points::plane_at_angle`]): the kernel's branch
/// variable is then `tan²(angle/2)`.
pub fn plane_at_angle(sampler: &mut Sampler, angle: f64) -> Vec<f64> {
    let f = branch_points::plane_at_angle(sampler, angle);
    [scalars(&f.measured), scalars(&f.pose), scalars(&f.plane)].concat()
}
