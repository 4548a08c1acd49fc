//! What `generate-kernels` generates: one [`KernelSpec`] per factor of this
//! crate, named by [`PROVENANCE`], written into the crate `user-kernels`.
//!
//! A new factor with a kernel needs an entry in [`kernel_specs`] and a
//! `#[cfg_attr(feature = "kernels", factor(kernel = user_kernels::<name>::<name>,
//! regenerate = "..."))]` on its struct; then regenerate (see the crate
//! documentation).

use std::path::{Path, PathBuf};

use factor_codegen::{CodegenError, GeneratedCrate, HostSpec, KernelSpec, Provenance};
use factor_core::host::Apex;

use crate::{Direction, PointToPlane, RelativePose, RelativeSim3, ScaledRangeBearing};

/// What the generated files say about where they come from.
pub const PROVENANCE: Provenance = Provenance::new(
    "Residual-and-Jacobian kernels of the factors of `user-factors`, generated from\n\
     their definitions there.",
    "cargo run -p user-factors --bin generate-kernels",
    "cargo run -p user-factors --bin generate-kernels -- --check",
);

/// One spec per factor with a kernel: the module headers take each input's
/// layout and description from the factor's own definition. Two also get
/// the fused normal-equation kernel (`<name>_normal`), which the batch
/// evaluators of `factor-batch` use for `JᵀwJ` and `Jᵀwr`; the two over this
/// crate's own manifolds also get a kernel in apex-solver's chart
/// (`<name>_apex`, through [`crate::apex_chart`]).
pub fn kernel_specs() -> Vec<KernelSpec> {
    vec![
        KernelSpec::of::<RelativePose>().with_normal_equations(),
        KernelSpec::of::<PointToPlane>(),
        KernelSpec::of::<ScaledRangeBearing>(),
        KernelSpec::of::<Direction>()
            .with_normal_equations()
            .with_host(HostSpec::of::<Direction, Apex>()),
        KernelSpec::of::<RelativeSim3>().with_host(HostSpec::of::<RelativeSim3, Apex>()),
    ]
}

/// Every kernel, in [`kernel_specs`] order.
///
/// # Errors
///
/// As [`GeneratedCrate::generate`].
pub fn generate() -> Result<GeneratedCrate, CodegenError> {
    GeneratedCrate::generate(PROVENANCE, &kernel_specs())
}

/// The crate `user-kernels`, beside this crate in the source tree.
pub fn default_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the crate directory has a parent")
        .join("user-kernels")
}
