//! The one Levenberg–Marquardt minimizer of every slamjac solver.
//!
//! As in Ceres' `internal/ceres`, the minimizer is one loop and the linear
//! solver a strategy: a problem implements [`Model`] (linearize at the
//! current values, solve the damped normal equations, evaluate a trial
//! step, accept it) and [`minimize`] runs Levenberg–Marquardt over it with
//! the same damping, stopping criteria, verdicts and iteration reports
//! whatever the problem:
//!
//! - crate `factor-schur`: landmarks eliminated by a Schur complement, the
//!   reduced system by sparse or dense Cholesky (bundle adjustment, pose
//!   graphs, g2o's graphs, problem files);
//! - crate `factor-tracking`: one pose against a fixed map, a dense 6 × 6
//!   system per frame.
//!
//! apex-solver's own loop (crate `factor-apex`, `--solver apex`) reports
//! in the same vocabulary ([`SolveOptions`], [`Iteration`], [`Verdict`],
//! [`Criterion`], [`Damping`]) so that a command line prints either alike.
//!
//! ```
//! use std::time::Instant;
//!
//! use factor_minimizer::{Damped, Damping, Linearization, Model, Prediction, SolveOptions, Trial, minimize};
//!
//! /// `½ (x − 3)²` over one scalar: `H = 1`, `g = x − 3`.
//! struct Parabola { x: f64, step: f64 }
//! impl Model for Parabola {
//!     fn linearize(&mut self, cost: f64, bounds: (f64, f64)) -> Linearization {
//!         Linearization::read([(1.0, self.x - 3.0)], cost, bounds)
//!     }
//!     fn solve_damped(&mut self, damped: Damped) -> Option<Prediction> {
//!         let (h, g) = (1.0, self.x - 3.0);
//!         self.step = -g / (h + damped.of(h));
//!         Some(Prediction { g_delta: g * self.step, h_delta: h * self.step * self.step })
//!     }
//!     fn evaluate_step(&mut self) -> Trial {
//!         Trial::Cost(0.5 * (self.x + self.step - 3.0).powi(2))
//!     }
//!     fn accept(&mut self) { self.x += self.step; }
//!     fn step_norm(&self) -> f64 { self.step.abs() }
//!     fn parameter_norm(&self) -> f64 { self.x.abs() }
//! }
//!
//! let mut parabola = Parabola { x: 0.0, step: 0.0 };
//! let options = SolveOptions::default();
//! let minimized = minimize(&mut parabola, 4.5, Instant::now(), Damping::Diagonal, &options, |_| {});
//! assert!(minimized.verdict.is_converged(), "{}", minimized.verdict);
//! assert!((parabola.x - 3.0).abs() < 1e-9);
//! ```

#![deny(missing_docs)]

mod levenberg_marquardt;
mod model;
mod options;
mod report;

pub use levenberg_marquardt::{Minimized, minimize};
pub use model::{Damped, Linearization, Model, Prediction, Trial};
pub use options::{Damping, SolveOptions};
pub use report::{Criterion, Iteration, Verdict};
