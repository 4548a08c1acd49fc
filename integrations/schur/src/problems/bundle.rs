//! Bundle adjustment of BAL and Bundler problems (Snavely's camera model),
//! the points eliminated.

use factor_apex::problems::bundle::{
    bal_camera, camera_pose, factor_of, observation_name, solved_bal, solved_bundler,
};
use factor_core::lie::Se3RhoTheta;
use factor_core::{Factor, Storage};
use nalgebra::Vector3;
use slam_data::{BalCamera, BalProblem, BundlerProblem, SnavelyIntrinsics};
use slam_factors::SnavelyReprojection;

use super::{BuildError, Built, Keys};
use crate::problem::{Problem, VariableId};

/// The variables of a bundle-adjustment problem.
#[derive(Debug, Clone)]
pub struct BundleKeys {
    /// Each camera's world-to-camera pose (`Se3RhoTheta`).
    pub poses: Vec<VariableId>,
    /// Each camera's `[f, k1, k2]`.
    pub intrinsics: Vec<VariableId>,
    /// Each point.
    pub points: Vec<VariableId>,
}

/// Builds the bundle adjustment of `bal`: camera 0's pose fixed, the
/// points eliminated.
pub(super) fn build(bal: &BalProblem) -> Result<Built, BuildError> {
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
        factor.validate().map_err(|error| BuildError::Degenerate {
            which: format!("{} at the initial values", observation_name(bal, k)),
            error,
        })?;
        problem.add(
            &factor,
            &[
                keys.poses[o.camera],
                keys.intrinsics[o.camera],
                keys.points[o.point],
            ],
        )?;
    }
    // The gauge: camera 0's pose fixed (the scale is left to the damping),
    // as the general path holds it.
    if let Some(&pose) = keys.poses.first() {
        problem.fix(pose);
    }
    Ok(Built {
        problem,
        keys: Keys::Bundle(keys),
        blocks: bal.observations.len(),
    })
}

impl BundleKeys {
    /// Camera `k` of the values, as BAL writes it.
    fn camera<'a>(&self, k: usize, value: &impl Fn(VariableId) -> &'a [f64]) -> BalCamera {
        let pose = Se3RhoTheta::<f64>::from_scalars(value(self.poses[k])).se3();
        bal_camera(&pose, value(self.intrinsics[k]))
    }

    /// `bal` with the values' cameras and points.
    pub fn write_bal<'a>(
        &self,
        bal: &BalProblem,
        value: impl Fn(VariableId) -> &'a [f64],
    ) -> BalProblem {
        solved_bal(
            bal,
            |k| self.camera(k, &value),
            |j| Vector3::from_column_slice(value(self.points[j])),
        )
    }

    /// `bundler` with the values' cameras and points.
    pub fn write_bundler<'a>(
        &self,
        bundler: &BundlerProblem,
        value: impl Fn(VariableId) -> &'a [f64],
    ) -> BundlerProblem {
        solved_bundler(
            bundler,
            |k| self.camera(k, &value),
            |j| Vector3::from_column_slice(value(self.points[j])),
        )
    }
}
