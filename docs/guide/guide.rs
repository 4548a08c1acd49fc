//! The guide's chapters, Markdown files beside this one: with
//! `cargo test -p slamjac-guide`, every `rust` code block of them compiles
//! and runs as a doctest (blocks marked `no_run` compile only; lines
//! starting with `# ` are hidden in the rendered book). The chapter on
//! solver charts and the front page (`README.md`, whose example solves)
//! need apex-solver: their blocks run as the documentation tests of
//! `factor-apex` (`integrations/apex`).

/// `writing-a-factor.md`.
#[cfg(doctest)]
#[doc = include_str!("writing-a-factor.md")]
pub struct WritingAFactor;

/// `kernels.md`.
#[cfg(doctest)]
#[doc = include_str!("kernels.md")]
pub struct Kernels;

/// `generated-kernels.md`.
#[cfg(doctest)]
#[doc = include_str!("generated-kernels.md")]
pub struct GeneratedKernels;

/// `cpp-and-ceres.md`.
#[cfg(doctest)]
#[doc = include_str!("cpp-and-ceres.md")]
pub struct CppAndCeres;

/// `point-line-plane.md`.
#[cfg(doctest)]
#[doc = include_str!("point-line-plane.md")]
pub struct PointLinePlane;
