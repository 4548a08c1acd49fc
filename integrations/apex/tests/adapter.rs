//! The adapter's Jacobians are apex-solver's: they equal central
//! differences through apex's own retraction (`SE3 ⊕ τ`, `Rn + δ`), for the
//! generated kernels and for dual numbers, and they equal apex's own
//! hand-written factors where apex has the same factor with the same
//! variables (its BAL projection factor, its between factor).

use apex_solver::NoiseModel;
use apex_solver::apex_camera_models::{BALPinholeCameraStrict, DistortionModel, PinholeParams};
use apex_solver::factors::Factor as ApexFactorTrait;
use apex_solver::factors::SelfCalibration;
use apex_solver::factors::pose::BetweenFactor as ApexBetween;
use apex_solver::factors::visual::ProjectionFactor;
use apex_solver::manifold::se3::{SE3, SE3Tangent};
use apex_solver::manifold::so2::{SO2, SO2Tangent};
use apex_solver::manifold::so3::{SO3, SO3Tangent};
use apex_solver::manifold::{LieGroup, Tangent};
use factor_apex::variables::apex_pose;
use factor_apex::{ApexFactor, Kernels, Rejections};
use factor_core::host::{
    Apex, ApexManifold, HostFactor, HostKernel, HostLayout, HostManifold, host_parameters,
};
use factor_testing::generated::input_scale;
use factor_testing::samples::Sampler;
use factor_testing::{branch_points, near_degenerate};
use slam_factors::{BetweenFactor, SnavelyReprojection};

/// Configurations per factor.
const CONFIGURATIONS: usize = 1000;

/// The apex parameters of each apex variable of `factor`, in order.
fn apex_parameters<F: HostFactor<Apex>>(factor: &F) -> Vec<Vec<f64>> {
    host_parameters::<F, Apex>(&HostLayout::of::<F, Apex>(), factor)
}

/// Residual and the column-major `rows × Σ dof` Jacobian of an apex factor.
fn linearize(factor: &dyn ApexFactorTrait, params: &[Vec<f64>]) -> (Vec<f64>, Vec<f64>) {
    let slices: Vec<&[f64]> = params.iter().map(Vec::as_slice).collect();
    let (rows, cols) = factor.jacobian_shape();
    let mut residual = vec![0.0; rows];
    let mut jacobian = vec![0.0; rows * cols];
    factor.linearize(
        &slices,
        &mut residual,
        Some(faer::mat::MatMut::from_column_major_slice_mut(
            &mut jacobian,
            rows,
            cols,
        )),
    );
    (residual, jacobian)
}

/// The residual alone (no Jacobian asked for).
fn residual_of(factor: &dyn ApexFactorTrait, params: &[Vec<f64>]) -> Vec<f64> {
    let slices: Vec<&[f64]> = params.iter().map(Vec::as_slice).collect();
    let mut residual = vec![0.0; factor.residual_dim()];
    factor.linearize(&slices, &mut residual, None);
    residual
}

/// `params` of `manifold` moved by apex-solver's own retraction (its
/// `LieGroup::plus`) along tangent coordinate `c` by `h`.
fn apex_retract(manifold: ApexManifold, params: &[f64], c: usize, h: f64) -> Vec<f64> {
    match manifold {
        ApexManifold::Se3 => {
            let mut tau = [0.0; 6];
            tau[c] = h;
            SE3::from_param_slice(params)
                .plus(&SE3Tangent::from_slice(&tau), None, None)
                .as_param_slice()
                .to_vec()
        }
        ApexManifold::So3 => {
            let mut theta = nalgebra_apex::Vector3::zeros();
            theta[c] = h;
            SO3::from_param_slice(params)
                .plus(&SO3Tangent::new(theta), None, None)
                .as_param_slice()
                .to_vec()
        }
        ApexManifold::So2 => SO2::from_param_slice(params)
            .plus(&SO2Tangent::new(h), None, None)
            .as_param_slice()
            .to_vec(),
        ApexManifold::Rn(_) => {
            let mut moved = params.to_vec();
            moved[c] += h;
            moved
        }
    }
}

/// Central differences through apex's retraction, Richardson-extrapolated.
fn numeric_jacobian(
    factor: &dyn ApexFactorTrait,
    params: &[Vec<f64>],
    parts: &[ApexManifold],
) -> Vec<f64> {
    let (rows, cols) = factor.jacobian_shape();
    let mut jacobian = vec![0.0; rows * cols];
    let mut column = 0;
    for (k, manifold) in parts.iter().enumerate() {
        for c in 0..manifold.dof() {
            let central = |h: f64| {
                let moved = |h: f64| {
                    let mut out = params.to_vec();
                    out[k] = apex_retract(*manifold, &params[k], c, h);
                    residual_of(factor, &out)
                };
                let (plus, minus) = (moved(h), moved(-h));
                plus.iter()
                    .zip(&minus)
                    .map(|(a, b)| (a - b) / (2.0 * h))
                    .collect::<Vec<_>>()
            };
            let (coarse, fine) = (central(1e-4), central(5e-5));
            for r in 0..rows {
                jacobian[column * rows + r] = (4.0 * fine[r] - coarse[r]) / 3.0;
            }
            column += 1;
        }
    }
    jacobian
}

fn relative(a: &[f64], b: &[f64]) -> f64 {
    let diff: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let norm: f64 = b.iter().map(|y| y * y).sum();
    diff.sqrt() / norm.sqrt().max(1e-9)
}

/// The residual error of `a` against `b` as the generated kernels are
/// judged (`factor_testing::generated::input_scale`): relative to
/// `max(‖b‖, the largest stored scalar)`, since two correct evaluation
/// orders differ by the rounding of the residual's terms, not of its value.
fn residual_error<F: factor_core::Factor>(factor: &F, a: &[f64], b: &[f64]) -> f64 {
    let difference: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let norm: f64 = b.iter().map(|y| y * y).sum();
    difference.sqrt() / norm.sqrt().max(input_scale(factor))
}

/// The adapter's residual and Jacobian (generated apex kernel and dual
/// numbers) against the factor's own residual and central differences
/// through apex's own retraction, at every configuration `sample` draws.
fn check_against_apex_retraction<F: HostKernel<Apex> + 'static>(
    seed: u64,
    count: usize,
    mut sample: impl FnMut(&mut Sampler, usize) -> F,
) {
    let mut sampler = Sampler::new(seed);
    let mut worst: f64 = 0.0;
    for i in 0..count {
        let factor = sample(&mut sampler, i);
        let params = apex_parameters(&factor);
        for kernels in [Kernels::Generated, Kernels::Dual] {
            let served = ApexFactor::new(&factor, kernels).expect("servable");
            let (residual, jacobian) = linearize(&served, &params);
            let expected = factor.residual_dyn().expect("valid");
            assert!(
                residual_error(&factor, &residual, expected.as_slice()) < 1e-12,
                "{} {i}: residual {residual:?}, expected {expected:?}",
                F::NAME
            );
            let numeric = numeric_jacobian(&served, &params, &served.parts());
            let error = relative(&jacobian, &numeric);
            assert!(
                error <= 1e-7,
                "{} configuration {i} ({kernels:?}): {error:e}",
                F::NAME
            );
            worst = worst.max(error);
        }
    }
    println!(
        "{}: {count} configurations, worst relative error vs apex's retraction {worst:e}",
        F::NAME
    );
}

#[test]
fn point_jacobians_are_derivatives_through_apex_retraction() {
    check_against_apex_retraction(41, CONFIGURATIONS, |s, _| s.point_reprojection());
}

/// Well-conditioned lines and lines near the orthonormal representation's
/// branch (the line through the camera centre, 0.05 to 1 m away).
#[test]
fn line_jacobians_are_derivatives_through_apex_retraction() {
    check_against_apex_retraction(42, CONFIGURATIONS, |s, i| match i % 4 {
        0 => near_degenerate::line_at_distance(i as u64, 0.05 + 0.001 * i as f64),
        _ => s.line_reprojection(),
    });
}

#[test]
fn plucker_jacobians_are_derivatives_through_apex_retraction() {
    check_against_apex_retraction(43, CONFIGURATIONS, |s, _| s.plucker_line_reprojection());
}

/// Well-conditioned planes and planes straddling the plane kernel's two
/// selects (the quaternion logarithm's small-angle series and its sheet).
#[test]
fn plane_jacobians_are_derivatives_through_apex_retraction() {
    let mut branch = branch_points::plane_branch_configurations(&mut Sampler::new(440), 500);
    check_against_apex_retraction(44, CONFIGURATIONS, move |s, i| match branch.pop() {
        Some(factor) if i % 2 == 0 => factor,
        _ => s.plane(),
    });
}

#[test]
fn free_line_jacobians_are_derivatives_through_apex_retraction() {
    check_against_apex_retraction(45, CONFIGURATIONS, |s, _| s.free_line());
}

#[test]
fn snavely_jacobians_are_derivatives_through_apex_retraction() {
    check_against_apex_retraction(51, CONFIGURATIONS, |s, _| s.snavely_reprojection());
}

#[test]
fn stereo_jacobians_are_derivatives_through_apex_retraction() {
    check_against_apex_retraction(52, CONFIGURATIONS, |s, _| s.stereo_reprojection());
}

/// Relative poses near the between factor's branch (a rotation error near
/// π) as well as well-conditioned ones.
#[test]
fn between_jacobians_are_derivatives_through_apex_retraction() {
    check_against_apex_retraction(53, CONFIGURATIONS, |s, i| match i % 4 {
        0 => s.between_with_error(1.7),
        _ => s.between(),
    });
}

/// The Snavely factor against apex's `ProjectionFactor<BALPinholeCameraStrict,
/// SelfCalibration>` at the same values: the same residual and the same
/// blocks (apex orders its variables pose, point, intrinsics).
#[test]
fn snavely_equals_apex_bal_projection_factor() {
    let mut sampler = Sampler::new(54);
    for i in 0..CONFIGURATIONS {
        let factor: SnavelyReprojection = sampler.snavely_reprojection();
        let served = ApexFactor::new(&factor, Kernels::Generated).expect("servable");
        let ours = apex_parameters(&factor);
        let (residual, jacobian) = linearize(&served, &ours);
        let i_ = &factor.intrinsics;
        let camera = BALPinholeCameraStrict::new(
            PinholeParams::new(i_.focal, i_.focal, 0.0, 0.0).expect("valid"),
            DistortionModel::Radial {
                k1: i_.k1,
                k2: i_.k2,
            },
        )
        .expect("valid");
        let apex: ProjectionFactor<BALPinholeCameraStrict, SelfCalibration> = ProjectionFactor::new(
            nalgebra_apex::Matrix2xX::from_columns(&[nalgebra_apex::Vector2::new(
                factor.observed.x,
                factor.observed.y,
            )]),
            camera,
        );
        let apex_params = vec![ours[0].clone(), ours[2].clone(), ours[1].clone()];
        let (apex_residual, apex_jacobian) = linearize(&apex, &apex_params);
        assert!(
            residual_error(&factor, &residual, &apex_residual) < 1e-12,
            "configuration {i}: residual"
        );
        // Columns: ours pose 0..6, intrinsics 6..9, point 9..12; apex's pose,
        // point 6..9, intrinsics 9..12.
        let column = |j: &[f64], c: usize| j[2 * c..2 * c + 2].to_vec();
        let apex_column = |c: usize| match c {
            0..6 => c,
            6..9 => c + 3,
            _ => c - 3,
        };
        for c in 0..12 {
            let e = relative(
                &column(&jacobian, c),
                &column(&apex_jacobian, apex_column(c)),
            );
            assert!(e < 1e-9, "configuration {i}, column {c}: {e:e}");
        }
    }
}

/// The between factor against apex's `BetweenFactor<SE3>` whitened by the
/// same square-root information (in apex's `[ρ, θ]` residual order): apex's
/// residual is `Log(T_j⁻¹ T_i Z) = −Log(Z⁻¹ T_i⁻¹ T_j)`, so the whitened
/// residuals and blocks agree up to the sign and an orthogonal change of
/// the residual's basis; their Gram matrices `JᵀJ`, `Jᵀr` and cost agree
/// exactly.
#[test]
fn between_equals_apex_between_factor() {
    let mut sampler = Sampler::new(55);
    for i in 0..CONFIGURATIONS {
        let factor: BetweenFactor = sampler.between();
        let served = ApexFactor::new(&factor, Kernels::Generated).expect("servable");
        let params = apex_parameters(&factor);
        let (residual, jacobian) = linearize(&served, &params);
        let apex = ApexBetween::new(SE3::from_param_slice(&apex_pose(&factor.measured)));
        let (mut apex_residual, mut apex_jacobian) = linearize(&apex, &params);
        let u = factor.sqrt_information.matrix();
        let p = |a: usize| (a + 3) % 6;
        let sqrt = nalgebra_apex::DMatrix::from_fn(6, 6, |a, b| u[(p(a), p(b))]);
        let noise = NoiseModel::from_sqrt_info(sqrt).expect("valid");
        noise.whiten_residual(&mut apex_residual);
        noise.whiten_jacobian(&mut apex_jacobian, 6, 12);
        let gram = |j: &[f64], r: &[f64]| {
            let j = nalgebra::DMatrix::from_column_slice(6, 12, j);
            let r = nalgebra::DVector::from_column_slice(r);
            (j.transpose() * &j, j.transpose() * &r, r.norm_squared())
        };
        let (h, g, c) = gram(&jacobian, &residual);
        let (h_apex, g_apex, c_apex) = gram(&apex_jacobian, &apex_residual);
        assert!(
            relative(h.as_slice(), h_apex.as_slice()) < 1e-9,
            "configuration {i}: JᵀJ"
        );
        assert!(
            relative(g.as_slice(), g_apex.as_slice()) < 1e-9,
            "configuration {i}: Jᵀr"
        );
        assert!(
            (c - c_apex).abs() <= 1e-9 * c.max(1.0),
            "configuration {i}: cost"
        );
    }
}

/// A configuration the factor rejects gives a NaN residual where apex
/// evaluates a trial step (residual only: apex then refuses the step, so it
/// never linearizes there), through both kernel choices, and is counted;
/// dual numbers, which validate in every call, also give a NaN Jacobian.
#[test]
fn degenerate_configurations_are_nan_and_counted() {
    let mut factor = Sampler::new(56).snavely_reprojection();
    factor.point = factor
        .pose
        .se3()
        .inverse()
        .transform_point(&nalgebra::Vector3::new(0.1, 0.2, 3.0));
    let rejections = Rejections::new();
    let params = apex_parameters(&factor);
    for kernels in [Kernels::Generated, Kernels::Dual] {
        let served = ApexFactor::new(&factor, kernels)
            .expect("servable")
            .with_rejections(rejections.clone());
        assert!(residual_of(&served, &params).iter().all(|x| x.is_nan()));
    }
    let dual = ApexFactor::new(&factor, Kernels::Dual).expect("servable");
    let (residual, jacobian) = linearize(&dual, &params);
    assert!(residual.iter().chain(&jacobian).all(|x| x.is_nan()));
    assert_eq!(rejections.count(), 2);
    assert!(
        rejections
            .first()
            .expect("recorded")
            .contains("behind the camera")
    );
}

/// The stereo factor against apex's `StereoFactor`, whose pose is the
/// inverse (world-to-camera): the same residual, the same landmark block,
/// and the pose blocks related by the change of chart: apex perturbs
/// `T_cw ⊕ δ'`, this factor `T_wc ⊕ δ`, and `(T_wc Exp(δ))⁻¹ = Exp(−δ) T_cw
/// = T_cw Exp(−Ad_{T_wc} δ)`, so `J = J_apex · (−Ad_{T_wc})` with the
/// adjoint in apex's `[ρ, θ]` order, `[[R, t^ R], [0, R]]`.
#[test]
fn stereo_equals_apex_stereo_factor_up_to_the_chart() {
    use apex_solver::factors::visual::{StereoCalibration, StereoFactor};
    use factor_core::lie::so3::hat;
    let mut sampler = Sampler::new(58);
    for i in 0..CONFIGURATIONS {
        let mut factor = sampler.stereo_reprojection();
        factor.calibration.skew = 0.0;
        let served = ApexFactor::new(&factor, Kernels::Generated).expect("servable");
        let params = apex_parameters(&factor);
        let (residual, jacobian) = linearize(&served, &params);
        let c = factor.calibration;
        let apex = StereoFactor::new(
            nalgebra_apex::Vector3::new(factor.observed.x, factor.observed.y, factor.observed.z),
            StereoCalibration::new(c.fx, c.fy, c.u0, c.v0, c.baseline).expect("valid"),
        );
        let apex_params = vec![apex_pose(&factor.pose.se3().inverse()), params[1].clone()];
        let (apex_residual, apex_jacobian) = linearize(&apex, &apex_params);
        assert!(
            residual_error(&factor, &residual, &apex_residual) < 1e-12,
            "configuration {i}: residual"
        );
        let j = nalgebra::DMatrix::from_column_slice(3, 9, &jacobian);
        let j_apex = nalgebra::DMatrix::from_column_slice(3, 9, &apex_jacobian);
        let landmark = |m: &nalgebra::DMatrix<f64>| m.columns(6, 3).into_owned();
        assert!(
            relative(landmark(&j).as_slice(), landmark(&j_apex).as_slice()) < 1e-9,
            "configuration {i}: landmark block"
        );
        let r = factor.pose.se3().rotation.matrix();
        let mut adjoint = nalgebra::Matrix6::zeros();
        adjoint.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
        adjoint.fixed_view_mut::<3, 3>(3, 3).copy_from(&r);
        adjoint
            .fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(hat(&factor.pose.translation()) * r));
        let pose_apex: nalgebra::DMatrix<f64> = j_apex.columns(0, 6).into_owned();
        let expected = -(pose_apex * adjoint);
        assert!(
            relative(j.columns(0, 6).into_owned().as_slice(), expected.as_slice()) < 1e-9,
            "configuration {i}: pose block"
        );
    }
}
