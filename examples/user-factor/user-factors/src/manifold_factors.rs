//! Factors over this crate's own manifolds: a direction on S²
//! ([`crate::unit_vector`]) and similarity transforms ([`crate::sim3`]).

use factor_core::lie::So3;
use factor_core::{Factor, Scalar};
use nalgebra::{SVector, Vector2};

use crate::sim3::Sim3;
use crate::unit_vector::UnitVector3;

/// `B(m)ᵀ R d`: a sensor with orientation `R` (world to sensor) measures a
/// world-fixed direction `d` (gravity, a vanishing direction, a plane's
/// normal) as the unit vector `m` in its own frame; the residual is the
/// predicted direction's coordinates in the tangent plane of `m`, whose norm
/// is the sine of the angle error (GTSAM's `Unit3::error` has this form). It
/// is also zero at `R d = −m`, the largest angle error: start within a
/// hemisphere of the truth.
#[derive(Debug, Clone, Factor)]
#[factor(residual = direction_residual, dim = 2)]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = user_kernels::direction::direction,
        regenerate = "cargo run -p user-cli --no-default-features -- generate",
        hosts(apex)
    )
)]
pub struct Direction<S: Scalar = f64> {
    /// The measured direction `m`, in the sensor frame.
    pub measured: UnitVector3<S>,
    /// `R`, world to sensor, perturbed on the left: `R ← Exp(δω) R`.
    #[variable(left)]
    pub orientation: So3<S>,
    /// The direction `d`, in the world frame: `d ← d ⊞ δ` on S².
    #[variable]
    pub direction: UnitVector3<S>,
}

/// The residual of [`Direction`]. `B(m)` branches on the sign of `m_z`
/// through `Scalar::select_lt`, which the generated kernel keeps.
pub fn direction_residual<S: Scalar>(f: &Direction<S>) -> Vector2<S> {
    let predicted = f.orientation.rotate(&f.direction.vector());
    f.measured.basis().transpose() * predicted
}

/// `Log(S̃_ij⁻¹ S_i⁻¹ S_j)`: the Sim(3) "between" factor of monocular SLAM
/// loop closures, zero when the similarity transforms agree with the
/// measurement (rotation, translation and log-scale of the relative
/// transform).
#[derive(Debug, Clone, Factor)]
#[factor(residual = relative_sim3_residual, dim = 7)]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = user_kernels::relative_sim3::relative_sim3,
        regenerate = "cargo run -p user-cli --no-default-features -- generate",
        hosts(apex)
    )
)]
pub struct RelativeSim3<S: Scalar = f64> {
    /// The measured relative transform `S̃_ij`.
    pub measured: Sim3<S>,
    /// `S_i`, perturbed on the left: `S_i ← Exp(δξ) S_i`.
    #[variable(left)]
    pub sim_i: Sim3<S>,
    /// `S_j`, perturbed on the left.
    #[variable(left)]
    pub sim_j: Sim3<S>,
}

/// The residual of [`RelativeSim3`], tangent order `[ω, ρ, σ]`.
pub fn relative_sim3_residual<S: Scalar>(f: &RelativeSim3<S>) -> SVector<S, 7> {
    let predicted = f.sim_i.inverse().compose(&f.sim_j);
    f.measured.inverse().compose(&predicted).log()
}
