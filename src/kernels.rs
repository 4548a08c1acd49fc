//! The document factors' kernels: what `slamjac generate` writes into
//! `generated/`, through the public generator API of `factor-codegen`, as
//! any user's generator does.

use factor_codegen::{CodegenError, GeneratedCrate, KernelSpec, Provenance};
use slam_factors::{
    FreeLineFactor, LineReprojection, PlaneFactor, PluckerLineReprojection, PointReprojection,
};

/// Where `generated/` comes from: the kernels of the document factors,
/// written by `slamjac generate` and checked by `slamjac check`.
pub const PROVENANCE: Provenance = Provenance {
    description: "Residual-and-Jacobian kernels of the document factors, generated from their\n\
                  definitions in `slam-factors`.",
    generate: "slamjac generate",
    check: "slamjac check",
    conventions: "Conventions: quaternions `[x, y, z, w]`, Hamilton product, active rotation; \
                  poses of document 000 map world to camera (`X_c = R X_w + t`); pose \
                  tangents `[δω, δρ]`, rotation first; each block is the derivative of \
                  `r(x ⊞ δ)` at `δ = 0` on the variable's perturbation side.",
};

/// The five document factors of `slam-factors`, in the order `list` shows
/// them, each naming the document section its residual comes from.
pub fn document_kernels() -> Vec<KernelSpec> {
    vec![
        KernelSpec::of::<PointReprojection>()
            .with_source("document 000 §II (2)–(5)")
            .with_normal_equations(),
        KernelSpec::of::<LineReprojection>()
            .with_source("document 000 §III (6)–(12)")
            .with_normal_equations(),
        KernelSpec::of::<PluckerLineReprojection>()
            .with_source("document 000 §III (6)–(8), raw Plücker [n, v]")
            .with_normal_equations(),
        KernelSpec::of::<PlaneFactor>()
            .with_source("document 000 §IV (13)")
            .with_normal_equations(),
        KernelSpec::of::<FreeLineFactor>()
            .with_source("document 001 §3–4")
            .with_normal_equations(),
    ]
}

/// The spec of the document factor named `name`.
pub fn find(name: &str) -> Option<KernelSpec> {
    document_kernels()
        .into_iter()
        .find(|spec| spec.name == name)
}

/// Every document kernel, generated in [`document_kernels`] order.
///
/// # Errors
///
/// As [`GeneratedCrate::generate`] (none for the document factors).
pub fn generate_all() -> Result<GeneratedCrate, CodegenError> {
    GeneratedCrate::generate(PROVENANCE, &document_kernels())
}
