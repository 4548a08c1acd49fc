//! The `slamjac` code generator: a factor traced by the symbolic engine
//! (crate `factor-symbolic`) becomes one module of a dependency-free crate of
//! straight-line residual-and-Jacobian kernels (`generated/` in the
//! workspace, or a crate of a user's own).
//!
//! The stages, in order:
//!
//! - [`kernel`]: the factor traced ([`trace`]) into residual and Jacobian
//!   expressions, each block formed the cheapest exact way
//!   ([`SymbolicKernel`]);
//! - [`compile`]: expressions of the DAG compiled to a short straight-line
//!   program of binary instructions ([`ir`]);
//! - [`lower`]: the residual and every block lowered into one program;
//! - [`schedule`]: under which condition each instruction runs (always,
//!   when one of several Jacobian blocks is requested, or for one block
//!   only);
//! - [`emit`]: the module as tokens (`quote`), formatted by `prettyplease`;
//! - [`module`]: trace → lower → schedule → emit for one factor
//!   ([`GeneratedModule`]), what to generate ([`spec`]: [`KernelSpec`],
//!   [`Provenance`]);
//! - [`crate_writer`]: the crate's `src/` files, written ([`write_crate`]) or
//!   compared with the disk ([`check_crate`]).
//!
//! Output is deterministic: no timestamps, no hash-map iteration order, so
//! regenerating from unchanged definitions is byte-identical, and a check
//! (`slamjac check` for `generated/`) fails when a crate is stale.
//!
//! # Kernels of your own factors
//!
//! A build script cannot see the types of the crate it builds, so a crate
//! defining factors generates their kernels from one of its binaries (or
//! tests) into a dependency-free crate of its own tree, which it then
//! depends on through `#[factor(kernel = path)]`, behind a feature so the
//! generator builds without it. The steps: a [`KernelSpec`] per factor, a
//! [`Provenance`] naming the command, [`generate_with`], then
//! [`write_crate`] or [`check_crate`]:
//!
//! ```no_run
//! use factor_codegen::{self as codegen, KernelSpec, Provenance, trace};
//! use factor_core::lie::Se3;
//! use factor_core::{Factor, Scalar};
//! use nalgebra::Vector3;
//!
//! #[derive(Clone, Debug, Factor)]
//! #[factor(residual = offset_residual, dim = 3)]
//! // with the generated crate: #[cfg_attr(feature = "kernels",
//! //     factor(kernel = my_kernels::offset::offset))]
//! pub struct Offset<S: Scalar = f64> {
//!     pub measured: Vector3<S>,
//!     #[variable]
//!     pub pose: Se3<S>,
//! }
//!
//! pub fn offset_residual<S: Scalar>(f: &Offset<S>) -> Vector3<S> {
//!     f.pose.translation - f.measured
//! }
//!
//! const PROVENANCE: Provenance = Provenance::new(
//!     "Residual-and-Jacobian kernels of `my-factors`.",
//!     "cargo run -p my-factors --bin generate-kernels",
//!     "cargo run -p my-factors --bin generate-kernels -- --check",
//! );
//!
//! let spec = KernelSpec {
//!     name: <Offset as Factor>::NAME,
//!     source_type: "my_factors::Offset",
//!     document: "a translation prior",
//!     inputs: &[("measured", "[x, y, z]"), ("pose", "[qx, qy, qz, qw, tx, ty, tz]")],
//!     // Any value: only the type is traced.
//!     trace: || trace(&Offset { measured: Vector3::zeros(), pose: Se3::identity() }),
//! };
//! let modules = vec![codegen::generate_with(&spec, &PROVENANCE)];
//! let dir = std::path::Path::new("my-kernels"); // the crate; sources go to `src/`
//! codegen::write_crate(dir, &modules)?;
//! if let Err(stale) = codegen::check_crate(dir, &modules) {
//!     panic!("stale: {stale:?}");
//! }
//! # Ok::<(), std::io::Error>(())
//! ```
//!
//! `examples/user-factor/` in the workspace is a complete example (crates
//! `user-factors` and `user-kernels`); the README's "Embedding kernels of
//! your own factor" gives the commands.

pub mod compile;
pub mod crate_writer;
pub mod emit;
pub mod ir;
pub mod kernel;
pub mod lower;
pub mod module;
pub mod schedule;
pub mod spec;

pub use crate_writer::{check_crate, write_crate};
pub use ir::OpCounts;
pub use kernel::{JacobianBlock, JacobianForm, SymbolicKernel, trace};
pub use module::{GeneratedModule, generate_module, generate_with, operation_counts};
pub use spec::{KernelSpec, Provenance};
