//! Bundle adjustment of BAL and Bundler problems (Snavely's camera model).

use apex_solver::apex_camera_models::{BALPinholeCameraStrict, DistortionModel, PinholeParams};
use apex_solver::core::VarKey;
use apex_solver::factors::SelfCalibration;
use apex_solver::factors::visual::ProjectionFactor;
use apex_solver::linalg::LinearSolverType;
use apex_solver::{ManifoldType, apex_camera_models::CameraModelError};
use factor_core::Factor;
use slam_data::{BalProblem, SnavelyIntrinsics};
use slam_problems::ProblemError;
use slam_problems::bundle::by_point;
pub use slam_problems::bundle::{
    bal_camera, camera_pose, factor_of, observation_name, solved_bal, solved_bundler,
};
use std::sync::Arc;

use crate::adapter::ApexFactor;
use crate::builder::ProblemBuilder;
use crate::built::Built;
use crate::options::{BuildError, BuildOptions, FactorChoice};
use crate::variables::apex_pose;

/// The variables of a bundle-adjustment problem, as apex's keys.
pub type BundleKeys = slam_problems::bundle::BundleKeys<VarKey>;

/// apex-solver's own factor for observation `k`.
fn apex_factor(
    bal: &BalProblem,
    k: usize,
) -> Result<ProjectionFactor<BALPinholeCameraStrict, SelfCalibration>, CameraModelError> {
    let o = &bal.observations[k];
    let SnavelyIntrinsics { focal, k1, k2 } = bal.cameras[o.camera].intrinsics;
    let camera = BALPinholeCameraStrict::new(
        PinholeParams::new(focal, focal, 0.0, 0.0)?,
        DistortionModel::Radial { k1, k2 },
    )?;
    let observed = nalgebra_apex::Matrix2xX::from_columns(&[nalgebra_apex::Vector2::new(
        o.pixel.x, o.pixel.y,
    )]);
    Ok(ProjectionFactor::new(observed, camera))
}

/// Builds the bundle adjustment of `bal`.
pub(super) fn build(
    bal: &BalProblem,
    options: &BuildOptions,
) -> Result<Built<BundleKeys>, BuildError> {
    let mut builder = ProblemBuilder::with_options(options);
    let mut keys = BundleKeys {
        poses: Vec::with_capacity(bal.cameras.len()),
        intrinsics: Vec::with_capacity(bal.cameras.len()),
        points: Vec::with_capacity(bal.points.len()),
    };
    for camera in &bal.cameras {
        keys.poses
            .push(builder.variable(ManifoldType::SE3, apex_pose(&camera_pose(camera))));
        let SnavelyIntrinsics { focal, k1, k2 } = camera.intrinsics;
        keys.intrinsics
            .push(builder.variable(ManifoldType::RN, vec![focal, k1, k2]));
    }
    for point in &bal.points {
        let key = builder.variable(ManifoldType::RN, point.as_slice().to_vec());
        builder.eliminate(key);
        keys.points.push(key);
    }
    for k in by_point(bal) {
        let o = &bal.observations[k];
        let (pose, intrinsics, point) = (
            keys.poses[o.camera],
            keys.intrinsics[o.camera],
            keys.points[o.point],
        );
        match options.factors {
            FactorChoice::Ours(kernels) => {
                let factor = factor_of(bal, k);
                factor
                    .validate()
                    .map_err(|e| ProblemError::at_initial_values(observation_name(bal, k), e))?;
                let served =
                    ApexFactor::new(&factor, kernels)?.with_rejections(builder.rejections());
                builder.block(&[pose, intrinsics, point], Arc::new(served), None)?;
            }
            FactorChoice::Apex => {
                let factor = apex_factor(bal, k).map_err(|e| BuildError::Solver(e.to_string()))?;
                builder.block(&[pose, point, intrinsics], Arc::new(factor), None)?;
            }
        }
    }
    // The gauge: camera 0's pose fixed (six of its seven dimensions; the
    // scale is left to the damping), as apex-solver's own BA example does.
    if let Some(&pose) = keys.poses.first() {
        builder.fix(pose, 6)?;
    }
    builder.finish(keys, LinearSolverType::ExplicitSparseSchur)
}
