//! Bundle adjustment of BAL and Bundler problems (Snavely's camera model),
//! the points eliminated.

use factor_core::lie::Se3RhoTheta;
use factor_core::{Factor, Storage};
use slam_data::{BalProblem, SnavelyIntrinsics};
use slam_factors::SnavelyReprojection;
use slam_problems::ProblemError;
use slam_problems::bundle::{camera_pose, factor_of, observation_name};

use factor_core::noise::Noise;
use slam_problems::Kernels;

use super::error::BuildError;
use crate::problem::{Problem, VariableId};

/// The variables of a bundle-adjustment problem: each camera's
/// world-to-camera pose (`Se3RhoTheta`) and `[f, k1, k2]`, each point.
pub type BundleKeys = slam_problems::bundle::BundleKeys<VariableId>;

/// Builds the bundle adjustment of `bal`: camera 0's pose fixed, the
/// points eliminated.
pub(super) fn build(
    bal: &BalProblem,
    kernels: Kernels,
) -> Result<(Problem, BundleKeys), BuildError> {
    let mut problem = Problem::new();
    let mut keys = BundleKeys {
        poses: Vec::with_capacity(bal.cameras.len()),
        intrinsics: Vec::with_capacity(bal.cameras.len()),
        points: Vec::with_capacity(bal.points.len()),
    };
    for camera in &bal.cameras {
        let pose = Se3RhoTheta::new(camera_pose(camera));
        keys.poses.push(problem.add_variable(&pose.to_scalars()));
        let SnavelyIntrinsics { focal, k1, k2 } = camera.intrinsics;
        keys.intrinsics.push(problem.add_variable(&[focal, k1, k2]));
    }
    for point in &bal.points {
        let id = problem.add_variable(point.as_slice());
        problem.eliminate(id);
        keys.points.push(id);
    }
    // Each camera's pose and intrinsics set once, in a template factor (its
    // first observation's), rather than at each observation.
    let mut templates: Vec<Option<SnavelyReprojection>> = vec![None; bal.cameras.len()];
    for (k, o) in bal.observations.iter().enumerate() {
        let template = templates[o.camera].get_or_insert_with(|| factor_of(bal, k));
        let factor = SnavelyReprojection {
            observed: o.pixel,
            point: bal.points[o.point],
            ..template.clone()
        };
        factor
            .validate()
            .map_err(|e| ProblemError::at_initial_values(observation_name(bal, k), e))?;
        let ids = [
            keys.poses[o.camera],
            keys.intrinsics[o.camera],
            keys.points[o.point],
        ];
        problem.add_by(&factor, &ids, &Noise::Unit, None, kernels)?;
    }
    // The gauge: camera 0's pose fixed (the scale is left to the damping),
    // as the general path holds it.
    if let Some(&pose) = keys.poses.first() {
        problem.fix(pose);
    }
    Ok((problem, keys))
}
