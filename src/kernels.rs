//! The shipped factors: `slamjac`'s own registry ([`shipped`]) and their
//! kernels, what `slamjac generate` writes into `generated/`, through the
//! public generator API of `factor-codegen`, as any user's generator does.

use factor_codegen::{CodegenError, GeneratedCrate, KernelSpec, Provenance};

use crate::registry::{KernelCrate, Registry};
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

/// The workspace's `generated/`, found from where this binary was built:
/// the package `factor-generated`, written by [`PROVENANCE`]'s commands.
pub const KERNEL_CRATE: KernelCrate = KernelCrate {
    package: "factor-generated",
    dir: concat!(env!("CARGO_MANIFEST_DIR"), "/generated"),
    provenance: PROVENANCE,
};

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

/// Every shipped kernel, generated in [`shipped_kernels`] order.
///
/// # Errors
///
/// As [`GeneratedCrate::generate`] (none for the shipped factors).
pub fn generate_all() -> Result<GeneratedCrate, CodegenError> {
    GeneratedCrate::generate(PROVENANCE, &shipped_kernels())
}

/// `slamjac`'s own registry: the factors `slam-factors` ships, each with
/// its kernel in the workspace's `generated/` ([`shipped_kernels`]).
pub fn shipped() -> Registry {
    let registry = Registry::new()
        .with::<PointReprojection>()
        .with::<LineReprojection>()
        .with::<PlaneFactor>()
        .with::<FreeLineFactor>()
        .with::<PluckerLineReprojection>()
        .with::<SnavelyReprojection>()
        .with::<StereoReprojection>()
        .with::<BetweenFactor>()
        .with_kernel_crate(KERNEL_CRATE);
    shipped_kernels()
        .into_iter()
        .fold(registry, Registry::with_spec)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_fields_follow_the_declared_variables() {
        for entry in shipped().factors() {
            let declared: Vec<&str> = (entry.variables)().iter().map(|v| v.name).collect();
            let fields: Vec<&str> = entry
                .json_fields(true)
                .iter()
                .map(|(name, _)| *name)
                .collect();
            assert_eq!(declared, fields, "{}", entry.name);
        }
    }

    #[test]
    fn unknown_factors_list_the_known_ones() {
        let error = shipped().find("nope", "factor").unwrap_err();
        assert_eq!(error.path, "factor");
        assert!(
            error
                .message
                .contains("point_reprojection, line_reprojection, plane, free_line")
        );
    }

    #[test]
    fn every_shipped_factor_has_its_kernel_generated() {
        let registry = shipped();
        let factors: Vec<&str> = registry.factors().iter().map(|f| f.name).collect();
        let kernels: Vec<&str> = registry.specs().iter().map(|s| s.name).collect();
        let mut sorted = (factors.clone(), kernels);
        sorted.0.sort_unstable();
        sorted.1.sort_unstable();
        assert_eq!(sorted.0, sorted.1);
        assert!(registry.kernel_crate().is_some());
    }
}
