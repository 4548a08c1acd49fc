//! SE(3) with its tangent ordered translation first, `[δρ, δθ]`: the chart of
//! apex-solver, manif and Sophus (this project's [`Se3`] orders `[δω, δρ]`).
//!
//! A factor whose pose is meant for such a solver declares it
//! `#[variable(right)] pose: Se3RhoTheta<S>`: its Jacobian columns are then
//! the solver's own (`T ← T Exp([δρ, δθ])`: `R ← R Exp(δθ)`,
//! `t ← t + R Jl(δθ) δρ`), so the generated kernel emits the solver's block
//! and nothing is permuted or multiplied by an adjoint at run time. The stored
//! scalars are those of [`Se3`] (`[qx, qy, qz, qw, x, y, z]`); only the
//! tangent differs.
//!
//! Where the shipped factors meet: the factors of the documents (point,
//! line and plane) take a world-to-camera [`Se3`] perturbed on the left;
//! those of `slamjac solve` and g2o's (pose graphs, stereo, bundle
//! adjustment, g2o's lines and planes) a body- or camera-to-world
//! [`Se3RhoTheta`] perturbed on the right. One camera is
//! [`Se3RhoTheta::from_world_to_camera`] /
//! [`Se3RhoTheta::world_to_camera`] of the other, and
//! [`inverse_pose_block`] moves a Jacobian block between the two.

use nalgebra::{SMatrix, Vector3};

use crate::dual::Dual;
use crate::lie::Se3;
use crate::lie::se3::seeded_se3;
use crate::lie::so3::{left_jacobian, left_jacobian_inverse};
use crate::manifold::{Manifold, NoLocal, Perturbation};
use crate::scalar::Scalar;
use crate::storage::{Layout, Storage, StorageError};

/// A rigid transform `X ↦ R X + t` whose tangent is `[δρ, δθ]`
/// (translation, then rotation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Se3RhoTheta<S>(Se3<S>);

impl<S: Scalar> Se3RhoTheta<S> {
    /// The pose `T`.
    pub fn new(pose: Se3<S>) -> Self {
        Se3RhoTheta(pose)
    }

    /// The pose as [`Se3`] (the same transform; only the tangent differs).
    pub fn se3(&self) -> Se3<S> {
        self.0
    }

    /// `t`.
    pub fn translation(&self) -> Vector3<S> {
        self.0.translation
    }

    /// `T x = R x + t`.
    pub fn transform_point(&self, x: &Vector3<S>) -> Vector3<S> {
        self.0.transform_point(x)
    }

    /// `T⁻¹ y = Rᵀ (y − t)`.
    pub fn inverse_transform_point(&self, y: &Vector3<S>) -> Vector3<S> {
        self.0.rotation.inverse().rotate(&(y - self.0.translation))
    }
}

impl<S: Scalar> Se3RhoTheta<S> {
    /// The camera-to-world pose of a camera given by its world-to-camera
    /// pose `T_cw` (document 000's [`Se3`]): `T_cw⁻¹`.
    pub fn from_world_to_camera(world_to_camera: &Se3<S>) -> Self {
        Se3RhoTheta::new(world_to_camera.inverse())
    }

    /// The world-to-camera pose `self⁻¹` of the camera this camera-to-world
    /// pose places (document 000's pose of it).
    pub fn world_to_camera(&self) -> Se3<S> {
        self.0.inverse()
    }
}

/// The Jacobian block of a residual w.r.t. a pose, moved to the inverse
/// pose in the other chart: a block w.r.t. document 000's world-to-camera
/// [`Se3`] `T` perturbed on the **left** (`T ← Exp(δξ) T`, columns `[δω,
/// δρ]`) becomes the block w.r.t. the camera-to-world [`Se3RhoTheta`] `X =
/// T⁻¹` perturbed on the **right** (`X ← X Exp([δρ, δθ])`, columns `[δρ,
/// δθ]`), and back (the map is its own inverse).
///
/// From `(X Exp(ξ))⁻¹ = Exp(−ξ) X⁻¹`: the right step `[δρ, δθ]` of `X` is
/// the left step `−[δθ, δρ]` of `T`, so `J_X = −[J_T,ρ | J_T,ω]` (the
/// halves swapped and negated). Exact for the Jacobians, since the two
/// retractions agree with `X Exp(ξ)` and `Exp(δξ) T` to first order.
pub fn inverse_pose_block<const R: usize>(block: &SMatrix<f64, R, 6>) -> SMatrix<f64, R, 6> {
    SMatrix::from_fn(|r, c| -block[(r, (c + 3) % 6)])
}

impl<S: Scalar> From<Se3<S>> for Se3RhoTheta<S> {
    fn from(pose: Se3<S>) -> Self {
        Se3RhoTheta::new(pose)
    }
}

/// Stored as [`Se3`]: `{rotation: [qx, qy, qz, qw], translation: [x, y, z]}`.
impl<S: Scalar> Storage<S> for Se3RhoTheta<S> {
    type With<T: Scalar> = Se3RhoTheta<T>;
    const SCALARS: usize = 7;
    fn layout() -> Layout {
        <Se3<S> as Storage<S>>::layout()
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Se3RhoTheta<T> {
        Se3RhoTheta(self.0.map_scalars(f))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        Se3RhoTheta(Se3::read_scalars(next))
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        <Se3<f64> as Storage<f64>>::from_input(input)
    }
}

/// `[δρ, δθ]` reordered to [`Se3`]'s `[δθ, δρ]`.
fn rotation_first<S: Scalar>(delta: &[S]) -> [S; 6] {
    [delta[3], delta[4], delta[5], delta[0], delta[1], delta[2]]
}

/// The exact exponential on either side, the tangent read as `[δρ, δθ]`:
/// - Right: `T ← T Exp([δρ, δθ])`, `R ← R Exp(δθ)`, `t ← t + R Jl(δθ) δρ`:
///   apex-solver's `T ⊕ τ`. [`Se3`]'s right chart (document 001's (4.1)–(4.2))
///   moves `t` by `R δρ` instead: the same to first order (the same
///   Jacobians), but not the same steps, and the solver's steps are taken
///   in this chart. Measured on g2o's line and plane graphs
///   (`data/g2o-addons/`), the decoupled retraction took 181, 157 and 171
///   iterations where this one takes 75, 106 and 123, as apex-solver does.
/// - Left: `T ← Exp([δθ, δρ] of Se3) T`, [`Se3`]'s.
///
/// `local` is the inverse of each.
impl<S: Scalar> Manifold<S> for Se3RhoTheta<S> {
    const DIM: usize = 6;
    fn retract(&self, delta: &[S], side: Perturbation) -> Self {
        let stepped = self.0.retract(&rotation_first(delta), side);
        match side {
            Perturbation::Left => Se3RhoTheta(stepped),
            Perturbation::Right => {
                let rho = Vector3::new(delta[0], delta[1], delta[2]);
                let theta = Vector3::new(delta[3], delta[4], delta[5]);
                let moved = self.0.rotation.rotate(&(left_jacobian(&theta) * rho));
                Se3RhoTheta(Se3::new(stepped.rotation, self.0.translation + moved))
            }
        }
    }
    fn retract_first_order(&self, delta: &[S], side: Perturbation) -> Self {
        Se3RhoTheta(self.0.retract_first_order(&rotation_first(delta), side))
    }
    /// [`Se3`]'s closed form with the halves of the tangent swapped.
    #[inline(always)]
    fn seeded<const D: usize, const N: usize>(
        &self,
        side: Perturbation,
        offset: usize,
    ) -> <Self as Storage<S>>::With<Dual<N>>
    where
        S: Into<f64>,
    {
        let pose = self.0.map_scalars(&mut |s| s.into());
        Se3RhoTheta(seeded_se3(&pose, side, offset + 3, offset))
    }
    fn tangent_description(side: Perturbation) -> &'static str {
        match side {
            Perturbation::Left => {
                "left: T ← Exp(δξ) T, columns δξ = [δρ_x, δρ_y, δρ_z, δθ_x, δθ_y, δθ_z] \
                 (translation first)"
            }
            Perturbation::Right => {
                "right: T ← T Exp([δρ, δθ]) (apex-solver's chart), columns [δρ_x, δρ_y, δρ_z, \
                 δθ_x, δθ_y, δθ_z]"
            }
        }
    }
    fn local(&self, other: &Self, side: Perturbation, delta: &mut [S]) -> Result<(), NoLocal> {
        let mut theta_rho = [S::zero(); 6];
        self.0.local(&other.0, side, &mut theta_rho)?;
        if side == Perturbation::Right {
            // Se3's right chart gives `R⁻¹ (t' − t)` = `Jl(δθ) δρ`.
            let theta = Vector3::new(theta_rho[0], theta_rho[1], theta_rho[2]);
            let moved = Vector3::new(theta_rho[3], theta_rho[4], theta_rho[5]);
            let rho = left_jacobian_inverse(&theta) * moved;
            theta_rho[3..].copy_from_slice(&[rho.x, rho.y, rho.z]);
        }
        // The swap of the halves is its own inverse: `[δθ, δρ]` → `[δρ, δθ]`.
        delta[..6].copy_from_slice(&rotation_first(&theta_rho));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::lie::So3;

    fn pose() -> Se3<f64> {
        Se3::new(
            So3::exp(&Vector3::new(0.3, -0.2, 0.5)),
            Vector3::new(1.0, 2.0, -0.5),
        )
    }

    /// On the left the same step retracts `Se3RhoTheta` as it retracts
    /// `Se3` with the halves of the tangent swapped; on the right it is
    /// `T Exp(δ)` with the SE(3) exponential (`Se3::exp`, `[δω, δρ]`), and
    /// `local` inverts both.
    #[test]
    fn the_tangent_is_translation_first_and_the_right_step_is_the_exponential() {
        let pose = pose();
        let rho_theta = [0.1, -0.2, 0.3, 0.4, 0.2, -0.3];
        let theta_rho = [0.4, 0.2, -0.3, 0.1, -0.2, 0.3];
        assert_eq!(
            Se3RhoTheta::new(pose)
                .retract(&rho_theta, Perturbation::Left)
                .se3(),
            pose.retract(&theta_rho, Perturbation::Left)
        );
        let right = Se3RhoTheta::new(pose).retract(&rho_theta, Perturbation::Right);
        let exp = Se3::exp(&nalgebra::Vector6::from_row_slice(&theta_rho));
        let expected = pose.compose(&exp);
        assert!((right.translation() - expected.translation).norm() < 1e-14);
        let (a, b) = (
            right.se3().rotation.quaternion,
            expected.rotation.quaternion,
        );
        assert!((a.coords() - b.coords()).norm() < 1e-14);
        for side in [Perturbation::Left, Perturbation::Right] {
            let stepped = Se3RhoTheta::new(pose).retract(&rho_theta, side);
            let mut back = [0.0; 6];
            Se3RhoTheta::new(pose)
                .local(&stepped, side, &mut back)
                .unwrap();
            for (x, y) in back.iter().zip(&rho_theta) {
                assert!((x - y).abs() < 1e-13, "{side:?}: {back:?}");
            }
        }
    }
}
