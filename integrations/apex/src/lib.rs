//! apex-solver as the estimator of `slamjac` factors.
//!
//! - [`adapter`]: [`ApexFactor`], one generic adapter that serves any factor
//!   derived with `#[derive(Factor)]` to apex-solver through its generated
//!   kernel ([`Kernels::Generated`]) or dual numbers ([`Kernels::Dual`]);
//! - [`options`]: how a problem is built (which factors, a robust loss)
//!   and why a build fails;
//! - [`builder`]: a problem of any derived factors (the user's own
//!   included) built with typed variables, noise models and robust losses;
//! - [`built`]: a built problem, with what the solve needs beside apex's
//!   problem (the linear solver, the damping, the clock of the passes);
//! - [`variables`]: values of this project's types as apex variables
//!   (through their `HostMap<Apex>`) and back;
//! - [`losses`]: robust losses that keep their digits (Cauchy's, whose
//!   apex-solver version rounds its cost to 0 for a large δ);
//! - [`problems`]: BAL, Bundler, g2o, EDGE3 and KITTI VO problems (crate
//!   `slam-data`) built as apex problems, with this project's factors or,
//!   for comparison, apex's own, and the optimized values written back;
//! - [`inverse_pose`]: a factor on a world-to-camera pose served on the
//!   body-to-world pose apex holds;
//! - [`solve`]: Levenberg–Marquardt with a report per iteration;
//! - [`timing`]: the time of the solver's linearization and evaluation passes.
//!
//! # Two nalgebras, no conflict
//!
//! apex-solver 1.5 is built on nalgebra 0.33, this project on 0.35. They
//! never meet: apex hands a factor plain `&[f64]` parameter slices and a
//! `faer` matrix, and the generated kernels (crate `factor-generated`, no
//! dependencies) take plain arrays. Only the initial values handed to
//! `Problem::add_variable` are apex's nalgebra `DVector`s, built here from
//! slices (`nalgebra-apex` is 0.33 under another name).
//!
//! # Conventions at the boundary
//!
//! apex retracts every manifold on the right, `SE3` with the tangent
//! `[ρ, θ]`. A factor is served in that chart whatever chart it was written
//! in (document 000's left-perturbed `[δω, δρ]` pose included): its apex
//! kernel (`<factor>_apex`, generated from the factor traced through apex's
//! retractions, [`factor_core::host`]) emits apex's Jacobian columns
//! directly, so nothing is permuted, and no adjoint is applied, at run time.

pub mod adapter;
pub mod builder;
pub mod built;
mod error;
pub mod inverse_pose;
pub mod losses;
pub mod options;
pub mod problems;
pub mod solve;
pub mod timing;
pub mod variables;

pub use adapter::{ApexFactor, Kernels, Rejections};
pub use error::AdapterError;

/// The guide's chapter on solver charts, whose Rust blocks run as this
/// crate's documentation tests (it needs apex-solver, which the main
/// workspace's tests do not build).
#[cfg(doctest)]
#[doc = include_str!("../../../docs/guide/solver-charts.md")]
pub struct SolverChartsGuide;

/// The front page, `README.md`, whose example defines a factor and solves
/// it through this crate: its Rust blocks run as this crate's
/// documentation tests too.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct Readme;
