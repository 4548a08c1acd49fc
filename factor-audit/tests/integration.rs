//! The crate's integration tests but `streaming.rs` (its own binary: its
//! counting global allocator must see no other test allocate), one binary
//! (see `Cargo.toml`): each other file of `tests/` is a module here.

mod audit;
mod corpus;
mod from_text;
mod from_text_fuzz;
mod guide;
mod reading_classes;
mod reading_reports;
mod textbook_notation;
