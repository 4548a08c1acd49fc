//! The package's integration tests but `solve.rs` (feature `solve`, its own
//! binary), one binary (see `Cargo.toml`): each other file of `tests/` is a
//! module here.

mod architecture;
mod cli;
mod codegen;
mod common;
mod derive;
mod files_and_messages;
mod hostile_input;
mod snapshots;
