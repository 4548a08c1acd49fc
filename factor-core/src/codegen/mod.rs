//! Code emission: a traced factor ([`crate::symbolic::trace`]) becomes one
//! module of the generated crate `factor-generated` (`generated/` in the
//! workspace).
//!
//! - [`spec`]: what is generated, per factor ([`KernelSpec`],
//!   [`document_kernels`]);
//! - [`schedule`]: lowering to one program and deciding under which
//!   condition each instruction runs (always, when one of several Jacobian
//!   blocks is requested, or for one block only);
//! - [`emit`]: the module as tokens (`quote`), formatted by `prettyplease`;
//! - [`module`]: trace → lower → schedule → emit for one factor
//!   ([`GeneratedModule`]);
//! - [`crate_writer`]: the crate's `src/` files, written ([`write_crate`]) or
//!   compared with the disk ([`check_crate`]).
//!
//! Output is deterministic: no timestamps, no hash-map iteration order, so
//! regenerating from unchanged definitions is byte-identical, and
//! `slamjac check` (CI) fails when `generated/` is stale.
//!
//! # Bootstrapping
//!
//! `factor-core` uses the generated kernels (the derive's `kernel = path`)
//! only with its default cargo feature `kernels`. When `generated/` is stale
//! in a way that does not compile (a factor gained a field, say), or while
//! it is being rewritten, regenerate without it:
//!
//! ```sh
//! cargo run --release --no-default-features -- generate
//! ```
//!
//! which builds neither the generated crate nor anything that calls it.

pub mod crate_writer;
pub mod emit;
pub mod module;
pub mod schedule;
pub mod spec;

pub use crate_writer::{check_crate, write_crate};
pub use module::{GeneratedModule, generate, generate_all, generate_module, operation_counts};
pub use spec::{KernelSpec, document_kernels};
