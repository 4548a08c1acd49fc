//! Bundle adjustment's fast path: Levenberg–Marquardt on problems whose
//! landmarks (points, and any variable no two of whose factors share
//! another eliminated variable) are eliminated by a Schur complement, the
//! normal equations formed straight from the factors' generated fused
//! kernels, no Jacobian ever stored.
//!
//! - [`problem`]: a [`Problem`] of variables (held fixed or eliminated) and
//!   factors of any type derived with `#[derive(Factor)]`: those whose
//!   kernel has normal equations (`factor_core::WithKernel`, the kernel
//!   crate's `lanes` feature) in lane batches, any other one factor at a
//!   time through its kernel or by dual numbers
//!   ([`Problem::add_linearized`]); each with its noise model
//!   (`Σ ½ ρ(‖S r‖²)`: `noise`) and optionally its own robust loss;
//! - [`solve`]: the problem as a `factor_minimizer::Model` ([`lm`]),
//!   minimized by the one Levenberg–Marquardt loop of every solver path
//!   (`factor_minimizer::minimize`), reporting each iteration as a
//!   `factor_minimizer::Iteration`, so that `slamjac solve` prints the
//!   same lines whichever path solves;
//! - [`problems`]: BAL, Bundler, KITTI stereo VO, g2o and EDGE3 pose
//!   graphs and g2o's line, plane and point graphs built from `slam-data`
//!   with the factors of crate `slam-problems`, as the apex-solver path
//!   (`factor_apex::problems`) builds them, and the solution written back.
//!
//! # A factor of your own
//!
//! Any factor written with `#[derive(Factor)]` goes in: variables by their
//! stored scalars ([`Problem::add_variable`]), held fixed or eliminated,
//! factors with their noise model, linearized by dual numbers (or through
//! their generated kernel, [`Jacobians`]), then [`solve`] with the
//! `factor_minimizer` options every solver path takes ([`SolveOptions`]),
//! each iteration reported to the callback ([`Iteration`]); a variable's
//! value comes back typed through `factor_core::Storage::from_scalars`.
//!
//! ```
//! use factor_core::lie::{Se3, So3};
//! use factor_core::nalgebra::Vector3;
//! use factor_core::noise::Noise;
//! use factor_core::{Factor, Scalar, Storage};
//! use factor_schur::{Jacobians, Problem, SolveOptions, Verdict, solve};
//!
//! /// A world point `landmark` seen at `measured` in the frame of the
//! /// world-to-body pose `pose`.
//! #[derive(Debug, Clone, Factor)]
//! #[factor(residual = seen, dim = 3)]
//! pub struct Seen<S: Scalar = f64> {
//!     pub measured: Vector3<S>,
//!     #[variable(left)]
//!     pub pose: Se3<S>,
//!     #[variable]
//!     pub landmark: Vector3<S>,
//! }
//!
//! fn seen<S: Scalar>(f: &Seen<S>) -> Vector3<S> {
//!     f.pose.transform_point(&f.landmark) - f.measured
//! }
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let poses = [
//!     Se3::identity(),
//!     Se3::new(So3::exp(&Vector3::new(0.05, -0.1, 0.3)), Vector3::new(1.0, 0.2, -0.1)),
//! ];
//! let landmarks = [
//!     Vector3::new(2.0, 1.0, 5.0),
//!     Vector3::new(-1.5, 0.5, 4.0),
//!     Vector3::new(0.5, -2.0, 6.0),
//! ];
//! // The second pose and the landmarks start away from the truth.
//! let start = Se3::new(So3::exp(&Vector3::new(0.0, 0.0, 0.2)), Vector3::new(0.8, 0.0, 0.0));
//! let mut problem = Problem::new();
//! let pose_ids = [
//!     problem.add_variable(&poses[0].to_scalars()),
//!     problem.add_variable(&start.to_scalars()),
//! ];
//! problem.fix(pose_ids[0]); // the gauge
//! for (k, landmark) in landmarks.iter().enumerate() {
//!     let moved = landmark + Vector3::new(0.2, -0.1, 0.1 * k as f64);
//!     let id = problem.add_variable(&moved.to_scalars());
//!     problem.eliminate(id);
//!     for (pose, &pose_id) in poses.iter().zip(&pose_ids) {
//!         let factor = Seen {
//!             measured: pose.transform_point(landmark),
//!             pose: *pose,
//!             landmark: moved,
//!         };
//!         let noise = Noise::Sigma(0.01);
//!         problem.add_linearized(&factor, &[pose_id, id], &noise, None, Jacobians::Dual)?;
//!     }
//! }
//! let mut costs = Vec::new();
//! let outcome = solve(&mut problem, &SolveOptions::converged(50), |it| costs.push(it.cost))?;
//! assert!(matches!(outcome.verdict, Verdict::Converged(_)), "{:?}", outcome.verdict);
//! assert!(outcome.final_cost < 1e-20 && costs.len() == outcome.iterations);
//! let solved = Se3::<f64>::from_scalars(problem.value(pose_ids[1]));
//! assert!(poses[1].inverse().compose(&solved).log().norm() < 1e-9);
//! # Ok(())
//! # }
//! ```
//!
//! # How an iteration runs
//!
//! 1. **Linearization** (`passes`, `group`): the factors of each type,
//!    sorted by their eliminated variable and split among the threads at
//!    eliminated-variable boundaries, go through `factor_batch::normal` in
//!    chunks of 256 (inputs gathered from the current values into
//!    structure-of-arrays columns; 4 × `f64` lanes, the batch loop compiled
//!    for AVX-512 or AVX2 where the CPU has them). Each chunk's cost,
//!    gradient blocks and `JᵀwJ` blocks (`w` the robust IRLS weight) are
//!    added straight into the reduced blocks `U` (each thread its own
//!    copy), the landmarks' blocks `V` and the cross blocks `W`.
//! 2. **Elimination** (`schur`): `S = U + λD − Σ W V*⁻¹ Wᵀ`, per landmark,
//!    into `S` laid out as the lower triangle of a compressed-column matrix
//!    in a fill-reducing order fixed once (`structure`, from the
//!    factors' `layout`).
//! 3. **Reduced solve** (`reduced`): faer's sparse Cholesky (supernodal,
//!    its dense kernels), the symbolic analysis done once; a system of at
//!    most 40 unknowns by faer's dense Cholesky, where the sparse one's
//!    fixed costs dominate.
//! 4. **Back-substitution**, the model's decrease, the retraction of every
//!    variable by its own manifold, and the cost at the trial values (each
//!    factor validated: a degenerate configuration rejects the step).
//!
//! The lanes are 4 × `f64`: `f32` lanes are too coarse for a cost that
//! must match to 1e-6 relative, and on this project's machine 8 × `f64`
//! was no faster.

mod csc;
mod error;
mod group;
mod layout;
mod linearization;
pub mod lm;
mod noise;
mod ordering;
mod partition;
mod passes;
pub mod problem;
pub mod problems;
mod reduced;
mod robust;
mod schur;
mod sink;
mod structure;
mod whitened;

pub use error::SchurError;
pub use factor_minimizer::{Iteration, SolveOptions, Verdict};
pub use lm::{Outcome, Profile, SolveError, Solver, solve};
pub use problem::{Jacobians, Linearized, Problem, VariableId};
