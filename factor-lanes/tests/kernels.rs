//! The generated kernels in lanes against the same kernels one configuration
//! at a time, for every lane type: the point-reprojection kernel and the plane
//! kernel of `factor-generated` with its `lanes` feature, whose `Real` is
//! implemented for the lane types by `factor_lanes::impl_real!`.
//!
//! Tolerances:
//!
//! - Lanes against the scalar kernel whose `sin`, `cos` and `atan2` are the
//!   lane type's own (evaluated on a splat): **bit for bit**. Every other
//!   operation the kernels use (`+ − × ÷`, `sqrt`, literals, `select_lt`) is
//!   correctly rounded per lane by IEEE 754 exactly as in the scalar type, and
//!   Rust never fuses a multiply and an add on its own.
//! - The plane kernel in lanes against the plain `std` scalar kernel: its only
//!   inexact operation is one `atan2`, within `B` ulp of `std`
//!   (`tests/math_accuracy.rs`; `B` = 2 for `f64`, 3 for `f32`). So for every
//!   configuration the lanes must give, bit for bit, what the `std` kernel
//!   gives with its `atan2` moved by some `j` representable values, `|j| ≤ B`:
//!   the lane kernel differs from the scalar one by its `atan2` error and by
//!   nothing else. (An interval tolerance would be the wrong shape here: the
//!   outputs are rounded functions of the `atan2` value, not linear in it at
//!   the ulp scale.) The run prints the largest relative difference from
//!   `std` per output that this allows in practice.

#[path = "support/configurations.rs"]
mod configurations;
#[path = "support/lanes.rs"]
mod lanes;
#[path = "support/run.rs"]
mod run;
// `sin` and `cos` of the references serve kernels that these do not include.
#[allow(dead_code)]
#[path = "support/scalar_reference.rs"]
mod scalar_reference;
// `ulps_from` serves the accuracy tests.
#[allow(dead_code)]
#[path = "support/ulp.rs"]
mod ulp;

use factor_generated::{plane, point_reprojection};
use factor_lanes::{F32x8, F64x4, F64x8};
use factor_testing::branch_points;
use factor_testing::samples::Sampler;
use lanes::Lanes;
// The support modules name `crate::Real`: here the generated crate's.
use factor_generated::Real;
use scalar_reference::{NudgedAtan2, Std, ThroughLanes, set_atan2_steps, take_selections};
use ulp::Ulp;

/// Configurations per kernel and lane type, per set.
const PER_SET: usize = 4096;

/// The point kernel with both blocks: inputs 4 + 2 + 7 + 3, outputs 2 + 12 + 6.
fn point_kernel<T: Real>(x: &[T]) -> Vec<T> {
    let zero = T::constant(0.0);
    let (mut r, mut d_pose, mut d_point) = ([zero; 2], [zero; 12], [zero; 6]);
    point_reprojection::point_reprojection(
        x[0..4].try_into().unwrap(),
        x[4..6].try_into().unwrap(),
        x[6..13].try_into().unwrap(),
        x[13..16].try_into().unwrap(),
        &mut r,
        Some(&mut d_pose),
        Some(&mut d_point),
    );
    [&r[..], &d_pose, &d_point].concat()
}

/// The plane kernel with both blocks: inputs 4 + 7 + 4, outputs 3 + 18 + 9.
fn plane_kernel<T: Real>(x: &[T]) -> Vec<T> {
    let zero = T::constant(0.0);
    let (mut r, mut d_pose, mut d_plane) = ([zero; 3], [zero; 18], [zero; 9]);
    plane::plane(
        x[0..4].try_into().unwrap(),
        x[4..11].try_into().unwrap(),
        x[11..15].try_into().unwrap(),
        &mut r,
        Some(&mut d_pose),
        Some(&mut d_plane),
    );
    [&r[..], &d_pose, &d_plane].concat()
}

/// Asserts that `lanes` equals `reference` bit for bit (NaN for NaN).
fn assert_identical<S: Ulp + core::fmt::Debug>(what: &str, lanes: &[Vec<S>], reference: &[Vec<S>]) {
    for (c, (l, r)) in lanes.iter().zip(reference).enumerate() {
        for (o, (a, b)) in l.iter().zip(r).enumerate() {
            assert!(
                a.identical(*b),
                "{what}: configuration {c}, output {o}: lanes {a:?}, scalar {b:?}"
            );
        }
    }
}

/// 2 × 4096 point configurations: sampled factors, and every input uniform
/// in `[−3, 3]` (depths near 0, points behind the camera, non-unit
/// quaternions: the kernel's arithmetic anywhere).
fn point_configurations() -> Vec<Vec<f64>> {
    let mut s = Sampler::new(11);
    let mut out: Vec<Vec<f64>> = (0..PER_SET)
        .map(|_| configurations::point(&mut s))
        .collect();
    out.extend((0..PER_SET).map(|_| (0..16).map(|_| s.uniform(-3.0, 3.0)).collect()));
    out
}

fn point_exact<L: Lanes + Real>()
where
    L::S: Real + PartialOrd,
{
    let configurations = point_configurations();
    let lanes = run::in_lanes::<L>(&configurations, point_kernel::<L>);
    let scalar = run::one_by_one::<L, Std>(&configurations, point_kernel);
    assert_identical("point", &lanes, &scalar);
}

#[test]
fn point_f64x4_is_the_scalar_kernel_bit_for_bit() {
    point_exact::<F64x4>();
}

#[test]
fn point_f64x8_is_the_scalar_kernel_bit_for_bit() {
    point_exact::<F64x8>();
}

#[test]
fn point_f32x8_is_the_scalar_kernel_bit_for_bit() {
    point_exact::<F32x8>();
}

/// 4 × 4096 plane configurations: sampled factors (error up to 0.3 rad);
/// angles within a relative 10⁻¹²–10⁻² of the small-angle switch, either
/// side; within the same of π (where `w` changes sign), either side; and
/// angles uniform in `[0, 2π)`.
fn plane_configurations() -> Vec<Vec<f64>> {
    let mut s = Sampler::new(12);
    let mut out = Vec::new();
    out.extend((0..PER_SET).map(|_| {
        let f = s.plane();
        [
            configurations::scalars(&f.measured),
            configurations::scalars(&f.pose),
            configurations::scalars(&f.plane),
        ]
        .concat()
    }));
    for _ in 0..PER_SET {
        let angle = branch_points::near(&mut s, branch_points::PLANE_SERIES_ANGLE);
        out.push(configurations::plane_at_angle(&mut s, angle));
    }
    for _ in 0..PER_SET {
        let angle = branch_points::near(&mut s, branch_points::PLANE_W_ZERO);
        out.push(configurations::plane_at_angle(&mut s, angle));
    }
    for _ in 0..PER_SET {
        let angle = s.uniform(0.0, 2.0 * branch_points::PLANE_W_ZERO);
        out.push(configurations::plane_at_angle(&mut s, angle));
    }
    out
}

/// The plane kernel selects with `select_lt(tan²(θ/2), 1e-6, …)` then
/// `select_lt(0, w, …)`, first for the residual: both outcomes of each must
/// occur in the sets built to straddle them.
fn assert_branches_straddled<L: Lanes>(configurations: &[Vec<f64>])
where
    L::S: Real + PartialOrd,
{
    let _ = take_selections();
    let first_two = |set: &[Vec<f64>]| -> Vec<(bool, bool)> {
        set.iter()
            .map(|c| {
                run::one_by_one::<L, Std>(core::slice::from_ref(c), plane_kernel);
                let s = take_selections();
                (s[0], s[1])
            })
            .collect()
    };
    let series = first_two(&configurations[PER_SET..2 * PER_SET]);
    let w = first_two(&configurations[2 * PER_SET..3 * PER_SET]);
    for (name, outcomes) in [
        (
            "small angle",
            series.iter().map(|o| o.0).collect::<Vec<_>>(),
        ),
        ("w > 0", w.iter().map(|o| o.1).collect()),
    ] {
        let taken = outcomes.iter().filter(|&&t| t).count();
        assert!(
            taken > PER_SET / 4 && taken < 3 * PER_SET / 4,
            "{name}: {taken} of {PER_SET} took the first arm"
        );
    }
}

fn plane_exact<L: Lanes + Real>()
where
    L::S: Real + PartialOrd,
{
    let configurations = plane_configurations();
    assert_branches_straddled::<L>(&configurations);
    let lanes = run::in_lanes::<L>(&configurations, plane_kernel::<L>);
    let scalar = run::one_by_one::<L, ThroughLanes<L>>(&configurations, plane_kernel);
    assert_identical("plane", &lanes, &scalar);
}

#[test]
fn plane_f64x4_is_the_scalar_kernel_with_its_atan2_bit_for_bit() {
    plane_exact::<F64x4>();
}

#[test]
fn plane_f64x8_is_the_scalar_kernel_with_its_atan2_bit_for_bit() {
    plane_exact::<F64x8>();
}

#[test]
fn plane_f32x8_is_the_scalar_kernel_with_its_atan2_bit_for_bit() {
    plane_exact::<F32x8>();
}

/// The plane kernel in lanes against `std`'s scalar kernel: for each
/// configuration, the `std` kernel with its `atan2` moved by some `|j| ≤ B`
/// representable values (see the module documentation).
fn plane_within_atan2_bound<L: Lanes + Real>(bound: i64)
where
    L::S: Real + PartialOrd,
{
    let configurations = plane_configurations();
    let lanes = run::in_lanes::<L>(&configurations, plane_kernel::<L>);
    let nudged: Vec<Vec<Vec<L::S>>> = (-bound..=bound)
        .map(|j| {
            set_atan2_steps(j);
            run::one_by_one::<L, NudgedAtan2>(&configurations, plane_kernel)
        })
        .collect();
    let exact = &nudged[bound as usize];
    let mut worst_relative = 0.0f64;
    for (c, lane) in lanes.iter().enumerate() {
        let matches = nudged
            .iter()
            .any(|n| n[c].iter().zip(lane).all(|(a, b)| a.identical(*b)));
        assert!(
            matches,
            "plane: configuration {c}: lanes {lane:?}, std {:?}",
            exact[c]
        );
        for (l, e) in lane.iter().zip(&exact[c]) {
            let (l, e): (f64, f64) = ((*l).into(), (*e).into());
            if e != 0.0 && e.is_finite() {
                worst_relative = worst_relative.max(((l - e) / e).abs());
            }
        }
    }
    println!(
        "{}: largest relative difference from std over all outputs {worst_relative:e}",
        core::any::type_name::<L>()
    );
}

#[test]
fn plane_f64x4_is_std_up_to_its_atan2_error() {
    plane_within_atan2_bound::<F64x4>(2);
}

#[test]
fn plane_f64x8_is_std_up_to_its_atan2_error() {
    plane_within_atan2_bound::<F64x8>(2);
}

#[test]
fn plane_f32x8_is_std_up_to_its_atan2_error() {
    plane_within_atan2_bound::<F32x8>(3);
}
