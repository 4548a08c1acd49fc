//! Bundle adjustment of BAL and Bundler problems (Snavely's camera model):
//! each observation's factor, its name in errors, and a solution written
//! back as a BAL or Bundler problem.

use factor_core::lie::{Se3, Se3RhoTheta, So3};
use nalgebra::{Rotation3, Vector2, Vector3};
use slam_data::{BalCamera, BalProblem, BundlerProblem, SnavelyIntrinsics, ordinal};
use slam_factors::{RadialIntrinsics, SnavelyReprojection};

/// The variables of a bundle-adjustment problem, by key type `K` (each
/// solver's own: apex-solver's `VarKey`, the Schur-complement solver's
/// variable ids).
#[derive(Debug, Clone)]
pub struct BundleKeys<K> {
    /// Each camera's world-to-camera pose.
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
pub fn by_point(bal: &BalProblem) -> Vec<usize> {
    let mut order: Vec<usize> = (0..bal.observations.len()).collect();
    order.sort_by_key(|&k| bal.observations[k].point);
    order
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
    /// values by `pose` (in the solver's chart).
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
pub(crate) fn reprojection_errors(bal: &BalProblem) -> Vec<f64> {
    (0..bal.observations.len())
        .map(|k| {
            factor_of(bal, k)
                .residual()
                .map_or(f64::NAN, |r: Vector2<f64>| r.norm())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`bal_camera`] inverts [`camera_pose`]: the rotation read back from
    /// the pose is the camera's angle-axis vector (angle below π), the
    /// translation and intrinsics are kept.
    #[test]
    fn a_camera_reads_back_from_its_pose() {
        let camera = BalCamera {
            rotation: Vector3::new(0.3, -1.1, 0.7),
            translation: Vector3::new(-2.0, 0.5, 4.0),
            intrinsics: SnavelyIntrinsics {
                focal: 520.0,
                k1: -0.2,
                k2: 0.03,
            },
        };
        let back = bal_camera(&camera_pose(&camera), &[520.0, -0.2, 0.03]);
        assert!(
            (back.rotation - camera.rotation).norm() <= 1e-14,
            "{back:?}"
        );
        assert_eq!(back.translation, camera.translation);
        assert_eq!(back.intrinsics, camera.intrinsics);
    }
}
