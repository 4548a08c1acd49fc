//! Bundle adjustment of BAL and Bundler problems (Snavely's camera model).

use apex_solver::apex_camera_models::{BALPinholeCameraStrict, DistortionModel, PinholeParams};
use apex_solver::core::VarKey;
use apex_solver::factors::SelfCalibration;
use apex_solver::factors::visual::ProjectionFactor;
use apex_solver::linalg::LinearSolverType;
use apex_solver::{ManifoldType, apex_camera_models::CameraModelError};
use factor_core::Factor;
use factor_core::lie::{Se3, Se3RhoTheta, So3};
use nalgebra::{Rotation3, Vector2, Vector3};
use slam_data::{BalCamera, BalProblem, BundlerProblem, SnavelyIntrinsics, ordinal};
use slam_factors::{RadialIntrinsics, SnavelyReprojection};
use std::sync::Arc;

use crate::adapter::ApexFactor;
use crate::builder::ProblemBuilder;
use crate::built::Built;
use crate::options::{BuildError, BuildOptions, FactorChoice};
use crate::variables::apex_pose;

/// The variables of a bundle-adjustment problem, by key type `K`: apex's
/// `VarKey` here, the Schur-complement solver's variable ids in crate
/// `factor-schur`, which builds the same problem.
#[derive(Debug, Clone)]
pub struct BundleKeys<K = VarKey> {
    /// Each camera's world-to-camera pose (here `SE3`).
    pub poses: Vec<K>,
    /// Each camera's `[f, k1, k2]` (`Rn(3)`).
    pub intrinsics: Vec<K>,
    /// Each point (`Rn(3)`).
    pub points: Vec<K>,
}

/// A BAL camera's world-to-camera pose.
pub fn camera_pose(camera: &BalCamera) -> Se3<f64> {
    Se3::new(So3::exp(&camera.rotation), camera.translation)
}

/// Observation `k` of `bal` as errors name it (counted from 1, as the
/// readers count, with its camera and point indices).
pub fn observation_name(bal: &BalProblem, k: usize) -> String {
    let o = &bal.observations[k];
    format!(
        "{} (camera index {}, point index {})",
        ordinal("observation", k, bal.observations.len()),
        o.camera,
        o.point
    )
}

/// The factor of observation `k` of `bal` at the problem's values.
pub fn factor_of(bal: &BalProblem, k: usize) -> SnavelyReprojection {
    let o = &bal.observations[k];
    let camera = &bal.cameras[o.camera];
    let SnavelyIntrinsics { focal, k1, k2 } = camera.intrinsics;
    SnavelyReprojection {
        observed: o.pixel,
        pose: Se3RhoTheta::new(camera_pose(camera)),
        intrinsics: RadialIntrinsics::new(focal, k1, k2),
        point: bal.points[o.point],
    }
}

/// The observations grouped by point, points in order, each group in file
/// order: the order the Schur solver evaluates them in.
fn by_point(bal: &BalProblem) -> Vec<usize> {
    let mut order: Vec<usize> = (0..bal.observations.len()).collect();
    order.sort_by_key(|&k| bal.observations[k].point);
    order
}

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
                factor.validate().map_err(|error| BuildError::Degenerate {
                    which: format!("{} at the initial values", observation_name(bal, k)),
                    error,
                })?;
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

impl<K: Copy> BundleKeys<K> {
    /// Camera `k` of the values `value(key)`, its pose read by `pose`.
    fn camera<'a>(
        &self,
        k: usize,
        pose: &impl Fn(&[f64]) -> Se3<f64>,
        value: &impl Fn(K) -> &'a [f64],
    ) -> BalCamera {
        bal_camera(&pose(value(self.poses[k])), value(self.intrinsics[k]))
    }

    /// `bal` with the cameras and points of the values `value(key)` (a
    /// solution's), each camera's world-to-camera pose read from its
    /// values by `pose` (here [`apex_se3`](crate::variables::apex_se3)).
    pub fn write_bal<'a>(
        &self,
        bal: &BalProblem,
        pose: impl Fn(&[f64]) -> Se3<f64>,
        value: impl Fn(K) -> &'a [f64],
    ) -> BalProblem {
        solved_bal(
            bal,
            |k| self.camera(k, &pose, &value),
            |j| Vector3::from_column_slice(value(self.points[j])),
        )
    }

    /// `bundler` with the cameras and points of the values, as
    /// [`Self::write_bal`].
    pub fn write_bundler<'a>(
        &self,
        bundler: &BundlerProblem,
        pose: impl Fn(&[f64]) -> Se3<f64>,
        value: impl Fn(K) -> &'a [f64],
    ) -> BundlerProblem {
        solved_bundler(
            bundler,
            |k| self.camera(k, &pose, &value),
            |j| Vector3::from_column_slice(value(self.points[j])),
        )
    }
}

/// The BAL camera of world-to-camera pose `pose` and intrinsics
/// `[f, k1, k2]`: the inverse of [`camera_pose`].
pub fn bal_camera(pose: &Se3<f64>, intrinsics: &[f64]) -> BalCamera {
    BalCamera {
        rotation: pose.rotation.log(),
        translation: pose.translation,
        intrinsics: SnavelyIntrinsics {
            focal: intrinsics[0],
            k1: intrinsics[1],
            k2: intrinsics[2],
        },
    }
}

/// `bal` with a solution's cameras (`camera(k)`) and points (`point(j)`).
pub fn solved_bal(
    bal: &BalProblem,
    camera: impl Fn(usize) -> BalCamera,
    point: impl Fn(usize) -> Vector3<f64>,
) -> BalProblem {
    BalProblem {
        cameras: (0..bal.cameras.len()).map(camera).collect(),
        points: (0..bal.points.len()).map(point).collect(),
        observations: bal.observations.clone(),
    }
}

/// `bundler` with a solution's cameras (`camera(k)`, written as rotation
/// matrices) and points (`point(j)`; colours and feature keys kept).
pub fn solved_bundler(
    bundler: &BundlerProblem,
    camera: impl Fn(usize) -> BalCamera,
    point: impl Fn(usize) -> Vector3<f64>,
) -> BundlerProblem {
    let mut out = bundler.clone();
    for (k, written) in out.cameras.iter_mut().enumerate() {
        let solved = camera(k);
        written.rotation = *Rotation3::new(solved.rotation).matrix();
        written.translation = solved.translation;
        written.intrinsics = solved.intrinsics;
    }
    for (j, written) in out.points.iter_mut().enumerate() {
        written.position = point(j);
    }
    out
}

/// `‖f r p − observed‖` of each observation (NaN where degenerate).
pub(super) fn reprojection_errors(bal: &BalProblem) -> Vec<f64> {
    (0..bal.observations.len())
        .map(|k| {
            factor_of(bal, k)
                .residual()
                .map_or(f64::NAN, |r: Vector2<f64>| r.norm())
        })
        .collect()
}
