//! Stereo visual odometry (GTSAM's KITTI `VO_*` files), the landmarks
//! eliminated.

use std::collections::HashMap;

use factor_core::lie::Se3RhoTheta;
use factor_core::{Factor, Storage};
use slam_data::StereoVo;
use slam_problems::ProblemError;
use slam_problems::stereo::{camera_to_world, factor_of, observation_name};

use factor_core::noise::Noise;
use slam_problems::Kernels;

use super::error::BuildError;
use crate::problem::{Problem, VariableId};

/// The variables of a stereo VO problem: each pose's camera-to-world pose
/// (`Se3RhoTheta`), in file order, and each landmark id's position.
pub type StereoKeys = slam_problems::stereo::StereoKeys<VariableId>;

/// Builds the VO problem of `vo`: the first pose fixed, each landmark
/// initialised as the file initialises it and eliminated.
pub(super) fn build(vo: &StereoVo, kernels: Kernels) -> Result<(Problem, StereoKeys), BuildError> {
    let mut problem = Problem::new();
    let mut poses = HashMap::with_capacity(vo.poses.len());
    let mut keys = StereoKeys {
        poses: Vec::with_capacity(vo.poses.len()),
        landmarks: HashMap::new(),
        world_to_camera: false,
    };
    for p in &vo.poses {
        let pose = camera_to_world(p);
        let id = problem.add_variable(&Se3RhoTheta::new(pose).to_scalars());
        keys.poses.push(id);
        poses.insert(p.id, (id, pose));
    }
    let mut positions = HashMap::new();
    for (landmark, position) in vo.initial_landmarks() {
        let id = problem.add_variable(position.as_slice());
        problem.eliminate(id);
        keys.landmarks.insert(landmark, id);
        positions.insert(landmark, position);
    }
    for (k, o) in vo.observations.iter().enumerate() {
        let missing =
            |what: &str, id: usize| ProblemError::Data(format!("observation {k}: no {what} {id}"));
        let &(pose_id, pose) = poses.get(&o.pose).ok_or_else(|| missing("pose", o.pose))?;
        let (&landmark_id, position) = keys
            .landmarks
            .get(&o.landmark)
            .zip(positions.get(&o.landmark))
            .ok_or_else(|| missing("landmark", o.landmark))?;
        let factor = factor_of(vo, o, &pose, position);
        factor
            .validate()
            .map_err(|e| ProblemError::at_initial_values(observation_name(vo, k), e))?;
        problem.add_by(
            &factor,
            &[pose_id, landmark_id],
            &Noise::Unit,
            None,
            kernels,
        )?;
    }
    // The gauge: the first pose fixed, as GTSAM's example and the general
    // path do.
    if let Some(&id) = keys.poses.first() {
        problem.fix(id);
    }
    Ok((problem, keys))
}
