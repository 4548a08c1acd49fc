//! Lie groups generic over the scalar: unit quaternions, SO(2), SO(3), SE(3),
//! Sim(3), each implementing [`LieGroup`] (`identity`, `compose`, `inverse`, `act`,
//! `exp`, `log`, `adjoint`, the left and right Jacobians and their inverses,
//! `plus` and `minus` on either side; see [`group`] for the conventions and
//! for moving a Jacobian between perturbation sides).
//!
//! Conventions (as in `manif` and Sophus, and pinned by the specification):
//! - quaternions are stored `[x, y, z, w]`, Hamilton product, active rotation
//!   `R(q) v = q ⊗ [v, 0] ⊗ q⁻¹`; the quaternion `exp(ω) = [sin(θ/2) ω/θ, cos(θ/2)]`
//!   represents the rotation `Exp(ω)`;
//! - `hat(ω) b = ω × b`; `Exp` by Rodrigues; `Jl(ω) = I + (1−cos θ)/θ² [ω]× +
//!   (θ−sin θ)/θ³ [ω]×²` with `Exp(ω + δ) ≈ Exp(Jl(ω) δ) Exp(ω)`, and
//!   `Jr(ω) = Jl(−ω)` with `Exp(ω + δ) ≈ Exp(ω) Exp(Jr(ω) δ)`;
//! - SE(3) tangents are `[ω, ρ]`, rotation first; the adjoint of `T = (R, t)`
//!   is `[[R, 0], [t^ R, R]]` and `Jl([ω, ρ]) = [[Jl(ω), 0], [Q(ω, ρ), Jl(ω)]]`
//!   (see [`se3`]); [`Se3RhoTheta`] is the same group with the tangent
//!   ordered `[ρ, θ]`, the chart of apex-solver, manif and Sophus.
//!
//! Every small-angle case is a branch through [`crate::Scalar::select_lt`] on
//! `θ²` (never on `θ`, whose square root has no derivative at zero), taken
//! when `θ² <` [`SMALL_ANGLE_SQUARED`]; the series kept there are accurate to
//! machine precision below that threshold.

pub mod group;
pub mod quaternion;
pub mod se3;
pub mod se3_rho_theta;
pub mod sim3;
pub mod so2;
pub mod so3;
pub mod unit_quaternion;

pub use group::LieGroup;
pub use quaternion::Quaternion;
pub use se3::Se3;
pub use se3_rho_theta::{Se3RhoTheta, inverse_pose_block};
pub use sim3::Sim3;
pub use so2::So2;
pub use so3::So3;

/// Below this `θ²` the Taylor series of the angle functions are used. Their
/// first omitted terms are `O(θ⁶)`, i.e. below `1e-18` relative.
pub const SMALL_ANGLE_SQUARED: f64 = 1e-6;
