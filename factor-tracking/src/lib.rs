//! Pose-only Levenberg–Marquardt: one 6-dof camera pose against a fixed
//! map, the problem a visual tracking front-end solves at every frame.
//!
//! A [`PoseProblem`] holds a frame's observations: factors of any derived
//! types (`#[derive(Factor)]`, the shipped ones of `slam-factors` or a
//! user's), each with exactly one `Se3` variable — the pose — and its other
//! variables (points, lines, planes) held at the values the factor
//! carries: the map. Each observation's residual is whitened by its
//! noise model, [`Noise`] (`½ ‖S r‖²`; the one model of every solver
//! path, `factor_core::noise::Noise`). [`PoseProblem::solve`] then minimises the
//! sum from an initial pose (in tracking, the previous frame's):
//!
//! - each linearization calls every factor's generated kernel through
//!   [`Factor::linearize_stored_into`](factor_core::Factor::linearize_stored_into)
//!   with the pose's Jacobian block only requested (the landmarks' blocks,
//!   and the work only they need, are skipped; a factor without a kernel
//!   goes through dual numbers), no allocation per factor;
//! - the whitened rows are summed into the dense 6 × 6 Gauss–Newton matrix
//!   `H = Σ J̃ᵀJ̃` and gradient `g = Σ J̃ᵀr̃` ([`Normal`]);
//! - the one Levenberg–Marquardt of every slamjac solver
//!   (`factor_minimizer::minimize`: its damping, stopping criteria and
//!   verdicts) steps it: each step solves `(H + λ diag(H)) δ = −g` by
//!   Cholesky and retracts the pose on its factors' perturbation side (for
//!   the documents' `Se3`, the left: `T ← Exp(δ) T`); a step that leaves an
//!   observation undefined is rejected. Observations undefined at the
//!   initial pose itself (a landmark behind the previous frame's camera)
//!   are deferred: the pose is solved without them, then with all of them
//!   from there ([`PoseSolution::deferred`]).
//!
//! A pose the observations do not determine (fewer than six independent
//! residual directions) is refused at the start ([`PoseError::Underdetermined`]),
//! never solved into a NaN.
//!
//! ```
//! use factor_core::geometry::Intrinsics;
//! use factor_core::lie::Se3;
//! use factor_core::nalgebra::{Vector2, Vector3, Vector6};
//! use factor_tracking::{Noise, Options, PoseProblem};
//! use slam_factors::PointReprojection;
//!
//! // A camera 0.1 m and 0.05 rad away from the one that took the pixels.
//! let truth = Se3::exp(&Vector6::new(0.02, -0.03, 0.01, 0.1, -0.2, 0.05));
//! let initial = Se3::exp(&Vector6::new(0.05, 0.0, 0.0, 0.1, 0.0, 0.0)).compose(&truth);
//! let intrinsics = Intrinsics::new(400.0, 400.0, 320.0, 240.0);
//! let mut problem = PoseProblem::new();
//! for k in 0..12 {
//!     let point = Vector3::new(f64::from(k % 4) - 1.5, f64::from(k / 4) - 1.0, 5.0 + f64::from(k % 3));
//!     let seen = truth.transform_point(&point);
//!     let observed = Vector2::new(400.0 * seen.x / seen.z + 320.0, 400.0 * seen.y / seen.z + 240.0);
//!     let factor = PointReprojection { intrinsics, observed, pose: initial, point };
//!     problem.add(&factor, &Noise::Sigma(1.0))?;
//! }
//! let solution = problem.solve(&initial, &Options::default())?;
//! assert!(solution.verdict.is_converged(), "{:?}", solution.verdict);
//! assert!(solution.pose.compose(&truth.inverse()).log().norm() < 1e-9);
//! # Ok::<(), factor_tracking::PoseError>(())
//! ```

#![deny(missing_docs)]

mod error;
mod model;
mod observations;
mod solver;

pub use error::PoseError;
pub use factor_core::noise::Noise;
pub use factor_minimizer::{SolveOptions, Verdict};
pub use observations::Normal;
pub use solver::{Options, PoseProblem, PoseSolution};
