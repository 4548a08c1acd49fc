//! Stereo visual odometry (GTSAM's KITTI `VO_*` files).

use std::collections::HashMap;
use std::sync::Arc;

use apex_solver::ManifoldType;
use apex_solver::core::VarKey;
use apex_solver::factors::visual::{StereoCalibration as ApexStereoCalibration, StereoFactor};
use apex_solver::linalg::LinearSolverType;
use factor_core::Factor;
use slam_data::{StereoCalibration, StereoVo};
use slam_problems::ProblemError;
use slam_problems::stereo::by_landmark;
pub use slam_problems::stereo::{camera_to_world, factor_of, observation_name};

use crate::adapter::ApexFactor;
use crate::builder::ProblemBuilder;
use crate::built::Built;
use crate::options::{BuildError, BuildOptions, FactorChoice};
use crate::variables::apex_pose;

/// The variables of a stereo VO problem, as apex's keys.
pub type StereoKeys = slam_problems::stereo::StereoKeys<VarKey>;

/// apex-solver's stereo calibration, which has no skew and one principal
/// point for both images.
fn apex_calibration(c: &StereoCalibration) -> Result<ApexStereoCalibration, BuildError> {
    if c.skew != 0.0 {
        return Err(ProblemError::Unavailable(format!(
            "apex-solver's stereo factor has no skew; this calibration's is {}",
            c.skew
        ))
        .into());
    }
    ApexStereoCalibration::new(c.fx, c.fy, c.u0, c.v0, c.baseline).map_err(BuildError::Solver)
}

/// Builds the VO problem of `vo`.
pub(super) fn build(
    vo: &StereoVo,
    options: &BuildOptions,
) -> Result<Built<StereoKeys>, BuildError> {
    // apex's own `StereoFactor` takes world-to-camera poses.
    let world_to_camera = options.factors == FactorChoice::Apex;
    let calibration = match options.factors {
        FactorChoice::Apex => Some(apex_calibration(&vo.calibration)?),
        FactorChoice::Ours(_) => None,
    };
    let mut builder = ProblemBuilder::with_options(options);
    let mut poses = HashMap::with_capacity(vo.poses.len());
    let mut keys = StereoKeys {
        poses: Vec::with_capacity(vo.poses.len()),
        landmarks: HashMap::new(),
        world_to_camera,
    };
    for p in &vo.poses {
        let pose = camera_to_world(p);
        let value = if world_to_camera {
            apex_pose(&pose.inverse())
        } else {
            apex_pose(&pose)
        };
        let key = builder.variable(ManifoldType::SE3, value);
        keys.poses.push(key);
        poses.insert(p.id, (key, pose));
    }
    let landmarks = vo.initial_landmarks();
    let mut rank = HashMap::with_capacity(landmarks.len());
    let mut values = HashMap::with_capacity(landmarks.len());
    for (r, (id, position)) in landmarks.iter().enumerate() {
        let key = builder.variable(ManifoldType::RN, position.as_slice().to_vec());
        builder.eliminate(key);
        keys.landmarks.insert(*id, key);
        rank.insert(*id, r);
        values.insert(*id, *position);
    }
    for k in by_landmark(vo, &rank) {
        let o = &vo.observations[k];
        let (pose_key, pose) = poses[&o.pose];
        let landmark_key = keys.landmarks[&o.landmark];
        let factor = factor_of(vo, o, &pose, &values[&o.landmark]);
        let block: Arc<dyn apex_solver::factors::Factor + Send + Sync> =
            match (options.factors, &calibration) {
                (FactorChoice::Ours(kernels), _) => {
                    factor
                        .validate()
                        .map_err(|e| ProblemError::at_initial_values(observation_name(vo, k), e))?;
                    Arc::new(
                        ApexFactor::new(&factor, kernels)?.with_rejections(builder.rejections()),
                    )
                }
                (FactorChoice::Apex, Some(calibration)) => Arc::new(StereoFactor::new(
                    nalgebra_apex::Vector3::new(o.u_left, o.u_right, o.v),
                    calibration.clone(),
                )),
                (FactorChoice::Apex, None) => {
                    return Err(ProblemError::Unavailable("no stereo calibration".into()).into());
                }
            };
        builder.block(&[pose_key, landmark_key], block, None)?;
    }
    // The gauge: the first pose fixed, as GTSAM's example does.
    if let Some(&key) = keys.poses.first() {
        builder.fix(key, 6)?;
    }
    builder.finish(keys, LinearSolverType::ExplicitSparseSchur)
}
