//! The runtime of `slamjac` factors: what an estimator that embeds them
//! needs, and nothing that only the code generator needs.
//!
//! - [`scalar`]: the [`Scalar`] abstraction (`f64`, `f32`, dual numbers, and
//!   the symbolic scalar of crate `factor-symbolic`) that residuals and
//!   geometry are written against.
//! - [`dual`]: [`dual::Dual`], the dual numbers every exact linearization
//!   runs on (derivatives on the stack, as wide as the factor's tangent).
//! - [`lie`]: SO(2), SO(3), SE(3) and unit quaternions, generic over the scalar,
//!   with one vocabulary, [`lie::LieGroup`].
//! - [`geometry`]: Plücker lines and their orthonormal representation, infinite
//!   planes, the free line of document 001, camera intrinsics, bearing planes.
//! - [`manifold`]: tangent dimensions, retractions and perturbation sides.
//! - [`storage`]: how a value is stored as named scalars, and read from
//!   what a user writes.
//! - [`factor`]: the factor model and its errors; `#[derive(Factor)]`
//!   (crate `factor-macros`) implements it.
//! - [`host`]: host solvers' charts ([`host::Apex`]): a factor served to a
//!   solver in the solver's own manifolds, parameter layouts and tangents.
//! - [`kernel`]: [`WithKernel`], the link from a factor to its generated
//!   kernel, for batch evaluators, and how a stale kernel is caught.
//! - [`numeric`]: numerical differentiation with an error estimate, the
//!   independent reference for the exact Jacobians.
//! - [`linalg`]: vector helpers that need only [`Scalar`] arithmetic.
//! - [`validation`]: NaN-rejecting comparisons for validation code.
//!
//! The factors the toolchain ships are in crate `slam-factors`, the test
//! helpers in `factor-testing`, the symbolic engine and the code generator
//! in `factor-symbolic` and `factor-codegen`, the derivation audit in
//! `factor-audit`.
//!
//! Conventions (pinned for the whole workspace; see the README):
//! quaternions are stored `[x, y, z, w]` with the Hamilton product and the
//! active rotation `R(q) v = q ⊗ [v, 0] ⊗ q⁻¹`; `hat(ω) b = ω × b`; poses map
//! world to camera, `X_c = R X_w + t`; pose tangents are `[δω, δρ]`, rotation
//! first; Jacobians are residual rows × tangent columns.

pub mod dual;
pub mod factor;
pub mod geometry;
pub mod host;
pub mod kernel;
pub mod lie;
pub mod linalg;
pub mod manifold;
pub mod numeric;
pub mod scalar;
pub mod storage;
pub mod validation;

pub use factor::{
    DynLinearization, Factor, FactorError, FieldInfo, VariableInfo, first_non_finite,
};
pub use kernel::WithKernel;
pub use manifold::{Manifold, Perturbation};
pub use numeric::{NumericLinearization, NumericLinearize};
pub use scalar::Scalar;
pub use storage::{Layout, Storage, StorageError};

/// The `nalgebra` this crate's types and the derive's linearizations are
/// built on (0.35). A factor's fields and residual must use these types:
/// depend on the same `nalgebra` version, or write `factor_core::nalgebra`.
/// With another version the vectors are different types and the compiler
/// reports mismatched types. The generated kernels take plain arrays, so an
/// embedder on another `nalgebra` calls them directly.
pub use nalgebra;

/// Re-exports the derive macro's generated code relies on.
#[doc(hidden)]
pub mod __private {
    pub use nalgebra;
    pub use num_dual;

    /// Whether two shapes (lists of array lengths) are equal, in a constant:
    /// the derive's compile-time check that a generated kernel is current.
    pub const fn same_shape(a: &[usize], b: &[usize]) -> bool {
        if a.len() != b.len() {
            return false;
        }
        let mut i = 0;
        while i < a.len() {
            if a[i] != b[i] {
                return false;
            }
            i += 1;
        }
        true
    }

    /// Counts a factor type's kernel linearizations up to
    /// [`DEBUG_CHECKS`](crate::kernel::DEBUG_CHECKS): the derive's debug-build
    /// comparison with dual numbers runs while [`FirstCalls::take`] says so.
    pub struct FirstCalls(core::sync::atomic::AtomicU32);

    impl FirstCalls {
        /// No call counted yet.
        #[allow(clippy::new_without_default)]
        pub const fn new() -> Self {
            FirstCalls(core::sync::atomic::AtomicU32::new(0))
        }

        /// Whether this call is among the first
        /// [`DEBUG_CHECKS`](crate::kernel::DEBUG_CHECKS).
        pub fn take(&self) -> bool {
            use core::sync::atomic::Ordering::Relaxed;
            self.0
                .fetch_update(Relaxed, Relaxed, |n| {
                    (n < crate::kernel::DEBUG_CHECKS).then_some(n + 1)
                })
                .is_ok()
        }
    }

    /// Panics when `kernel` and `dual`, two linearizations of `F` at one
    /// configuration, disagree ([`kernel_mismatch`](crate::kernel::kernel_mismatch)):
    /// the kernel `kernel_path` is stale; `regenerate` says how to rewrite it.
    #[track_caller]
    pub fn assert_kernel_current<F: crate::Factor>(
        kernel: &crate::DynLinearization,
        dual: &crate::DynLinearization,
        kernel_path: &str,
        regenerate: &str,
    ) {
        if let Some(mismatch) = crate::kernel::kernel_mismatch::<F>(kernel, dual) {
            stale(kernel_path, &mismatch, regenerate);
        }
    }

    /// [`assert_kernel_current`] for `F`'s kernel in host `H`'s chart
    /// (`kernel_path`), which wrote `residual` and `jacobian` at the stored
    /// scalars `stored` and host parameters `parts`: compared with dual
    /// numbers in the same chart ([`crate::host::linearize_host_dual`]),
    /// unless the factor is invalid there (the solver reports that).
    #[track_caller]
    pub fn assert_host_kernel_current<F: crate::host::HostFactor<H>, H: crate::host::Host>(
        stored: &[f64],
        parts: &[&[f64]],
        residual: &[f64],
        jacobian: Option<&[f64]>,
        kernel_path: &str,
        regenerate: &str,
    ) {
        let layout = crate::host::HostLayout::<H::Manifold>::of::<F, H>();
        let mut dual_residual = vec![0.0; residual.len()];
        let mut dual_jacobian = vec![0.0; jacobian.map_or(0, <[f64]>::len)];
        let dual = crate::host::linearize_host_dual::<F, H>(
            &layout,
            stored,
            parts,
            &mut dual_residual,
            jacobian.map(|_| dual_jacobian.as_mut_slice()),
        );
        if dual.is_err() {
            return;
        }
        if let Some(mismatch) =
            crate::kernel::host_kernel_mismatch(residual, jacobian, &dual_residual, &dual_jacobian)
        {
            stale(kernel_path, &mismatch, regenerate);
        }
    }

    /// The panic of a stale kernel.
    #[track_caller]
    fn stale(kernel_path: &str, mismatch: &crate::kernel::KernelMismatch, regenerate: &str) -> ! {
        panic!(
            "the generated kernel `{kernel_path}` is stale: {mismatch} (a residual, a function \
             it calls or a variable's retraction changed since the kernel was generated); \
             {regenerate}. Debug builds compare the first {} kernel linearizations of each \
             factor type with dual numbers; release builds do not, and the generator's `check` \
             catches every change.",
            crate::kernel::DEBUG_CHECKS
        );
    }

    /// Whether two strings are equal, in a constant: the derive's check
    /// that a host's `NAME` is the one `hosts(…)` names.
    pub const fn same_str(a: &str, b: &str) -> bool {
        let (a, b) = (a.as_bytes(), b.as_bytes());
        if a.len() != b.len() {
            return false;
        }
        let mut i = 0;
        while i < a.len() {
            if a[i] != b[i] {
                return false;
            }
            i += 1;
        }
        true
    }
}

/// `#[derive(Factor)]`: the typed API and the [`Factor`] impl from a struct and
/// one generic residual function (crate `factor-macros`).
pub use factor_macros::Factor;

// Lets the derive's `::factor_core::...` paths resolve inside this crate.
extern crate self as factor_core;
