//! apex-solver as the estimator of `slamjac` factors.
//!
//! - [`adapter`]: [`ApexFactor`], one generic adapter that serves any factor
//!   derived with `#[derive(Factor)]` to apex-solver through its generated
//!   kernel ([`Kernels::Generated`]) or dual numbers ([`Kernels::Dual`]);
//! - [`variables`]: which apex manifold each factor variable is and how
//!   apex's parameter blocks map to the kernels' input arrays;
//! - [`losses`]: robust losses that keep their digits (Cauchy's, whose
//!   apex-solver version rounds its cost to 0 for a large δ);
//! - [`problems`]: BAL, Bundler, g2o, EDGE3 and KITTI VO problems (crate
//!   `slam-data`) built as apex problems, with this project's factors or,
//!   for comparison, apex's own, and the optimized values written back;
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
//! apex retracts `SE3` on the right with the tangent `[ρ, θ]`. The factors
//! served here declare their poses `#[variable(right)] Se3RhoTheta<S>`, whose
//! tangent is exactly that, so their generated kernels emit apex's Jacobian
//! columns: nothing is permuted, and no adjoint is applied, at run time. A
//! factor whose poses are in another chart is refused by [`ApexFactor::new`].

pub mod adapter;
pub mod losses;
pub mod problems;
pub mod solve;
pub mod timing;
pub mod variables;

pub use adapter::{ApexFactor, Kernels, Rejections};

/// A factor that [`ApexFactor`] cannot serve.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum AdapterError {
    /// A variable has no apex-solver counterpart with the same tangent.
    #[error(
        "{factor}: variable `{variable}` ({type_name}, tangent {tangent}) has no apex-solver \
         counterpart with the same tangent: declare poses `#[variable(right)] Se3RhoTheta<S>` \
         (apex's SE3 chart, [ρ, θ] on the right) and vectors additive"
    )]
    Unsupported {
        /// The factor's name.
        factor: &'static str,
        /// The variable's name.
        variable: &'static str,
        /// Its type as written.
        type_name: &'static str,
        /// Its tangent in words.
        tangent: &'static str,
    },
    /// The factor is larger than the adapter's stack buffers.
    #[error(
        "{factor}: more than {} stored scalars, {} variables or {} Jacobian entries",
        adapter::MAX_SCALARS,
        adapter::MAX_VARIABLES,
        adapter::MAX_JACOBIAN
    )]
    TooLarge {
        /// The factor's name.
        factor: &'static str,
    },
}
