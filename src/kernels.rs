//! The shipped factors' kernels: what `slamjac generate` writes into
//! `generated/`, through the public generator API of `factor-codegen`, as
//! any user's generator does.

use factor_codegen::{CodegenError, GeneratedCrate, KernelSpec, Provenance};
use slam_factors::{
    BetweenFactor, FreeLineFactor, LineReprojection, PlaneFactor, PluckerLineReprojection,
    PointReprojection, SnavelyReprojection, StereoReprojection,
};

/// Where `generated/` comes from: the kernels of the shipped factors,
/// written by `slamjac generate` and checked by `slamjac check`.
pub const PROVENANCE: Provenance = Provenance::new(
    "Residual-and-Jacobian kernels of the factors `slam-factors` ships, generated
\
     from their definitions.",
    "slamjac generate",
    "slamjac check",
);

/// The factors of `slam-factors` with kernels, in the order `list` shows
/// them, each naming where its residual comes from: the five document
/// factors, then the three of `slamjac solve`.
pub fn shipped_kernels() -> Vec<KernelSpec> {
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
        KernelSpec::of::<SnavelyReprojection>()
            .with_source(
                "the BAL / Bundler camera model (Snavely; Ceres' `SnavelyReprojectionError`)",
            )
            .with_normal_equations(),
        KernelSpec::of::<StereoReprojection>()
            .with_source("rectified stereo (GTSAM's `GenericStereoFactor3D`, `Cal3_S2Stereo`)")
            .with_normal_equations(),
        KernelSpec::of::<BetweenFactor>()
            .with_source("pose-graph relative pose (GTSAM's `BetweenFactor<Pose3>`), whitened"),
    ]
}

/// The spec of the shipped factor named `name`.
pub fn find(name: &str) -> Option<KernelSpec> {
    shipped_kernels().into_iter().find(|spec| spec.name == name)
}

/// Every shipped kernel, generated in [`shipped_kernels`] order.
///
/// # Errors
///
/// As [`GeneratedCrate::generate`] (none for the shipped factors).
pub fn generate_all() -> Result<GeneratedCrate, CodegenError> {
    GeneratedCrate::generate(PROVENANCE, &shipped_kernels())
}
