//! The crate's integration tests, one binary (see `Cargo.toml`): each file
//! of `tests/` is a module here.

mod common;
mod fuzz;
mod hostile;
mod plp_scene;
mod real_files;
mod round_trip;
mod streams_and_outputs;
mod synthetic;
