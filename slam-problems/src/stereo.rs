//! Stereo visual odometry (GTSAM's KITTI `VO_*` files): each
//! observation's factor, its name in errors, and a solution written back as
//! a VO file.

use std::collections::HashMap;

use factor_core::lie::{Quaternion, Se3, Se3RhoTheta, So3};
use nalgebra::Vector3;
use slam_data::{CameraPose, StereoCalibration, StereoObservation, StereoVo, ordinal};
use slam_factors::{StereoIntrinsics, StereoReprojection};

/// The variables of a stereo VO problem, by key type `K` (each solver's
/// own).
#[derive(Debug, Clone)]
pub struct StereoKeys<K> {
    /// Each pose's key, in file order.
    pub poses: Vec<K>,
    /// Each landmark id's key.
    pub landmarks: HashMap<usize, K>,
    /// Whether the poses are world-to-camera (apex's own stereo factor)
    /// rather than camera-to-world (this project's).
    pub world_to_camera: bool,
}

/// Observation `k` of `vo` as errors name it (counted from 1, as the
/// readers count, with its pose and landmark ids).
pub fn observation_name(vo: &StereoVo, k: usize) -> String {
    let o = &vo.observations[k];
    format!(
        "{} (pose {}, landmark {})",
        ordinal("observation", k, vo.observations.len()),
        o.pose,
        o.landmark
    )
}

/// A VO file's camera-to-world pose (its nearest rotation, the quaternion
/// normalised: `CameraPose::isometry`'s is unit only to about 1e-8).
pub fn camera_to_world(pose: &CameraPose) -> Se3<f64> {
    let iso = pose.isometry();
    let q = iso.rotation;
    Se3::new(
        So3::from_quaternion(Quaternion::new(q.i, q.j, q.k, q.w).normalized()),
        iso.translation.vector,
    )
}

fn intrinsics(c: &StereoCalibration) -> StereoIntrinsics<f64> {
    StereoIntrinsics::new(c.fx, c.fy, c.skew, c.u0, c.v0, c.baseline)
}

/// The factor of observation `o` of `vo` with the pose and landmark at
/// `pose` (camera to world) and `landmark`.
pub fn factor_of(
    vo: &StereoVo,
    o: &StereoObservation,
    pose: &Se3<f64>,
    landmark: &Vector3<f64>,
) -> StereoReprojection {
    StereoReprojection {
        calibration: intrinsics(&vo.calibration),
        observed: Vector3::new(o.u_left, o.u_right, o.v),
        pose: Se3RhoTheta::new(*pose),
        landmark: *landmark,
    }
}

/// The observations grouped by landmark, landmarks in order of first
/// appearance, each group in file order.
pub fn by_landmark(vo: &StereoVo, rank: &HashMap<usize, usize>) -> Vec<usize> {
    let mut order: Vec<usize> = (0..vo.observations.len()).collect();
    order.sort_by_key(|&k| rank[&vo.observations[k].landmark]);
    order
}

impl<K: Copy> StereoKeys<K> {
    /// `vo` with the poses of the values `value(key)` (a solution's, each
    /// pose read from its values by `pose`, in the solver's chart), and each observation's
    /// landmark in its camera's frame recomputed from them (so that reading
    /// the file back initialises every landmark at its optimized position).
    pub fn write<'a>(
        &self,
        vo: &StereoVo,
        pose: impl Fn(&[f64]) -> Se3<f64>,
        value: impl Fn(K) -> &'a [f64],
    ) -> StereoVo {
        let mut out = vo.clone();
        let mut solved = HashMap::with_capacity(vo.poses.len());
        for (p, &key) in out.poses.iter_mut().zip(&self.poses) {
            let pose = pose(value(key));
            let pose = if self.world_to_camera {
                pose.inverse()
            } else {
                pose
            };
            p.rotation = pose.rotation.matrix();
            p.translation = pose.translation;
            solved.insert(p.id, pose);
        }
        for o in &mut out.observations {
            if let (Some(pose), Some(&key)) = (solved.get(&o.pose), self.landmarks.get(&o.landmark))
            {
                o.landmark_in_camera = pose
                    .inverse()
                    .transform_point(&Vector3::from_column_slice(value(key)));
            }
        }
        out
    }
}

/// `‖π(T⁻¹ X) − [u_L, u_R, v]‖` of each observation, landmarks initialised
/// as the file initialises them (NaN where degenerate).
pub(crate) fn reprojection_errors(vo: &StereoVo) -> Vec<f64> {
    let poses: HashMap<usize, Se3<f64>> = vo
        .poses
        .iter()
        .map(|p| (p.id, camera_to_world(p)))
        .collect();
    let landmarks: HashMap<usize, Vector3<f64>> = vo.initial_landmarks().into_iter().collect();
    vo.observations
        .iter()
        .map(|o| match (poses.get(&o.pose), landmarks.get(&o.landmark)) {
            (Some(pose), Some(landmark)) => factor_of(vo, o, pose, landmark)
                .residual()
                .map_or(f64::NAN, |r: Vector3<f64>| r.norm()),
            _ => f64::NAN,
        })
        .collect()
}
