//! The guide's chapters, Markdown files beside this one: with
//! `cargo test -p slamjac-guide`, every `rust` code block of them compiles
//! and runs as a doctest (blocks marked `no_run` compile only; lines
//! starting with `# ` are hidden in the rendered book).

/// `writing-a-factor.md`.
#[cfg(doctest)]
#[doc = include_str!("writing-a-factor.md")]
pub struct WritingAFactor;

/// `kernels.md`.
#[cfg(doctest)]
#[doc = include_str!("kernels.md")]
pub struct Kernels;
