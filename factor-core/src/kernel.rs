//! The link from a factor to its generated kernel, for evaluators that run
//! the kernel on number types of their own, and the check that a kernel is
//! current.
//!
//! # A stale kernel never runs unnoticed
//!
//! A factor with `#[factor(kernel = path)]` linearizes through a kernel that
//! was generated from an earlier state of its definition. Three checks, from
//! the cheapest, keep that state from drifting silently:
//!
//! 1. **Layout, at compile time.** The derive compares the kernel module's
//!    `SHAPE` with the factor's fields, residual dimension and tangents: a
//!    field that gained a scalar or a changed tangent fails the build at the
//!    kernel's path, naming the `regenerate` command.
//! 2. **Values, at first use, in debug builds.** A change that keeps the
//!    layout (a sign in the residual, a helper it calls, a variable's
//!    retraction) still compiles, so `#[derive(Factor)]` compares the
//!    kernel with dual numbers through the current definition on the first
//!    [`DEBUG_CHECKS`] linearizations of each factor type in a process,
//!    and each kernel in a solver's chart (`hosts(…)`) with dual numbers in
//!    that chart on its first [`DEBUG_CHECKS`] calls
//!    ([`host_kernel_mismatch`]; `#[cfg(debug_assertions)]`, in the crate
//!    that defines the factor).
//!    When an output differs by more than [`STALE_TOLERANCE`]
//!    ([`kernel_mismatch`]) the linearization returns
//!    [`FactorError::StaleKernel`] naming the output, both values and the
//!    `regenerate` command (an error like any other: a test fails with it,
//!    the command line prints it on one line and exits 1), and so does
//!    every later linearization of that factor type in the process. Rounding
//!    separates the two by about 1e-13 relative; a changed definition by
//!    the size of the change. Any run of the user's code in a debug build
//!    (a test, `cargo run`, the command line's `eval` or `solve`) catches the edit,
//!    though the user wrote no test for it. Release builds compile none of
//!    it: no atomic counter, no branch, no dual numbers.
//! 3. **Text, in CI.** The generator's `check` regenerates every kernel and
//!    compares the sources (`slamjac check`, or a user's `check`): every
//!    change of the definitions, also one invisible at the configurations
//!    a debug run happened to see.
//!
//! Why not a fingerprint of the definition stored in the kernel: the derive
//! sees only the struct, not the residual function's body, the helpers it
//! calls or the variables' retractions, which all shape the kernel; hashing
//! the trace instead would put the symbolic engine into every factor
//! crate's build; and values of the residual at a fixed probe point written
//! into the module would make the generated text depend on the platform's
//! math library (so `check` would differ between machines), while a probe
//! point valid for any user's manifold cannot be made without user data.
//! The same lack of a configuration rules out a test emitted by the derive.
//! Dual numbers at the configurations the program actually linearizes need
//! none of that.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};

use crate::factor::{DynLinearization, Factor, FactorError};
use crate::host::{Host, HostFactor, HostLayout, linearize_host_dual};

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

/// How many linearizations of each factor type a debug build compares
/// with dual numbers (see the module documentation).
pub const DEBUG_CHECKS: u32 = 4;

/// How far a kernel's output may be from dual numbers': an entry differs
/// when `|kernel − dual| > STALE_TOLERANCE · max(1, m)`, `m` the largest
/// `|dual|` of its array (the residual, or one Jacobian block). Both are
/// exact to rounding, about 1e-13 relative apart, so an entry beyond this
/// tolerance comes from a different definition.
pub const STALE_TOLERANCE: f64 = 1e-6;

/// An output where a kernel and dual numbers disagree.
#[derive(Debug, Clone, PartialEq)]
pub struct KernelMismatch {
    /// `residual[1]`, or `` Jacobian w.r.t. `pose` (row 0, column 2) ``.
    pub output: String,
    /// The kernel's value.
    pub kernel: f64,
    /// Dual numbers' value.
    pub dual: f64,
}

impl std::fmt::Display for KernelMismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "its {} is {} where dual numbers through the current definition give {}",
            self.output, self.kernel, self.dual
        )
    }
}

/// The first entry where `kernel` and `dual` (two linearizations of factor
/// `F` at one configuration) differ beyond [`STALE_TOLERANCE`], residual
/// first, then the blocks in variable order. Entries the kernel leaves
/// non-finite are not compared (the linearization reports them itself).
///
/// ```
/// use factor_core::kernel::kernel_mismatch;
/// use factor_core::{DynLinearization, Factor, Scalar};
/// use nalgebra::{DMatrix, DVector, Vector2};
///
/// #[derive(Clone, Debug, Factor)]
/// #[factor(residual = prior_residual, dim = 2)]
/// pub struct Prior<S: Scalar = f64> {
///     pub measured: Vector2<S>,
///     #[variable]
///     pub x: Vector2<S>,
/// }
///
/// pub fn prior_residual<S: Scalar>(f: &Prior<S>) -> Vector2<S> {
///     f.x - f.measured
/// }
///
/// let dual = DynLinearization {
///     residual: DVector::from_vec(vec![0.5, -1.0]),
///     jacobians: vec![DMatrix::identity(2, 2)],
/// };
/// let mut kernel = dual.clone();
/// kernel.residual[1] += 1e-12; // rounding
/// assert_eq!(kernel_mismatch::<Prior>(&kernel, &dual), None);
/// kernel.residual[1] = 1.0; // a sign flipped since the kernel was generated
/// let mismatch = kernel_mismatch::<Prior>(&kernel, &dual).unwrap();
/// assert_eq!(mismatch.output, "residual[1]");
/// ```
pub fn kernel_mismatch<F: Factor>(
    kernel: &DynLinearization,
    dual: &DynLinearization,
) -> Option<KernelMismatch> {
    if let Some(i) = first_difference(kernel.residual.as_slice(), dual.residual.as_slice()) {
        return Some(KernelMismatch {
            output: format!("residual[{i}]"),
            kernel: kernel.residual[i],
            dual: dual.residual[i],
        });
    }
    for (k, (block, reference)) in kernel.jacobians.iter().zip(&dual.jacobians).enumerate() {
        // Column-major: index `i` is row `i % rows`, column `i / rows`.
        if let Some(i) = first_difference(block.as_slice(), reference.as_slice()) {
            let rows = reference.nrows().max(1);
            return Some(KernelMismatch {
                output: format!(
                    "Jacobian w.r.t. `{}` (row {}, column {})",
                    F::variables()[k].name,
                    i % rows,
                    i / rows
                ),
                kernel: block.as_slice()[i],
                dual: reference.as_slice()[i],
            });
        }
    }
    None
}

/// [`kernel_mismatch`] for a kernel in a host's chart
/// ([`crate::host::HostKernel`]): its `residual` and column-major
/// `jacobian` (`residual.len()` rows) against dual numbers' in the same
/// chart at the same host values.
pub fn host_kernel_mismatch(
    residual: &[f64],
    jacobian: Option<&[f64]>,
    dual_residual: &[f64],
    dual_jacobian: &[f64],
) -> Option<KernelMismatch> {
    if let Some(i) = first_difference(residual, dual_residual) {
        return Some(KernelMismatch {
            output: format!("residual[{i}]"),
            kernel: residual[i],
            dual: dual_residual[i],
        });
    }
    let jacobian = jacobian?;
    let rows = residual.len().max(1);
    first_difference(jacobian, dual_jacobian).map(|i| KernelMismatch {
        output: format!(
            "Jacobian in the host's chart (row {}, column {})",
            i % rows,
            i / rows
        ),
        kernel: jacobian[i],
        dual: dual_jacobian[i],
    })
}

/// The first index where `kernel` differs from `dual` beyond
/// [`STALE_TOLERANCE`] relative to the largest `|dual|` (at least 1);
/// non-finite kernel entries are not compared.
fn first_difference(kernel: &[f64], dual: &[f64]) -> Option<usize> {
    let scale = dual.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    kernel
        .iter()
        .zip(dual)
        .position(|(k, d)| k.is_finite() && (k - d).abs() > STALE_TOLERANCE * scale)
}

/// One kernel's debug-build watch, a `static` the derive emits per kernel:
/// the first [`DEBUG_CHECKS`] calls compare the kernel with dual numbers, and
/// once a comparison finds it stale every later call reports it too, so a
/// stale kernel is never used afterwards (a solver stops on it instead of
/// running it once the first comparisons are past).
#[doc(hidden)]
#[derive(Debug)]
pub struct KernelWatch {
    calls: AtomicU32,
    stale: OnceLock<FactorError>,
}

impl KernelWatch {
    /// No call seen yet.
    #[allow(clippy::new_without_default)]
    pub const fn new() -> Self {
        KernelWatch {
            calls: AtomicU32::new(0),
            stale: OnceLock::new(),
        }
    }

    /// `Err` when the kernel was found stale, by this call's `compare` (run
    /// on the first [`DEBUG_CHECKS`] calls; `Some` is the stale report) or
    /// an earlier call's.
    ///
    /// # Errors
    ///
    /// [`FactorError::StaleKernel`].
    pub fn check(&self, compare: impl FnOnce() -> Option<FactorError>) -> Result<(), FactorError> {
        if let Some(stale) = self.stale.get() {
            return Err(stale.clone());
        }
        let first = self
            .calls
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |n| {
                (n < DEBUG_CHECKS).then_some(n + 1)
            })
            .is_ok();
        match first.then(compare).flatten() {
            Some(stale) => Err(self.stale.get_or_init(|| stale).clone()),
            None => Ok(()),
        }
    }
}

/// [`FactorError::StaleKernel`] for `F`'s kernel `kernel_path` when `kernel`
/// and `dual`, two linearizations at one configuration, disagree
/// ([`kernel_mismatch`]); `regenerate` says how to rewrite it.
#[doc(hidden)]
pub fn kernel_stale<F: Factor>(
    kernel: &DynLinearization,
    dual: &DynLinearization,
    kernel_path: &'static str,
    regenerate: &str,
) -> Option<FactorError> {
    kernel_mismatch::<F>(kernel, dual).map(|m| stale::<F>(kernel_path, &m, regenerate))
}

/// [`kernel_stale`] for `F`'s kernel in host `H`'s chart (`kernel_path`),
/// which wrote `residual` and `jacobian` at the stored scalars `stored` and
/// host parameters `parts`: compared with dual numbers in the same chart
/// ([`linearize_host_dual`]), unless the factor is invalid there (the
/// linearization reports that).
#[doc(hidden)]
pub fn host_kernel_stale<F: HostFactor<H>, H: Host>(
    stored: &[f64],
    parts: &[&[f64]],
    residual: &[f64],
    jacobian: Option<&[f64]>,
    kernel_path: &'static str,
    regenerate: &str,
) -> Option<FactorError> {
    let layout = HostLayout::<H::Manifold>::of::<F, H>();
    let mut dual_residual = vec![0.0; residual.len()];
    let mut dual_jacobian = vec![0.0; jacobian.map_or(0, <[f64]>::len)];
    linearize_host_dual::<F, H>(
        &layout,
        stored,
        parts,
        &mut dual_residual,
        jacobian.map(|_| dual_jacobian.as_mut_slice()),
    )
    .ok()?;
    host_kernel_mismatch(residual, jacobian, &dual_residual, &dual_jacobian)
        .map(|m| stale::<F>(kernel_path, &m, regenerate))
}

/// The report of a stale kernel.
fn stale<F: Factor>(
    kernel_path: &'static str,
    mismatch: &KernelMismatch,
    regenerate: &str,
) -> FactorError {
    FactorError::StaleKernel {
        factor: F::NAME,
        kernel: kernel_path,
        detail: format!(
            "{mismatch} (a residual, a function it calls or a variable's retraction changed \
             since the kernel was generated); {regenerate}. Debug builds compare the first {} \
             kernel linearizations of each factor type with dual numbers; release builds do \
             not, and the generator's `check` catches every change",
            DEBUG_CHECKS
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::{DEBUG_CHECKS, KernelWatch};
    use crate::FactorError;

    fn stale() -> FactorError {
        FactorError::StaleKernel {
            factor: "f",
            kernel: "k",
            detail: "d".into(),
        }
    }

    #[test]
    fn the_watch_compares_the_first_calls_only() {
        let watch = KernelWatch::new();
        let mut compared = 0;
        for _ in 0..DEBUG_CHECKS + 3 {
            assert_eq!(
                watch.check(|| {
                    compared += 1;
                    None
                }),
                Ok(())
            );
        }
        assert_eq!(compared, DEBUG_CHECKS);
    }

    #[test]
    fn a_stale_kernel_stays_reported() {
        let watch = KernelWatch::new();
        assert_eq!(watch.check(|| None), Ok(()));
        assert_eq!(watch.check(|| Some(stale())), Err(stale()));
        for _ in 0..2 * DEBUG_CHECKS {
            assert_eq!(watch.check(|| None), Err(stale()));
        }
    }
}
