//! The package's integration tests but `solve.rs` and `track.rs` (feature
//! `solve`, their own binaries), one binary (see `Cargo.toml`): each other
//! file of `tests/` is a module here.

mod architecture;
mod cli;
mod codegen;
mod common;
mod cpp_kernels;
mod derive;
mod files_and_messages;
mod hostile_input;
mod snapshots;
