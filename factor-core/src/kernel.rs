//! The link from a factor to its generated kernel, for evaluators that run
//! the kernel on number types of their own.

use crate::factor::Factor;

/// A factor whose linearization goes through a generated kernel
/// (`#[factor(kernel = path)]`); `#[derive(Factor)]` implements it.
///
/// [`WithKernel::Kernel`] is the marker type `Kernel` of the kernel's module.
/// With the kernel crate's `lanes` feature the marker implements
/// `factor_lanes::Kernel` over every number type of the crate's `Real` (the
/// SIMD lane types of `factor-lanes` included), through which the batch
/// evaluators of `factor-batch` linearize many factors of the type at once
/// from structure-of-arrays columns. This crate names the marker only, so
/// it depends on neither.
pub trait WithKernel: Factor {
    /// The kernel module's marker type.
    type Kernel;
}
