//! The crate's integration tests, one binary (see `Cargo.toml`): each file
//! of `tests/` is a module here.

mod geometry_constructors;
mod lie_group_trait;
mod lie_properties;
mod local_coordinates;
mod plucker_host_map;
mod seeding;
