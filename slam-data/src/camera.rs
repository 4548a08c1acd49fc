//! The camera model of Bundler and BAL files (Snavely et al.).
//!
//! A world point `X` goes to the camera frame as `P = R X + t` (`R`, `t`
//! world-to-camera). The camera looks down its **−z** axis (y up, as in
//! OpenGL), so a point in front has `P_z < 0`, and
//!
//! ```text
//! p = −P / P_z                      (normalised image point)
//! r = 1 + k1 ‖p‖² + k2 ‖p‖⁴         (radial distortion)
//! pixel = f r p                     (origin at the image centre, x right, y up)
//! ```
//!
//! [`SnavelyCamera::world_from_camera_cv`] gives the same camera in the
//! computer-vision convention (x right, y down, looking down +z), which is
//! the pose GTSAM's readers give; in that convention the pixel is
//! `(u, −v)`.

use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector2, Vector3};

/// Focal length (pixels) and radial distortion coefficients of the model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnavelyIntrinsics {
    /// Focal length in pixels.
    pub focal: f64,
    /// Coefficient of ‖p‖² in the radial distortion.
    pub k1: f64,
    /// Coefficient of ‖p‖⁴ in the radial distortion.
    pub k2: f64,
}

impl SnavelyIntrinsics {
    /// The pixel of a point `p_camera` given in the camera frame; `None`
    /// unless it is in front of the camera (`P_z < 0`).
    pub fn project(&self, p_camera: &Vector3<f64>) -> Option<Vector2<f64>> {
        if p_camera.z >= 0.0 {
            return None;
        }
        let p = -p_camera.xy() / p_camera.z;
        let r2 = p.norm_squared();
        let distortion = 1.0 + r2 * (self.k1 + self.k2 * r2);
        Some(p * (self.focal * distortion))
    }
}

/// A camera of the model: world-to-camera rotation and translation, and
/// intrinsics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnavelyCamera {
    /// `R`, world to camera.
    pub rotation: Rotation3<f64>,
    /// `t`, world to camera: `P = R X + t`.
    pub translation: Vector3<f64>,
    /// Focal length and distortion.
    pub intrinsics: SnavelyIntrinsics,
}

impl SnavelyCamera {
    /// The pixel of world point `x`; `None` unless it is in front.
    pub fn project(&self, x: &Vector3<f64>) -> Option<Vector2<f64>> {
        self.intrinsics
            .project(&(self.rotation * x + self.translation))
    }

    /// The camera's position in the world, `−Rᵀ t`.
    pub fn centre(&self) -> Vector3<f64> {
        -(self.rotation.inverse() * self.translation)
    }

    /// World-from-camera pose in the computer-vision convention (x right, y
    /// down, looking down +z): rotation `Rᵀ diag(1, −1, −1)`, translation
    /// `−Rᵀ t`. This is GTSAM's `openGL2gtsam`; pair it with pixel `(u, −v)`.
    pub fn world_from_camera_cv(&self) -> Isometry3<f64> {
        let flip = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, -1.0));
        let rotation = Rotation3::from_matrix_unchecked(self.rotation.inverse().matrix() * flip);
        Isometry3::from_parts(
            Translation3::from(self.centre()),
            UnitQuaternion::from_rotation_matrix(&rotation),
        )
    }
}
