//! The crate's integration tests, one binary (see `Cargo.toml`): each file
//! of `tests/` is a module here.

mod common;
mod doc000;
mod doc001;
mod fuzz;
mod notation;
mod real_latex;
mod round_trip;
