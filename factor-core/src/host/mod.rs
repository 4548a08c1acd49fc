//! Host charts: a factor served to a solver in the solver's own chart and
//! parameter layout.
//!
//! A factor is written once, with each variable in the type and on the
//! perturbation side its derivation uses (document 000's camera pose is a
//! left-perturbed [`Se3`](crate::lie::Se3) with the tangent `[δω, δρ]`). A
//! host solver keeps its variables in its own manifolds (apex-solver: `SE3`
//! as `[tx, ty, tz, qw, qx, qy, qz]`, retracted on the right with the tangent
//! `[ρ, θ]`; `SO3`, `SO2`, `Rn`) and wants each Jacobian column in its
//! tangent. Three pieces connect the two, none of them a conversion at run
//! time:
//!
//! - [`Host`] describes a solver: its manifolds ([`HostManifold`]) with their
//!   parameter layouts, tangent orders and retractions. [`Apex`] is
//!   apex-solver's; a second solver with a fixed set of manifolds is a new
//!   description, not a new generator. (Ceres, whose manifolds are its
//!   user's, takes the factor's own charts instead: crate `factor-codegen`'s
//!   C++ emission generates them from each variable type's
//!   [`crate::Manifold`], [`crate::Factor::chart_over`].)
//! - [`HostMap<H>`] says, per variable type, which host variables it is
//!   served as ([`HostPart`]s, in order) and how their parameters give the
//!   type's stored scalars ([`crate::Storage`]). It is implemented here for
//!   every type this crate ships; a user implements it for a manifold of
//!   their own. The orthonormal line `(U, W)` is `SO3 × SO2`, and so is the
//!   Plücker line `[n, v]` (its orthonormal chart: a solve keeps it on the
//!   Klein quadric), the free line `[q_WL, d_L]` is `SO3 × Rn(1)`.
//! - `#[derive(Factor)]` implements [`HostFactor<H>`] for every host whose
//!   mappings all the factor's variable types have; a variable type without
//!   one makes the factor not a `HostFactor<H>`, a compile-time error at the
//!   use that names the type and this trait.
//!
//! The residual in a host's chart is [`host_residual`]: every host variable
//! retracted to first order in the host's chart, mapped to the variable's
//! stored scalars, and the factor's own residual evaluated there
//! ([`Factor::residual_over`]). Its derivative at `δ = 0` is the Jacobian in
//! the host's tangent: dual numbers evaluate it ([`linearize_host_dual`]) and
//! the code generator traces it into a kernel that reads the host's
//! parameter slices and writes its column-major blocks
//! ([`HostKernel`], [`linearize_host`]). The chart a factor was written in
//! does not matter: a left-perturbed pose gets its Jacobian in apex's right
//! `[ρ, θ]` chart exactly, with no adjoint at run time.
//!
//! # Kernel inputs in a host's layout
//!
//! The generated function `<factor>_<host>` takes one array per input, in
//! the factor's field order: a constant field is its stored scalars; a
//! variable is one array per host part, that host variable's parameters in
//! the host's layout ([`HostLayout`]). Its blocks are one per host part,
//! **column-major** (residual rows × the part's tangent columns, column
//! after column), so that the blocks of consecutive parts tile a
//! column-major Jacobian whose columns are the parts' tangents in order, as
//! apex-solver's factors write it. Its entry for solvers,
//! `<factor>_<host>_host` ([`HostKernel::host_kernel`]), takes what a
//! solver holds: the factor's stored scalars and one slice per host part,
//! and writes that whole Jacobian.

pub mod apex;
mod layout;
mod maps;
mod residual;

use crate::factor::Factor;
use crate::scalar::Scalar;
use crate::storage::Layout;

pub use apex::{Apex, ApexManifold};
pub use layout::{HostInput, HostLayout, HostVariable};
pub use residual::{
    MAX_STORED, MAX_VARIABLE_PARAMETERS, dual_pass, host_parameters, host_residual, inputs_of,
    linearize_host, linearize_host_dual, linearize_host_validated, variables_from_host,
};

/// A host solver's description: what [`HostMap`], the code generator and
/// the adapters need to serve factors to it.
pub trait Host: 'static {
    /// A short snake-case name: generated host kernels are named
    /// `<factor>_<NAME>`.
    const NAME: &'static str;
    /// The solver, in words (`apex-solver 1.5`).
    const SOLVER: &'static str;
    /// The host's manifolds in words, for error messages.
    const MANIFOLDS: &'static str;
    /// The host's manifold kinds.
    type Manifold: HostManifold;
}

/// One manifold of a host solver: its parameter layout, tangent and
/// retraction, as the solver defines them.
pub trait HostManifold: Copy + Eq + std::fmt::Debug + std::fmt::Display + 'static {
    /// The number of parameters the solver stores.
    fn parameters(self) -> usize;
    /// The tangent dimension.
    fn dof(self) -> usize;
    /// The parameters' names in the solver's order.
    fn parameter_layout(self) -> Layout;
    /// The retraction and the tangent's column order, in words.
    fn tangent_description(self) -> &'static str;
    /// The solver's retraction `x ⊞ δ` to first order at `δ = 0`, written
    /// into `out` (the same number of parameters): traced by the code
    /// generator and evaluated on dual numbers, so it follows the rules of
    /// [`crate::Manifold`] (generic, no comparison but `select_lt`).
    fn retract_first_order<T: Scalar>(self, params: &[T], delta: &[T], out: &mut [T]);
    /// The solver's exact retraction (tests compare it with the solver's own
    /// implementation and step central differences with it).
    fn retract(self, params: &[f64], delta: &[f64], out: &mut [f64]);
}

/// One host variable a variable is served as: a name for the part (empty
/// for a variable served as one host variable) and its manifold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HostPart<M> {
    /// The part's name (`u`, `w` of an orthonormal line); empty when the
    /// variable is one host variable.
    pub name: &'static str,
    /// The host manifold.
    pub manifold: M,
}

impl<M: HostManifold> HostPart<M> {
    /// The whole variable as one host variable.
    pub const fn whole(manifold: M) -> Self {
        HostPart { name: "", manifold }
    }

    /// A named part.
    pub const fn named(name: &'static str, manifold: M) -> Self {
        HostPart { name, manifold }
    }
}

/// How a variable type is served by host `H`: as which host variables, and
/// how their parameters give its stored scalars.
///
/// Implement it for a manifold of your own to serve factors over it to
/// `H`. The rules:
///
/// - [`HostMap::PARTS`] lists the host variables in order; their tangents,
///   stacked, are the variable's columns in the host.
/// - [`HostMap::stored_from_host`] maps the parts' parameters (concatenated,
///   in the host's layouts) to the type's stored scalars
///   ([`crate::Storage`]). It is traced and differentiated, so it follows the
///   rules of [`crate::Manifold`]'s retractions (generic over the scalar, no
///   comparison but `select_lt`). It must be a local diffeomorphism onto the
///   type's manifold where the host keeps its variables: the Jacobian in the
///   host's chart is the type's Jacobian through it.
/// - [`HostMap::host_from_stored`] is its inverse on values (initial values
///   and read-back).
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no mapping onto the manifolds of the host `{H}`",
    label = "a variable of this type cannot be served to `{H}`",
    note = "implement `factor_core::host::HostMap<{H}>` for it: which of the host's manifolds \
            it is served as (for `Apex`, apex-solver's SE3, SO3, SO2 and Rn(n)) and how their \
            parameters give its stored scalars (see the documentation of `factor_core::host`)"
)]
pub trait HostMap<H: Host> {
    /// The host variables, in order.
    const PARTS: &'static [HostPart<H::Manifold>];

    /// The stored scalars of the value whose host parameters are `host` (the
    /// parts' parameters concatenated in order).
    fn stored_from_host<T: Scalar>(host: &[T], stored: &mut [T]);

    /// The host parameters (the parts' concatenated) of the value stored as
    /// `stored`.
    fn host_from_stored(stored: &[f64], host: &mut [f64]);
}

/// A factor whose variables all have a mapping onto host `H`
/// (`#[derive(Factor)]` implements it): the per-variable dispatch to the
/// variables' [`HostMap`]s.
pub trait HostFactor<H: Host>: Factor {
    /// Variable `variable`'s type (at `f64`), to check what a solver's
    /// problem connects the factor to.
    fn variable_type(variable: usize) -> std::any::TypeId;

    /// Variable `variable`'s host parts ([`HostMap::PARTS`]).
    fn host_parts(variable: usize) -> &'static [HostPart<H::Manifold>];

    /// Variable `variable`'s [`HostMap::stored_from_host`].
    fn stored_from_host<T: Scalar>(variable: usize, host: &[T], stored: &mut [T]);

    /// Variable `variable`'s [`HostMap::host_from_stored`].
    fn host_from_stored(variable: usize, stored: &[f64], host: &mut [f64]);

    /// [`linearize_host_dual`]: [`dual_pass`] with the factor's tangent
    /// dimension as the dual numbers' width (the derive knows it as a
    /// constant; generic code cannot name it).
    ///
    /// # Errors
    ///
    /// As [`linearize_host`].
    fn linearize_host_dual_pass(
        layout: &HostLayout<H::Manifold>,
        template: &[f64],
        parts: &[&[f64]],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) -> Result<(), crate::FactorError>;
}

/// A factor with a kernel generated for host `H`
/// (`#[factor(kernel = path, hosts(…))]`): residual and column-major
/// Jacobian straight from the host's parameter slices.
pub trait HostKernel<H: Host>: HostFactor<H> {
    /// The generated function, for reports.
    const HOST_KERNEL: &'static str;

    /// The generated kernel's host entry (`<factor>_<host>_host`): the
    /// factor's stored scalars `stored` (its constants are read, its
    /// variables' are not), one parameter slice per host part in the host's
    /// layout, the residual, and the column-major Jacobian (`rows × Σ dof`,
    /// the parts' columns in order) or `None`. Returns `false`, computing
    /// nothing, when a length differs from what the kernel was generated
    /// for. No validation.
    fn host_kernel(
        stored: &[f64],
        parts: &[&[f64]],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) -> bool;

    /// Whether the kernel's outputs `residual` and `jacobian`, just computed
    /// from `stored` and `parts` by [`HostKernel::host_kernel`], come from
    /// the factor's current definition. `Ok` by default; in a debug build of
    /// the factor's crate the derive compares the first calls with dual
    /// numbers in the same chart ([`crate::kernel`]).
    ///
    /// # Errors
    ///
    /// [`FactorError::StaleKernel`](crate::FactorError::StaleKernel).
    fn check_host_kernel(
        stored: &[f64],
        parts: &[&[f64]],
        residual: &[f64],
        jacobian: Option<&[f64]>,
    ) -> Result<(), crate::FactorError> {
        let _ = (stored, parts, residual, jacobian);
        Ok(())
    }
}
