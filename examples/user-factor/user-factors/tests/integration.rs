//! The crate's integration tests, one binary (see `Cargo.toml`): each file
//! of `tests/` is a module here.

mod cpp;
mod generated;
mod local_coordinates;
mod manifold_factors;
mod retraction_rules;
mod sim3_group;
