//! The generated kernels of `generated/`: they agree with dual numbers to
//! rounding and with numerical differentiation at 200 random configurations per
//! factor, skip exactly the Jacobian blocks passed as `None`, and instantiate
//! with `f32` and with a user's own `Real` type. (`tests/codegen.rs` checks
//! that they are what the current definitions generate.)
#![cfg(feature = "kernels")]

use factor_core::{Factor, NumericLinearize, Storage};
use factor_testing::JacobianCheck;
use factor_testing::generated::compare;
use factor_testing::samples::Sampler;

const CONFIGURATIONS: usize = 200;
/// Generated vs dual numbers: both exact, so only rounding differs.
const VS_DUAL: f64 = 1e-12;
/// Generated vs numerical differentiation (the tolerance of `slam-factors/tests/jacobians.rs`).
const VS_NUMERIC: f64 = 1e-6;
/// `f32` vs `f64` instantiation of the same kernel, relative to the `f64`
/// output's norm or 1, whichever is larger (a residual of 0.02 px is known to
/// a few 1e-5 px in `f32`).
const F32_VS_F64: f64 = 1e-3;

/// The residual's error, then each block's (see [`compare`]).
fn errors(check: &JacobianCheck) -> Vec<f64> {
    std::iter::once(check.residual_error)
        .chain(check.block_errors.iter().map(|(_, e)| *e))
        .collect()
}

/// Checks `CONFIGURATIONS` samples against dual numbers and central
/// differences; returns the worst errors seen (vs dual, vs numeric).
fn check_agreement<F: Factor>(seed: u64, mut sample: impl FnMut(&mut Sampler) -> F) -> (f64, f64) {
    let mut sampler = Sampler::new(seed);
    let (mut worst_dual, mut worst_numeric) = (0.0_f64, 0.0_f64);
    for i in 0..CONFIGURATIONS {
        let factor = sample(&mut sampler);
        let generated = factor
            .linearize_generated_dyn()
            .unwrap_or_else(|| panic!("{} has a generated kernel", F::NAME))
            .unwrap_or_else(|e| panic!("{} configuration {i}: {e}", F::NAME));
        let dual = factor.linearize_dual_dyn().expect("valid");
        let numeric = factor.linearize_numeric_dyn().expect("valid");
        for (k, e) in errors(&compare(&factor, &generated, &dual))
            .into_iter()
            .enumerate()
        {
            assert!(
                e <= VS_DUAL,
                "{} configuration {i}, output {k}: generated vs dual {e:e}",
                F::NAME
            );
            worst_dual = worst_dual.max(e);
        }
        for (k, e) in errors(&compare(&factor, &generated, &numeric))
            .into_iter()
            .enumerate()
        {
            assert!(
                e <= VS_NUMERIC,
                "{} configuration {i}, output {k}: generated vs numeric {e:e}",
                F::NAME
            );
            worst_numeric = worst_numeric.max(e);
        }
    }
    println!(
        "{}: worst relative error vs dual {worst_dual:e}, vs numeric {worst_numeric:e}",
        F::NAME
    );
    (worst_dual, worst_numeric)
}

#[test]
fn point_reprojection_generated_matches_dual_and_numeric() {
    check_agreement(11, Sampler::point_reprojection);
}

#[test]
fn line_reprojection_generated_matches_dual_and_numeric() {
    check_agreement(12, Sampler::line_reprojection);
}

#[test]
fn plucker_line_reprojection_generated_matches_dual_and_numeric() {
    check_agreement(13, Sampler::plucker_line_reprojection);
}

#[test]
fn plane_generated_matches_dual_and_numeric() {
    check_agreement(14, Sampler::plane);
}

/// Both branches of the quaternion logarithm: small errors (below its
/// small-angle threshold) and exactly zero.
#[test]
fn plane_generated_matches_dual_near_and_at_zero_error() {
    let mut sampler = Sampler::new(15);
    for i in 0..CONFIGURATIONS {
        let factor = sampler.plane_with_error(if i % 2 == 0 { 1e-4 } else { 0.0 });
        let generated = factor.linearize_generated_dyn().expect("kernel").unwrap();
        let dual = factor.linearize_dual_dyn().unwrap();
        for e in errors(&compare(&factor, &generated, &dual)) {
            assert!(e <= VS_DUAL, "configuration {i}: {e:e}");
        }
    }
}

#[test]
fn free_line_generated_matches_dual_and_numeric() {
    check_agreement(16, Sampler::free_line);
}

#[test]
fn snavely_reprojection_generated_matches_dual_and_numeric() {
    check_agreement(18, Sampler::snavely_reprojection);
}

#[test]
fn stereo_reprojection_generated_matches_dual_and_numeric() {
    check_agreement(19, Sampler::stereo_reprojection);
}

#[test]
fn between_generated_matches_dual_and_numeric() {
    check_agreement(20, Sampler::between);
}

/// `linearize()` goes through the kernel, and the typed and dynamic forms agree.
#[test]
fn g2o_se3_generated_matches_dual_and_numeric() {
    check_agreement(21, Sampler::g2o_se3);
}

#[test]
fn line_observation_generated_matches_dual_and_numeric() {
    check_agreement(22, Sampler::line_observation);
}

#[test]
fn linearize_uses_the_generated_kernel() {
    let mut sampler = Sampler::new(17);
    let factor = sampler.point_reprojection();
    assert_eq!(
        <slam_factors::PointReprojection as Factor>::KERNEL,
        Some("factor_generated::point_reprojection::point_reprojection")
    );
    let typed = factor.linearize().unwrap();
    assert_eq!(typed, factor.linearize_generated().unwrap());
    assert_eq!(
        typed.to_dyn(),
        factor.linearize_generated_dyn().unwrap().unwrap()
    );
}

/// What a block not requested holds before and after a linearization.
const UNTOUCHED: f64 = 7.0;

/// A stored-scalar entry of the `Factor` trait: `linearize_stored_into`
/// or its validated twin.
type StoredEntry =
    fn(&[f64], &mut [f64], &mut [Option<&mut [f64]>]) -> Result<(), factor_core::FactorError>;

/// The residual and every block of `F` at `stored` through `entry`, the
/// blocks requested per `requested` (the others keep [`UNTOUCHED`]).
fn stored_entry<F: Factor>(
    entry: StoredEntry,
    stored: &[f64],
    requested: &[bool],
) -> Result<Vec<Vec<f64>>, factor_core::FactorError> {
    let mut residual = vec![UNTOUCHED; F::RESIDUAL_DIM];
    let mut blocks: Vec<Vec<f64>> = F::variables()
        .iter()
        .map(|v| vec![UNTOUCHED; F::RESIDUAL_DIM * v.tangent_dim])
        .collect();
    let mut out: Vec<Option<&mut [f64]>> = blocks
        .iter_mut()
        .zip(requested)
        .map(|(b, &r)| r.then_some(&mut b[..]))
        .collect();
    entry(stored, &mut residual, &mut out)?;
    Ok(std::iter::once(residual).chain(blocks).collect())
}

/// `linearize_stored_validated_into` is `linearize_stored_into` without
/// the validation, every block requested or some: the same outputs where
/// the factor is valid; where the validation refuses the configuration
/// (the point behind the camera) the kernel's own outputs instead of the
/// error; a non-finite output still an error.
#[test]
fn the_validated_entry_skips_the_validation_only() {
    type F = slam_factors::SnavelyReprojection;
    let checked: StoredEntry = F::linearize_stored_into;
    let validated: StoredEntry = F::linearize_stored_validated_into;
    let kernel = |f: &F| {
        let (observed, pose, intrinsics, point) = (
            flat(&f.observed, |x| x),
            flat(&f.pose, |x| x),
            flat(&f.intrinsics, |x| x),
            flat(&f.point, |x| x),
        );
        let (mut r, mut d0, mut d1, mut d2) = ([0.0; 2], [0.0; 12], [0.0; 6], [0.0; 6]);
        factor_generated::snavely_reprojection::snavely_reprojection(
            &observed,
            &pose,
            &intrinsics,
            &point,
            &mut r,
            Some(&mut d0),
            Some(&mut d1),
            Some(&mut d2),
        );
        vec![r.to_vec(), d0.to_vec(), d1.to_vec(), d2.to_vec()]
    };
    let all = [true; 3];
    let pose_only = [true, false, false];
    let mut sampler = Sampler::new(23);
    for i in 0..CONFIGURATIONS {
        let factor = sampler.snavely_reprojection();
        let stored = factor.to_scalars();
        let expected = kernel(&factor);
        for requested in [all, pose_only] {
            let through = |entry| stored_entry::<F>(entry, &stored, &requested);
            let (a, b) = (through(checked).unwrap(), through(validated).unwrap());
            assert_eq!(a, b, "configuration {i}, blocks {requested:?}");
            for (k, (block, kernel_block)) in a[1..].iter().zip(&expected[1..]).enumerate() {
                match requested[k] {
                    true => assert_eq!(block, kernel_block, "configuration {i}, block {k}"),
                    false => assert!(block.iter().all(|&x| x == UNTOUCHED), "block {k} written"),
                }
            }
            assert_eq!(a[0], expected[0], "configuration {i}, blocks {requested:?}");
        }
        // The point mirrored behind the camera: −P_z < 0.
        let mut behind = factor.clone();
        let mut p_c = factor.pose.transform_point(&factor.point);
        p_c.z = -p_c.z;
        behind.point = factor.pose.inverse_transform_point(&p_c);
        let stored = behind.to_scalars();
        let refused = stored_entry::<F>(checked, &stored, &all).unwrap_err();
        assert!(
            matches!(refused, factor_core::FactorError::Degenerate { .. }),
            "configuration {i}: {refused}"
        );
        let kernel_outputs = stored_entry::<F>(validated, &stored, &all).unwrap();
        assert_eq!(kernel_outputs, kernel(&behind), "configuration {i}");
    }
    let mut not_finite = sampler.snavely_reprojection();
    not_finite.observed.x = f64::NAN;
    let stored = not_finite.to_scalars();
    let non_finite = factor_core::FactorError::NonFinite {
        factor: F::NAME,
        what: "residual".into(),
    };
    for requested in [all, pose_only] {
        for entry in [checked, validated] {
            assert_eq!(
                stored_entry::<F>(entry, &stored, &requested),
                Err(non_finite.clone())
            );
        }
    }
}

/// The stored scalars of a field in storage order, converted by `convert`.
fn flat<M: Storage<f64>, T: Copy + Default, const N: usize>(
    value: &M,
    convert: fn(f64) -> T,
) -> [T; N] {
    let stored = value.to_scalars();
    assert_eq!(stored.len(), N, "a field stores {N} scalars");
    std::array::from_fn(|i| convert(stored[i]))
}

/// `‖a − b‖ / max(‖b‖, 1)`: the loose comparison of `f32` with `f64`.
fn relative(a: &[f64], b: &[f64]) -> f64 {
    let diff: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let norm: f64 = b.iter().map(|y| y * y).sum();
    diff.sqrt() / norm.sqrt().max(1.0)
}

fn f32_of(x: f64) -> f32 {
    x as f32
}

fn widen(x: &[f32]) -> Vec<f64> {
    x.iter().map(|v| f64::from(*v)).collect()
}

/// For a factor with two variables (its kernel is
/// `factor_generated::$sample::$sample`): every combination of requested blocks
/// gives the same residual and the same requested blocks as requesting all,
/// and leaves the others untouched; and the `f32` instance agrees loosely
/// with the `f64` one.
macro_rules! check_kernel {
    ($seed:expr, $sample:ident, [$($field:ident),+], $r:literal, $d0:literal, $d1:literal) => {{
        let mut sampler = Sampler::new($seed);
        let mut worst_f32: f64 = 0.0;
        for i in 0..CONFIGURATIONS {
            let factor = sampler.$sample();
            $(let $field = flat(&factor.$field, |x| x);)+
            let run = |a: bool, b: bool| {
                let mut r = [f64::NAN; $r];
                let mut d0 = [f64::NAN; $r * $d0];
                let mut d1 = [f64::NAN; $r * $d1];
                factor_generated::$sample::$sample($(&$field,)+ &mut r, a.then_some(&mut d0), b.then_some(&mut d1));
                (r, d0, d1)
            };
            let (r, d0, d1) = run(true, true);
            assert!(r.iter().chain(&d0).chain(&d1).all(|x| x.is_finite()), "configuration {i}");
            for (a, b) in [(true, false), (false, true), (false, false)] {
                let (r_ab, d0_ab, d1_ab) = run(a, b);
                assert_eq!(r_ab, r, "configuration {i}: residual with blocks ({a}, {b})");
                if a {
                    assert_eq!(d0_ab, d0, "configuration {i}: first block");
                } else {
                    assert!(d0_ab.iter().all(|x| x.is_nan()), "first block written");
                }
                if b {
                    assert_eq!(d1_ab, d1, "configuration {i}: second block");
                } else {
                    assert!(d1_ab.iter().all(|x| x.is_nan()), "second block written");
                }
            }
            $(let $field = flat(&factor.$field, f32_of);)+
            let mut r32 = [0.0_f32; $r];
            let mut d0_32 = [0.0_f32; $r * $d0];
            let mut d1_32 = [0.0_f32; $r * $d1];
            factor_generated::$sample::$sample::<f32>($(&$field,)+ &mut r32, Some(&mut d0_32), Some(&mut d1_32));
            for (low, high) in [(widen(&r32), &r[..]), (widen(&d0_32), &d0[..]), (widen(&d1_32), &d1[..])] {
                let e = relative(&low, high);
                assert!(e <= F32_VS_F64, "configuration {i}: f32 vs f64 {e:e}: {low:?} vs {high:?}");
                worst_f32 = worst_f32.max(e);
            }
        }
        println!("{}: worst f32 vs f64 relative error {worst_f32:e}", stringify!($sample));
    }};
}

#[test]
fn point_reprojection_kernel_outputs_are_optional_and_f32_works() {
    check_kernel!(
        21,
        point_reprojection,
        [intrinsics, observed, pose, point],
        2,
        6,
        3
    );
}

#[test]
fn line_reprojection_kernel_outputs_are_optional_and_f32_works() {
    check_kernel!(
        22,
        line_reprojection,
        [intrinsics, start, end, pose, line],
        2,
        6,
        4
    );
}

#[test]
fn plucker_line_reprojection_kernel_outputs_are_optional_and_f32_works() {
    check_kernel!(
        23,
        plucker_line_reprojection,
        [intrinsics, start, end, pose, line],
        2,
        6,
        6
    );
}

#[test]
fn plane_kernel_outputs_are_optional_and_f32_works() {
    check_kernel!(24, plane, [measured, pose, plane], 3, 6, 3);
}

#[test]
fn stereo_reprojection_kernel_outputs_are_optional_and_f32_works() {
    check_kernel!(
        27,
        stereo_reprojection,
        [calibration, observed, pose, landmark],
        3,
        6,
        3
    );
}

#[test]
fn between_kernel_outputs_are_optional_and_f32_works() {
    check_kernel!(
        28,
        between,
        [sqrt_information, measured, pose_i, pose_j],
        6,
        6,
        6
    );
}

#[test]
fn free_line_kernel_outputs_are_optional_and_f32_works() {
    check_kernel!(
        25,
        free_line,
        [extrinsics, bearing_start, bearing_end, body_pose, line],
        2,
        6,
        4
    );
}

/// The kernels are generic over `Real` only: a user type implementing it
/// (here a scalar that counts nothing, wrapping `f64`) instantiates them.
#[test]
fn kernels_instantiate_with_a_user_real_type() {
    use std::ops::{Add, Div, Mul, Neg, Sub};

    #[derive(Clone, Copy, Debug, Default, PartialEq)]
    struct Lane(f64);
    macro_rules! op {
        ($tr:ident, $m:ident, $o:tt) => {
            impl $tr for Lane {
                type Output = Lane;
                fn $m(self, rhs: Lane) -> Lane {
                    Lane(self.0 $o rhs.0)
                }
            }
        };
    }
    op!(Add, add, +);
    op!(Sub, sub, -);
    op!(Mul, mul, *);
    op!(Div, div, /);
    impl Neg for Lane {
        type Output = Lane;
        fn neg(self) -> Lane {
            Lane(-self.0)
        }
    }
    impl factor_generated::Real for Lane {
        fn constant(c: f64) -> Self {
            Lane(c)
        }
        fn sqrt(self) -> Self {
            Lane(self.0.sqrt())
        }
        fn sin(self) -> Self {
            Lane(self.0.sin())
        }
        fn cos(self) -> Self {
            Lane(self.0.cos())
        }
        fn atan2(self, x: Self) -> Self {
            Lane(self.0.atan2(x.0))
        }
        fn exp(self) -> Self {
            Lane(self.0.exp())
        }
        fn ln(self) -> Self {
            Lane(self.0.ln())
        }
        fn acos(self) -> Self {
            Lane(self.0.acos())
        }
        fn asin(self) -> Self {
            Lane(self.0.asin())
        }
        fn atan(self) -> Self {
            Lane(self.0.atan())
        }
        fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
            if lhs.0 < rhs.0 { if_less } else { otherwise }
        }
    }
    let factor = Sampler::new(26).plane();
    let lane = |x: f64| Lane(x);
    let (measured, pose, plane) = (
        flat(&factor.measured, lane),
        flat(&factor.pose, lane),
        flat(&factor.plane, lane),
    );
    let mut r = [Lane(0.0); 3];
    let mut d_pose = [Lane(0.0); 18];
    factor_generated::plane::plane(&measured, &pose, &plane, &mut r, Some(&mut d_pose), None);
    let reference = factor.linearize_generated().unwrap();
    for (k, x) in r.iter().enumerate() {
        assert_eq!(x.0, reference.residual[k]);
    }
    for (k, x) in d_pose.iter().enumerate() {
        assert_eq!(x.0, reference.pose[(k / 6, k % 6)]);
    }
}

/// The plane kernel at the points where the quaternion logarithm is
/// delicate: error angles at and near 0 (its series branch and the switch),
/// at and around π, and close to 2π (the antipode, where only the exact
/// branch is valid). Generated, dual and numerical differentiation agree
/// everywhere (the fixed step of 1e-3 the numerical method had crossed the
/// antipode at 2π − 1e-3, so it was compared below π + 0.5 only).
#[test]
fn plane_kernel_is_exact_near_its_singular_points() {
    use factor_core::lie::Quaternion;
    use std::f64::consts::PI;
    let mut sampler = Sampler::new(17);
    for angle in [
        0.0,
        1e-8,
        1e-4,
        2e-3,
        0.5,
        PI - 1e-9,
        PI,
        PI + 1e-6,
        2.0 * PI - 1e-3,
    ] {
        for _ in 0..20 {
            let mut factor = sampler.plane_with_error(0.0);
            let axis = sampler.vector3(1.0).normalize();
            // At zero error φ = q_w, so q_w ⊗ exp(θa) makes the error
            // quaternion q_w ⊗ exp(−θa) ⊗ q_w⁻¹: an error of angle exactly θ.
            let landmark = factor.plane.quaternion;
            factor.plane.quaternion = landmark.mul(&Quaternion::exp(&(axis * angle)));
            let generated = factor
                .linearize_generated_dyn()
                .expect("kernel")
                .unwrap_or_else(|e| panic!("angle {angle}: {e}"));
            let dual = factor
                .linearize_dual_dyn()
                .unwrap_or_else(|e| panic!("angle {angle}: {e}"));
            for e in errors(&compare(&factor, &generated, &dual)) {
                assert!(e <= VS_DUAL, "angle {angle}: generated vs dual {e:e}");
            }
            assert!(
                (generated.residual.norm() - angle).abs() <= 1e-9 * (1.0 + angle),
                "angle {angle}"
            );
            let numeric = factor.linearize_numeric_dyn().unwrap();
            for e in errors(&compare(&factor, &generated, &numeric)) {
                assert!(e <= VS_NUMERIC, "angle {angle}: generated vs numeric {e:e}");
            }
        }
    }
}
