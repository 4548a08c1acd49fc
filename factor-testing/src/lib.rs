//! Test helpers for factor authors, in the spirit of GTSAM's
//! `EXPECT_CORRECT_FACTOR_JACOBIANS`: one line in a test checks a factor.
//!
//! - [`assert_correct_jacobians`] ([`numeric`]): the dual-number Jacobians
//!   agree with numerical differentiation on the variables' manifolds;
//! - [`assert_generated_matches_dual`] ([`generated`]): the generated kernel
//!   agrees with dual numbers to rounding;
//! - [`host`]: a factor's Jacobians in a host solver's chart against
//!   central differences through the host's retraction;
//! - [`local`]: a manifold's `local` against the retraction it inverts;
//! - [`mod@reference`]: a factor's residual and Jacobians in double-double
//!   arithmetic, to measure the accuracy of an `f64` evaluation;
//! - [`seeding`]: the seeded one-pass dual linearization against the
//!   same derivative through each variable's retraction, column by column;
//! - [`near_degenerate`]: configurations a given distance from a factor's
//!   degeneracy;
//! - [`samples`]: seeded, well-conditioned configurations of the shipped
//!   factors (and the poses, rotations and vectors they are built from);
//! - [`branch_points`]: configurations straddling the kernels' branch
//!   points (the plane factor's two selects);
//! - [`cpp`]: a kernel crate's generated C++ compiled and run against the
//!   Rust kernels, dual numbers and the variables' charts.

pub mod branch_points;
pub mod cpp;
#[cfg(feature = "bench")]
pub mod cpu_time;
pub mod generated;
pub mod host;
pub mod local;
pub mod near_degenerate;
pub mod numeric;
pub mod reference;
#[cfg(feature = "bench")]
pub mod rounds;
pub mod samples;
pub mod seeding;

pub use generated::{GENERATED_TOLERANCE, assert_generated_matches_dual, check_generated};
pub use numeric::{DEFAULT_TOLERANCE, JacobianCheck, assert_correct_jacobians, check_jacobians};
