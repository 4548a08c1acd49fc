//! The shipped factors' kernels: what `slamjac generate` writes into
//! `generated/`, through the public generator API of `factor-codegen`, as
//! any user's generator does.

use factor_codegen::{CodegenError, GeneratedCrate, HostSpec, KernelSpec, Provenance};
use factor_core::host::{Apex, HostFactor};
use slam_factors::{
    BetweenFactor, FreeLineFactor, G2oSe3Edge, LineObservation, LineReprojection, PlaneFactor,
    PluckerLineReprojection, PointReprojection, SnavelyReprojection, StereoReprojection,
};

/// Where `generated/` comes from: the kernels of the shipped factors,
/// written by `slamjac generate` and checked by `slamjac check`.
pub const PROVENANCE: Provenance = Provenance {
    description: "Residual-and-Jacobian kernels of the factors `slam-factors` ships, generated\n\
                  from their definitions.",
    generate: "slamjac generate",
    check: "slamjac check",
    conventions: "Conventions: quaternions `[x, y, z, w]`, Hamilton product, active rotation; \
                  poses of document 000 map world to camera (`X_c = R X_w + t`); pose \
                  tangents `[δω, δρ]`, rotation first, except `Se3RhoTheta` poses \
                  (`[δρ, δθ]`, apex-solver's chart); each block is the derivative of \
                  `r(x ⊞ δ)` at `δ = 0` on the variable's perturbation side.",
};

/// The factors of `slam-factors` with kernels, in the order `list` shows
/// them, each naming where its residual comes from: the five document
/// factors and the 3D line observation over the documents' orthonormal
/// line, the three of `slamjac solve`, then g2o's pose-edge error. (g2o's
/// line and plane edge errors linearize through dual numbers: their kernels
/// take the generator 30 s and 19 s, which every `generate` and `check`
/// would pay; see `slam_factors::g2o`.) Every one also has a kernel in
/// apex-solver's chart ([`factor_core::host::Apex`]).
pub fn shipped_kernels() -> Vec<KernelSpec> {
    vec![
        with_apex::<PointReprojection>()
            .with_source("document 000 §II (2)–(5)")
            .with_normal_equations(),
        with_apex::<LineReprojection>()
            .with_source("document 000 §III (6)–(12)")
            .with_normal_equations(),
        with_apex::<PluckerLineReprojection>()
            .with_source("document 000 §III (6)–(8), raw Plücker [n, v]")
            .with_normal_equations(),
        with_apex::<PlaneFactor>()
            .with_source("document 000 §IV (13)")
            .with_normal_equations(),
        with_apex::<LineObservation>()
            .with_source("a 3D line in the camera frame over document 000 §III's orthonormal line")
            .with_normal_equations(),
        with_apex::<FreeLineFactor>()
            .with_source("document 001 §3–4")
            .with_normal_equations(),
        with_apex::<SnavelyReprojection>()
            .with_source(
                "the BAL / Bundler camera model (Snavely; Ceres' `SnavelyReprojectionError`)",
            )
            .with_normal_equations(),
        with_apex::<StereoReprojection>()
            .with_source("rectified stereo (GTSAM's `GenericStereoFactor3D`, `Cal3_S2Stereo`)")
            .with_normal_equations(),
        with_apex::<BetweenFactor>()
            .with_source("pose-graph relative pose (GTSAM's `BetweenFactor<Pose3>`), whitened"),
        with_apex::<G2oSe3Edge>().with_source("g2o's `EdgeSE3` error (`EDGE_SE3:QUAT`)"),
    ]
}

/// Factor `F`'s spec with its kernel in apex-solver's chart beside its own
/// (`<name>_apex`).
fn with_apex<F: HostFactor<Apex>>() -> KernelSpec {
    KernelSpec::of::<F>().with_host(HostSpec::of::<F, Apex>())
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
