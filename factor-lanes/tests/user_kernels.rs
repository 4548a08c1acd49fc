//! `factor_lanes::impl_real!` on a user's kernel crate: the kernels of
//! `examples/user-factor/user-kernels` (whose `Real` is that crate's own
//! copy) with its `lanes` feature, in lanes against the same kernels one
//! configuration at a time with the lane type's own `sin`, `cos` and
//! `atan2`: bit for bit, for the reason given in
//! `tests/kernels.rs`. `relative_pose` uses `sqrt`, `sin`, `cos`, `atan2` and
//! `select_lt`; `point_to_plane` only arithmetic.

// Only `scalars` of the configurations is needed here.
#[allow(dead_code)]
#[path = "support/configurations.rs"]
mod configurations;
#[path = "support/lanes.rs"]
mod lanes;
#[path = "support/run.rs"]
mod run;
// The selections record serves the plane test of `tests/kernels.rs`; the
// nudged atan2 is not needed here.
#[allow(dead_code)]
#[path = "support/scalar_reference.rs"]
mod scalar_reference;
// Only `identical` of the ulp helpers is needed here.
#[allow(dead_code)]
#[path = "support/ulp.rs"]
mod ulp;

use core::f64::consts::PI;

use configurations::scalars;
use factor_core::lie::Se3;
use factor_lanes::{F32x8, F64x4, F64x8};
use factor_testing::samples::Sampler;
use lanes::Lanes;
use nalgebra::Vector6;
use scalar_reference::ThroughLanes;
use ulp::Ulp;
// The support modules name `crate::Real`: here the user's kernel crate's.
use user_kernels::Real;
use user_kernels::{point_to_plane, relative_pose};

const CONFIGURATIONS: usize = 8192;

/// `relative_pose` with both blocks: inputs 7 × 3, outputs 6 + 36 + 36.
fn relative_pose_kernel<T: Real>(x: &[T]) -> Vec<T> {
    let zero = T::constant(0.0);
    let (mut r, mut d_i, mut d_j) = ([zero; 6], [zero; 36], [zero; 36]);
    relative_pose::relative_pose(
        x[0..7].try_into().unwrap(),
        x[7..14].try_into().unwrap(),
        x[14..21].try_into().unwrap(),
        &mut r,
        Some(&mut d_i),
        Some(&mut d_j),
    );
    [&r[..], &d_i, &d_j].concat()
}

/// `point_to_plane` with its block: inputs 3 + 3 + 3 + 7, outputs 1 + 6.
fn point_to_plane_kernel<T: Real>(x: &[T]) -> Vec<T> {
    let zero = T::constant(0.0);
    let (mut r, mut d_pose) = ([zero; 1], [zero; 6]);
    point_to_plane::point_to_plane(
        x[0..3].try_into().unwrap(),
        x[3..6].try_into().unwrap(),
        x[6..9].try_into().unwrap(),
        x[9..16].try_into().unwrap(),
        &mut r,
        Some(&mut d_pose),
    );
    [&r[..], &d_pose].concat()
}

/// Relative-pose configurations: the measurement is the predicted relative
/// pose moved by `Exp(ξ)`, the rotation part of `ξ` of norm log-uniform in
/// `[10⁻¹⁰, 1]` for half of them (the small-angle branches of `Log`) and
/// within `10⁻⁶` of π for the other half.
fn relative_pose_configurations() -> Vec<Vec<f64>> {
    let mut s = Sampler::new(21);
    (0..CONFIGURATIONS)
        .map(|k| {
            let (pose_i, pose_j) = (s.pose(), s.pose());
            let axis = s.rotation().rotate(&nalgebra::Vector3::z());
            let angle = if k % 2 == 0 {
                s.uniform(1e-10f64.ln(), 0.0).exp()
            } else {
                PI + s.uniform(-1e-6, 1e-6)
            };
            let rho = s.vector3(1.0);
            let xi = Vector6::new(
                axis.x * angle,
                axis.y * angle,
                axis.z * angle,
                rho.x,
                rho.y,
                rho.z,
            );
            let measured = pose_i.inverse().compose(&pose_j).compose(&Se3::exp(&xi));
            [scalars(&measured), scalars(&pose_i), scalars(&pose_j)].concat()
        })
        .collect()
}

fn point_to_plane_configurations() -> Vec<Vec<f64>> {
    let mut s = Sampler::new(22);
    (0..CONFIGURATIONS)
        .map(|_| {
            let normal = s.rotation().rotate(&nalgebra::Vector3::z());
            [
                scalars(&s.vector3(5.0)),
                scalars(&s.vector3(5.0)),
                scalars(&normal),
                scalars(&s.pose()),
            ]
            .concat()
        })
        .collect()
}

fn exact<L: Lanes + Real>(
    configurations: &[Vec<f64>],
    kernel: run::Kernel<L>,
    scalar: run::Kernel<scalar_reference::Scalar<L::S, ThroughLanes<L>>>,
) where
    L::S: Real + PartialOrd,
{
    let lanes = run::in_lanes::<L>(configurations, kernel);
    let reference = run::one_by_one::<L, ThroughLanes<L>>(configurations, scalar);
    for (c, (l, r)) in lanes.iter().zip(&reference).enumerate() {
        for (o, (a, b)) in l.iter().zip(r).enumerate() {
            assert!(
                a.identical(*b),
                "configuration {c}, output {o}: lanes {a:?}, scalar {b:?}"
            );
        }
    }
}

macro_rules! user_kernel_tests {
    ($($test:ident: $lanes:ty),* $(,)?) => {
        $(
            #[test]
            fn $test() {
                exact::<$lanes>(&relative_pose_configurations(), relative_pose_kernel::<$lanes>, relative_pose_kernel);
                exact::<$lanes>(&point_to_plane_configurations(), point_to_plane_kernel::<$lanes>, point_to_plane_kernel);
            }
        )*
    };
}

user_kernel_tests!(
    user_kernels_f64x4_are_the_scalar_kernels_bit_for_bit: F64x4,
    user_kernels_f64x8_are_the_scalar_kernels_bit_for_bit: F64x8,
    user_kernels_f32x8_are_the_scalar_kernels_bit_for_bit: F32x8,
);
