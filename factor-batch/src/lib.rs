//! Batch linearization: many factors of one type at once, through the
//! factor's generated kernel on SIMD lanes.
//!
//! The inputs are structure-of-arrays [`Columns`]: one column per stored
//! scalar of the factor, in [`factor_core::Storage`] order
//! ([`factor_core::Factor::fields`] gives the layout; [`Columns::from_factors`]
//! builds them from factors), one row per factor. The outputs are columns
//! too:
//!
//! - [`linearize`] writes [`JacobianColumns`]: the residual and each free
//!   variable's Jacobian block (row-major entries, one column each);
//! - [`normal`] writes [`NormalColumns`]: the fused normal equations of
//!   each factor, its cost `½ w rᵀr`, the gradient blocks `Jᵢᵀ w r` and the
//!   upper triangle of `JᵀwJ` block by block, for a per-factor weight `w`.
//!
//! A variable held fixed has `None` for its blocks, which are then not
//! computed, nor the work only they need.
//!
//! ```
//! use factor_batch::{Columns, JacobianColumns, Options, linearize};
//! use factor_lanes::F64x4;
//! use slam_factors::PointReprojection;
//!
//! let factors: Vec<PointReprojection> = (0..10)
//!     .map(|_| factor_testing::samples::Sampler::new(1).point_reprojection())
//!     .collect();
//! let inputs = Columns::from_factors(&factors);
//! // The pose is held fixed: no pose block.
//! let mut outputs = JacobianColumns::new::<PointReprojection>(factors.len(), &[false, true]);
//! linearize::<PointReprojection, F64x4>(&inputs, &mut outputs, Options::default())?;
//! let point = outputs.blocks[1].as_ref().expect("free");
//! let dual = factors[9].linearize_dual()?;
//! assert!((point.column(2)[9] - dual.point[(0, 2)]).abs() < 1e-9 * dual.point.norm());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # How a batch reaches a factor's kernel
//!
//! `#[derive(Factor)]` with `kernel = path` implements
//! [`factor_core::WithKernel`], whose `Kernel` is the marker type of the
//! kernel's generated module; with the kernel crate's `lanes` feature that
//! marker implements [`factor_lanes::Kernel`] (and, for a kernel generated
//! with normal equations, [`factor_lanes::NormalKernel`]) for every number
//! type of the crate's `Real`: `f64`, `f32` and the lane types `F64x4`,
//! `F64x8`, `F32x8`. The trait hands the kernel its inputs and outputs as
//! fixed-size arrays, so the batch loop, instantiated per factor type and
//! lane type with the kernel inlined, keeps them in registers. Any derived
//! factor with a generated kernel works, a user's as well as the shipped
//! ones: the user's kernel crate declares the `lanes` feature (the crate
//! writer's sources expect it; see `factor_codegen::crate_writer`), and the
//! crate that calls the batch enables it.
//!
//! # Lanes, tail and threads
//!
//! The lane type `L` is a type parameter: groups of `L::LANES` rows are
//! loaded from the columns, evaluated in one call and stored; the rows left
//! over (fewer than `L::LANES`) run one at a time with `L::Scalar`, so any
//! number of rows works, none included. [`Threads::Rayon`] cuts the rows
//! into chunks of [`CHUNK`] and runs them on rayon's pool.
//!
//! Lanes compute each configuration exactly as the scalar kernel does, up
//! to the vectorised elementary functions (`sin`, `cos`, `atan2`, …; at
//! most 2 ulp from `std` in `f64` lanes, 3 in `f32`; see `factor-lanes`):
//! kernels built from `+ − × ÷ √` and `select_lt` alone give bit-for-bit
//! the scalar results.

#![deny(missing_docs)]

mod batch;
mod columns;
mod dispatch;
mod error;
mod outputs;
mod run;
mod threads;

pub use batch::{Options, linearize, normal};
pub use columns::Columns;
pub use dispatch::{Isa, detected};
pub use error::BatchError;
pub use outputs::{JacobianColumns, NormalColumns, pairs};
pub use threads::{CHUNK, Threads};
