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
//! - [`noise`]: [`noise::Noise`], the noise model every solver path
//!   whitens a residual by.
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
pub mod noise;
pub mod numeric;
mod residual_check;
pub mod scalar;
pub mod storage;
pub mod validation;

pub use factor::{
    DynLinearization, Factor, FactorError, FieldInfo, VariableInfo, all_finite, first_non_finite,
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

    pub use crate::kernel::{KernelWatch, host_kernel_stale, kernel_stale};
    pub use crate::residual_check::{residual_arg, residual_value};

    /// [`all_finite`](crate::all_finite) of `values`, unrolled for their
    /// length `N` when it is `N` (the derive's check of a kernel's outputs
    /// in memory, whose lengths it knows).
    #[inline(always)]
    pub fn all_finite_of<const N: usize>(values: &[f64]) -> bool {
        match <&[f64; N]>::try_from(values) {
            Ok(values) => crate::all_finite(values),
            Err(_) => crate::all_finite(values),
        }
    }

    /// The most outputs (residual and every block) of a kernel that the
    /// derive's linearizations keep in local arrays, to test and copy them
    /// from registers: measured, 20–30 outputs (the point, line, plane,
    /// Snavely and stereo factors) are faster so, 78 (the between factor's)
    /// slower, its locals spilled to memory and copied once more.
    pub const OUTPUTS_IN_REGISTERS: usize = 32;

    /// Whether outputs of these lengths (the residual's, each block's) are
    /// at most [`OUTPUTS_IN_REGISTERS`], in a constant.
    pub const fn in_registers(lengths: &[usize]) -> bool {
        let (mut total, mut i) = (0, 0);
        while i < lengths.len() {
            total += lengths[i];
            i += 1;
        }
        total <= OUTPUTS_IN_REGISTERS
    }

    /// The derive's test that a kernel's outputs, in registers, are all
    /// finite: their sum is. A NaN or an infinity makes the sum NaN or
    /// infinite, so a finite sum is exact; a sum of finite values can
    /// overflow, so an infinite one is only a hint, which the derive
    /// confirms value by value ([`first_non_finite`](crate::first_non_finite)).
    /// One addition per value, in four interleaved sums (one sum would be a
    /// chain of dependent additions) started at `−0`, which the first
    /// additions fold away (`x + (−0) = x` exactly).
    #[derive(Debug, Clone, Copy)]
    pub struct OutputSum([f64; 4]);

    impl OutputSum {
        /// No values yet.
        pub const EMPTY: Self = OutputSum([-0.0; 4]);

        /// `values` added.
        #[inline(always)]
        pub fn with<const N: usize>(mut self, values: &[f64; N]) -> Self {
            for (i, x) in values.iter().enumerate() {
                self.0[i % 4] += x;
            }
            self
        }

        /// Whether the sum is finite.
        #[inline(always)]
        pub fn is_finite(self) -> bool {
            let [a, b, c, d] = self.0;
            ((a + b) + (c + d)).is_finite()
        }
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
///
/// ```
/// use factor_core::lie::Se3;
/// use factor_core::{Factor, FactorError, Scalar};
/// use nalgebra::{Vector2, Vector3};
///
/// #[derive(Clone, Debug, Factor)]
/// #[factor(residual = point_residual, dim = 2, validate = point_validate)]
/// pub struct PointReprojection<S: Scalar = f64> {
///     pub focal: S, // no attribute: a constant
///     pub observed: Vector2<S>,
///     #[variable(left)] // `left`, `right`, or a bare `#[variable]` (= left)
///     pub pose: Se3<S>,
///     #[variable]
///     pub point: Vector3<S>,
/// }
///
/// pub fn point_residual<S: Scalar>(f: &PointReprojection<S>) -> Vector2<S> {
///     let p = f.pose.transform_point(&f.point);
///     Vector2::new(p.x / p.z, p.y / p.z) * f.focal - f.observed
/// }
///
/// pub fn point_validate(f: &PointReprojection<f64>) -> Result<(), FactorError> {
///     let depth = f.pose.transform_point(&f.point).z;
///     if depth > 1e-9 {
///         Ok(())
///     } else {
///         Err(FactorError::Degenerate {
///             factor: "point_reprojection",
///             reason: format!("point at depth {depth}"),
///         })
///     }
/// }
///
/// let f = PointReprojection {
///     focal: 500.0,
///     observed: Vector2::new(12.0, 25.0),
///     pose: Se3::identity(),
///     point: Vector3::new(0.1, 0.2, 4.0),
/// };
/// let linearization: PointReprojectionLinearization = f.linearize().unwrap();
/// assert_eq!(linearization.pose.shape(), (2, 6));
/// assert_eq!(linearization.point.shape(), (2, 3));
/// assert_eq!(<PointReprojection as Factor>::NAME, "point_reprojection");
/// // Numerical differentiation on the manifolds agrees (in a test, one line
/// // does all blocks: `factor_testing::assert_correct_jacobians(&f, 1e-6)`).
/// use factor_core::NumericLinearize;
/// let numeric = f.linearize_numeric_dyn().unwrap();
/// let error = numeric.jacobians[0]
///     .iter()
///     .zip(linearization.pose.iter())
///     .map(|(n, d)| (n - d).abs())
///     .fold(0.0, f64::max);
/// assert!(error <= 1e-6 * linearization.pose.amax());
/// ```
pub use factor_macros::Factor;

// Lets the derive's `::factor_core::...` paths resolve inside this crate.
extern crate self as factor_core;
