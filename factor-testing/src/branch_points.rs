//! Configurations at the branch points of the shipped factors' kernels,
//! where a `select_lt` switches arms: tests straddle them to exercise both
//! arms and the values between.
//!
//! The plane factor's residual is the quaternion logarithm of the error
//! quaternion, which selects twice: a series below `tan²(θ/2) = 10⁻⁶`
//! ([`PLANE_SERIES_ANGLE`]), and the sign of `w` (the angle `θ` crosses π,
//! [`PLANE_W_ZERO`]).

use core::f64::consts::PI;

use factor_core::geometry::plane::transpose_transform;
use factor_core::lie::Quaternion;
use nalgebra::{Unit, Vector3};
use slam_factors::PlaneFactor;

use crate::samples::Sampler;

/// The error angle at which the plane kernel switches to its small-angle
/// series: `tan²(θ/2) = 10⁻⁶`.
pub const PLANE_SERIES_ANGLE: f64 = 0.001_999_999_333_333_733_6;

/// The error angle at which the plane kernel's other select switches: the
/// error quaternion's `w` changes sign.
pub const PLANE_W_ZERO: f64 = PI;

/// A plane factor whose residual has norm `angle` (up to rounding) about a
/// random axis: the measured plane `π_c` is chosen so that
/// `Tᵀ π_c ∝ exp(angle · axis) ⊗ q_w`.
pub fn plane_at_angle(sampler: &mut Sampler, angle: f64) -> PlaneFactor {
    let mut f = sampler.plane_with_error(0.0);
    let axis = sampler.rotation().rotate(&Vector3::z());
    let y = Quaternion::exp(&(axis * angle))
        .mul(&f.plane.quaternion)
        .coords();
    // `transpose_transform(T⁻¹, ·)` is `T⁻ᵀ`, the inverse of `Tᵀ`.
    f.measured = Unit::new_normalize(transpose_transform(&f.pose.inverse(), &y));
    f
}

/// `value · (1 ± u)`, `u` log-uniform in `[10⁻¹², 10⁻²]`, either sign with
/// equal odds: a value just below or above `value`.
pub fn near(sampler: &mut Sampler, value: f64) -> f64 {
    let u = sampler.uniform(1e-12f64.ln(), 1e-2f64.ln()).exp();
    if sampler.uniform(0.0, 1.0) < 0.5 {
        value * (1.0 - u)
    } else {
        value * (1.0 + u)
    }
}

/// Plane factors around both branch points and across every angle: a
/// quarter each near [`PLANE_SERIES_ANGLE`], near [`PLANE_W_ZERO`],
/// uniform in `[0, 2π)`, and sampled with errors up to 0.3 rad.
pub fn plane_branch_configurations(sampler: &mut Sampler, count: usize) -> Vec<PlaneFactor> {
    (0..count)
        .map(|i| match i % 4 {
            0 => {
                let angle = near(sampler, PLANE_SERIES_ANGLE);
                plane_at_angle(sampler, angle)
            }
            1 => {
                let angle = near(sampler, PLANE_W_ZERO);
                plane_at_angle(sampler, angle)
            }
            2 => {
                let angle = sampler.uniform(0.0, 2.0 * PI);
                plane_at_angle(sampler, angle)
            }
            _ => sampler.plane(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_series_angle_is_where_tan_squared_of_half_is_a_millionth() {
        let t = (PLANE_SERIES_ANGLE / 2.0).tan();
        assert!((t * t - 1e-6).abs() < 1e-20, "{}", t * t);
    }

    #[test]
    fn the_measured_plane_is_off_by_the_angle() {
        let mut s = Sampler::new(3);
        for angle in [1e-4, 0.5, 3.0, 4.0] {
            let f = plane_at_angle(&mut s, angle);
            let r = slam_factors::plane::plane_residual(&f);
            assert!((r.norm() - angle).abs() < 1e-12, "{angle}: {}", r.norm());
        }
    }
}
