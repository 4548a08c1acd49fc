//! The crate's integration tests, one binary (see `Cargo.toml`): each file
//! of `tests/` is a module here.

mod agreement;
mod document_factors;
mod shapes;
mod users_factor;
