//! Stereo reprojection for a calibrated, rectified camera pair, as GTSAM's
//! `GenericStereoFactor3D` with `Cal3_S2Stereo`.

use nalgebra::Vector3;

use crate::{DEGENERACY_TOLERANCE, check_residual_digits, degenerate, max_abs};
use factor_core::lie::Se3RhoTheta;
use factor_core::storage::{Layout, Storage, StorageError};
use factor_core::validation::{exceeds, number_text};
use factor_core::{Factor, FactorError, Scalar};

/// A rectified stereo pair's intrinsics `[fx, fy, s, u0, v0, b]`: focal
/// lengths and skew (pixels), principal point (pixels) and baseline (the
/// right camera sits at `+b` along the left camera's x axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StereoIntrinsics<S> {
    /// Horizontal focal length.
    pub fx: S,
    /// Vertical focal length.
    pub fy: S,
    /// Skew.
    pub skew: S,
    /// Principal point, horizontal.
    pub u0: S,
    /// Principal point, vertical.
    pub v0: S,
    /// Baseline.
    pub baseline: S,
}

impl<S: Scalar> StereoIntrinsics<S> {
    /// From `[fx, fy, s, u0, v0, b]`.
    pub fn new(fx: S, fy: S, skew: S, u0: S, v0: S, baseline: S) -> Self {
        StereoIntrinsics {
            fx,
            fy,
            skew,
            u0,
            v0,
            baseline,
        }
    }

    /// `[u_L, u_R, v]` of a point in the left camera's frame (x right, y
    /// down, z forward): `u_L = fx x/z + s y/z + u0`, `u_R = u_L − fx b/z`,
    /// `v = fy y/z + v0`. `z ≠ 0` is the caller's to check.
    pub fn project(&self, p: &Vector3<S>) -> Vector3<S> {
        let inverse_depth = p.z.recip();
        let (x, y) = (p.x * inverse_depth, p.y * inverse_depth);
        let u_left = self.fx * x + self.skew * y + self.u0;
        Vector3::new(
            u_left,
            u_left - self.fx * self.baseline * inverse_depth,
            self.fy * y + self.v0,
        )
    }
}

/// Stored `[fx, fy, s, u0, v0, b]`; from users, non-zero focal lengths.
impl<S: Scalar> Storage<S> for StereoIntrinsics<S> {
    type With<T: Scalar> = StereoIntrinsics<T>;
    const SCALARS: usize = 6;
    fn layout() -> Layout {
        Layout::array(&["fx", "fy", "s", "u0", "v0", "b"])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> StereoIntrinsics<T> {
        StereoIntrinsics::new(
            f(self.fx),
            f(self.fy),
            f(self.skew),
            f(self.u0),
            f(self.v0),
            f(self.baseline),
        )
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        StereoIntrinsics::new(next(), next(), next(), next(), next(), next())
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        for (i, name) in [(0, "fx"), (1, "fy")] {
            if input[i] == 0.0 {
                return Err(StorageError::new(format!("focal length {name} is zero"))
                    .within(&format!("[{i}]")));
            }
        }
        Ok(input.to_vec())
    }
}

/// The stereo reprojection error of a landmark, predicted minus observed, in
/// pixels: `π(T⁻¹ X) − [u_L, u_R, v]` with `π` of [`StereoIntrinsics::project`]
/// (GTSAM's `GenericStereoFactor3D`, `StereoCamera::project`).
///
/// - `pose` `T = [R | t]` maps the left camera to the world (camera to world,
///   as KITTI VO files store it; the camera frame is x right, y down, z
///   forward): **right** perturbation, tangent `[δρ, δθ]` ([`Se3RhoTheta`]),
///   apex-solver's chart, the body-frame perturbation GTSAM's `Pose3`
///   retracts with.
/// - `landmark` `X` in the world: additive.
///
/// Degenerate: the landmark at or behind the camera (`z ≤ 1e-9` times the
/// largest coordinate of `X − t`, `X` or `t`), or observed so close to a
/// far off-axis prediction that the residual loses its digits
/// ([`crate::check_residual_digits`]).
#[derive(Debug, Clone, Factor)]
#[factor(
    residual = stereo_reprojection_residual,
    dim = 3,
    validate = validate_stereo_reprojection
)]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = factor_generated::stereo_reprojection::stereo_reprojection,
        regenerate = "cargo run --release --no-default-features -- generate",
        hosts(apex)
    )
)]
pub struct StereoReprojection<S: Scalar = f64> {
    /// `[fx, fy, s, u0, v0, b]`.
    pub calibration: StereoIntrinsics<S>,
    /// The measurement `[u_L, u_R, v]`, pixels.
    pub observed: Vector3<S>,
    /// Camera-to-world pose of the left camera.
    #[variable(right)]
    pub pose: Se3RhoTheta<S>,
    /// The landmark in the world.
    #[variable]
    pub landmark: Vector3<S>,
}

/// The landmark in the left camera's frame, `Rᵀ (X − t)`.
fn landmark_in_camera<S: Scalar>(f: &StereoReprojection<S>) -> Vector3<S> {
    f.pose.inverse_transform_point(&f.landmark)
}

/// `π(Rᵀ (X − t)) − [u_L, u_R, v]`.
pub fn stereo_reprojection_residual<S: Scalar>(f: &StereoReprojection<S>) -> Vector3<S> {
    f.calibration.project(&landmark_in_camera(f)) - f.observed
}

/// Rejects a landmark at or behind the camera, and a residual that has lost
/// its digits to the depth's rounding.
pub fn validate_stereo_reprojection(f: &StereoReprojection<f64>) -> Result<(), FactorError> {
    // Only the depth is needed: the third row of `Rᵀ`, i.e. the third
    // column of `R(q)` written from the quaternion (in the homogeneous form
    // the kernels use), times `X − t`. This runs at every linearization.
    let q = f.pose.se3().rotation.quaternion;
    let column = Vector3::new(
        2.0 * (q.x * q.z + q.w * q.y),
        2.0 * (q.y * q.z - q.w * q.x),
        q.w * q.w - q.x * q.x - q.y * q.y + q.z * q.z,
    );
    let t = f.pose.translation();
    let offset = f.landmark - t;
    let depth = column.dot(&offset);
    let scale = max_abs(&[offset, f.landmark, t]);
    if !exceeds(depth, DEGENERACY_TOLERANCE * scale) {
        return Err(degenerate(
            StereoReprojection::NAME,
            format!(
                "landmark is at or behind the camera (depth z = {})",
                number_text(depth)
            ),
        ));
    }
    // The pixels move by `(|fx| + |s|)(1 + |x/z| + |y/z|) + |fx b/z|` (the
    // columns) and `|fy| (1 + |y/z|)` (the row) per relative error of the
    // depth and of `x`, `y`.
    let p = landmark_in_camera(f);
    let c = &f.calibration;
    let (x, y) = ((p.x / depth).abs(), (p.y / depth).abs());
    let terms = (c.fx.abs() + c.skew.abs()) * (1.0 + x + y)
        + (c.fx * c.baseline / depth).abs()
        + c.fy.abs() * (1.0 + y);
    let residual = || stereo_reprojection_residual(f).norm();
    check_residual_digits(StereoReprojection::NAME, residual, scale / depth, terms)
}
