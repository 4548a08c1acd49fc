//! The `slamjac` code generator: a factor traced by the symbolic engine
//! (crate `factor-symbolic`) becomes one module of a dependency-free crate of
//! straight-line residual-and-Jacobian kernels (`generated/` in the
//! workspace, or a crate of a user's own).
//!
//! The stages, in order:
//!
//! - [`host`]: the factor traced in a host solver's chart and layout
//!   ([`HostSpec`]), for a kernel beside its own;
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
//!   [`cpp`]: the same programs and schedules as a header-only C++17
//!   library ([`CppLibrary`]), with, for Ceres, each factor's ambient kernel
//!   ([`ambient`]) and its variables' own charts ([`chart`]);
//! - [`module`]: trace → lower → schedule → emit for one factor
//!   ([`GeneratedModule`]), what to generate ([`spec`]: [`KernelSpec`],
//!   [`Provenance`]);
//! - [`crate_writer`]: the crate's `src/` files ([`GeneratedCrate`]),
//!   written or compared with the disk;
//! - [`manifest`]: the kernel crate's `Cargo.toml` and the `src/lib.rs` it
//!   holds before the first generation;
//! - [`build_profile`]: whether the generator was built optimised, and the
//!   profile entries a user's workspace needs for that;
//! - [`error`]: what the generator refuses ([`CodegenError`]).
//!
//! Output is deterministic: no timestamps, no hash-map iteration order, so
//! regenerating from unchanged definitions is byte-identical, and a check
//! (`slamjac check` for `generated/`) fails when a crate is stale.
//!
//! # Kernels of your own factors
//!
//! A build script cannot see the types of the crate it builds, so a crate
//! defining factors generates their kernels from a binary that depends on
//! it into a dependency-free crate of its own tree, which it then depends
//! on through `#[factor(kernel = path)]`, behind a feature so the generator
//! builds without it. `slamjac init DIR` writes such a project (the factor
//! crate, its kernel crate with the [`manifest`] it needs, and a command
//! line built on `slamjac::cli` whose `generate` and `check` call this
//! crate); the workspace's `docs/guide/kernels.md` walks through it. The
//! steps underneath: a [`KernelSpec`] per factor (one line:
//! [`KernelSpec::of`]), a [`Provenance`] naming the commands, then
//! [`GeneratedCrate::generate`] and [`GeneratedCrate::write`] or
//! [`GeneratedCrate::check`]:
//!
//! ```no_run
//! use factor_codegen::{GeneratedCrate, KernelSpec, Provenance};
//! use factor_core::lie::Se3;
//! use factor_core::{Factor, Scalar};
//! use nalgebra::Vector3;
//!
//! /// A translation prior, `r = t − t̃`.
//! #[derive(Clone, Debug, Factor)]
//! #[factor(residual = offset_residual, dim = 3)]
//! // with the generated crate: #[cfg_attr(feature = "kernels", factor(
//! //     kernel = my_kernels::offset::offset,
//! //     regenerate = "cargo run -p my-cli --no-default-features -- generate"))]
//! pub struct Offset<S: Scalar = f64> {
//!     /// The measured translation `t̃`.
//!     pub measured: Vector3<S>,
//!     /// The pose whose translation is measured.
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
//!     "cargo run -p my-cli --no-default-features -- generate",
//!     "cargo run -p my-cli --no-default-features -- check",
//! );
//!
//! let kernels = GeneratedCrate::generate(PROVENANCE, &[KernelSpec::of::<Offset>()])?;
//! let dir = std::path::Path::new("my-kernels"); // the crate; sources go to `src/`
//! kernels.write(dir)?;
//! if let Err(stale) = kernels.check(dir) {
//!     panic!("stale: {stale:?}");
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! `slamjac::cli::Registry` does these steps for a command line's `generate`
//! and `check` (`slamjac init` writes such a project);
//! `examples/user-factor/` in the workspace is a complete example (crates
//! `user-factors`, `user-kernels` and the command line `user-cli`). Debug builds generate in seconds only with the symbolic
//! engine and the generator optimised ([`build_profile`]).

pub mod ambient;
pub mod build_profile;
pub mod chart;
pub mod compile;
pub mod cpp;
pub mod crate_writer;
pub mod emit;
pub mod error;
pub mod host;
pub mod ir;
pub mod kernel;
pub mod lower;
pub mod manifest;
pub mod module;
pub mod normal;
pub mod schedule;
pub mod spec;
mod tree;

pub use cpp::CppLibrary;
pub use crate_writer::GeneratedCrate;
pub use error::CodegenError;
pub use host::{HostSpec, HostTrace, trace_on_host};
pub use ir::OpCounts;
pub use kernel::{JacobianBlock, JacobianForm, SymbolicKernel, trace};
pub use module::{GeneratedModule, generate_module, generate_with, operation_counts};
pub use spec::{KernelSpec, Provenance};
