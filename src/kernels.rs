//! The shipped factors: `slamjac`'s own registry ([`shipped`]) and their
//! kernels, what `slamjac generate` writes into `generated/`, through the
//! public generator API of `factor-codegen`, as any user's generator does.

use factor_codegen::{HostSpec, KernelSpec, Provenance};
#[cfg(feature = "kernels")]
use factor_core::host::HostKernel;
use factor_core::host::{Apex, HostFactor};

use crate::registry::{KernelCrate, Registry};
use slam_factors::{
    BetweenFactor, FreeLineFactor, G2oLineEdge, G2oPlaneEdge, G2oSe3Edge, LineObservation,
    LineReprojection, PlaneFactor, PluckerLineReprojection, PointReprojection, SnavelyReprojection,
    StereoReprojection,
};

/// Where `generated/` comes from: the kernels of the shipped factors,
/// written by `slamjac generate` and checked by `slamjac check`.
pub const PROVENANCE: Provenance = Provenance::new(
    "Residual-and-Jacobian kernels of the factors `slam-factors` ships, generated\n\
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
/// factors and the 3D line observation over the documents' orthonormal
/// line, the three of `slamjac solve`, then g2o's pose-edge error. (g2o's
/// line and plane edge errors linearize through dual numbers: their kernels
/// would double the generator's time in every `generate` and `check`; see
/// `slam_factors::g2o`.) Every one also has a kernel in
/// apex-solver's chart ([`factor_core::host::Apex`]) and, in the C++ of
/// `generated/cpp/`, a Ceres cost function and manifolds.
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
            .with_source("pose-graph relative pose (GTSAM's `BetweenFactor<Pose3>`), whitened")
            .with_normal_equations(),
        with_apex::<G2oSe3Edge>().with_source("g2o's `EdgeSE3` error (`EDGE_SE3:QUAT`)"),
    ]
}

/// Factor `F`'s spec with its kernel in apex-solver's chart beside its own
/// (`<name>_apex`), and in its C++ a Ceres cost function and manifolds.
fn with_apex<F: HostFactor<Apex>>() -> KernelSpec {
    KernelSpec::of::<F>()
        .with_host(HostSpec::of::<F, Apex>())
        .with_ceres()
}

/// `slamjac`'s own registry: the factors `slam-factors` ships, each with
/// its kernel in the workspace's `generated/` ([`shipped_kernels`]), and
/// each solved from problem files: through its apex kernel, g2o's line and
/// plane edge errors through dual numbers (they have no kernel).
pub fn shipped() -> Registry {
    let with_kernels: [fn(Registry) -> Registry; 10] = [
        solved::<PointReprojection>,
        solved::<LineReprojection>,
        solved::<PlaneFactor>,
        solved::<FreeLineFactor>,
        solved::<PluckerLineReprojection>,
        solved::<LineObservation>,
        solved::<SnavelyReprojection>,
        solved::<StereoReprojection>,
        solved::<BetweenFactor>,
        solved::<G2oSe3Edge>,
    ];
    let registry = with_kernels
        .into_iter()
        .fold(Registry::new(), |registry, add| add(registry))
        .solve_with_dual::<G2oLineEdge>()
        .solve_with_dual::<G2oPlaneEdge>()
        .with_kernel_crate(KERNEL_CRATE);
    #[cfg(feature = "solve")]
    let registry = with_schur(registry);
    shipped_kernels()
        .into_iter()
        .fold(registry, Registry::with_spec)
}

/// The shipped factors also in the Schur-complement solver's problems:
/// those whose kernels have fused normal equations ([`shipped_kernels`]) in
/// lane batches, the pose-graph and g2o factors one at a time.
/// `PluckerLineReprojection` goes as `LineReprojection`, the same residual
/// with its line in the orthonormal chart
/// ([`slamjac_registry::schur_assembly::add_plucker_line`]): the Schur path retracts
/// each variable by its own manifold, and a `PluckerLine`'s is a free
/// 6-vector that leaves the Klein quadric and carries a scale no residual
/// sees.
#[cfg(feature = "solve")]
fn with_schur(registry: Registry) -> Registry {
    registry
        .solve_with_schur::<PointReprojection>()
        .solve_with_schur::<LineReprojection>()
        .solve_with_schur_by::<PluckerLineReprojection>(
            slamjac_registry::schur_assembly::add_plucker_line,
            factor_schur::Linearized::Batch,
        )
        .solve_with_schur::<PlaneFactor>()
        .solve_with_schur::<FreeLineFactor>()
        .solve_with_schur::<LineObservation>()
        .solve_with_schur::<SnavelyReprojection>()
        .solve_with_schur::<StereoReprojection>()
        .solve_with_schur_each::<BetweenFactor>()
        .solve_with_schur_each::<G2oSe3Edge>()
        .solve_with_schur_each::<G2oLineEdge>()
        .solve_with_schur_each::<G2oPlaneEdge>()
}

/// A shipped factor with a kernel, solved through it; in a build without
/// the kernels (`--no-default-features`, for `generate`) registered for
/// `list` and `eval` only.
#[cfg(feature = "kernels")]
fn solved<F: HostKernel<Apex> + 'static>(registry: Registry) -> Registry {
    registry.solve_with_kernel::<F>()
}

#[cfg(not(feature = "kernels"))]
fn solved<F: HostFactor<Apex> + 'static>(registry: Registry) -> Registry {
    registry.with::<F>()
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

    /// Every kernel is a listed factor's; the factors without one are g2o's
    /// line and plane edge errors (see [`shipped_kernels`]).
    #[test]
    fn every_shipped_factor_but_g2os_line_and_plane_has_its_kernel_generated() {
        let registry = shipped();
        let kernels: Vec<&str> = registry.specs().iter().map(|s| s.name).collect();
        let (with, without): (Vec<&str>, Vec<&str>) = registry
            .factors()
            .iter()
            .map(|f| f.name)
            .partition(|name| kernels.contains(name));
        assert_eq!(with.len(), kernels.len(), "a kernel without its factor");
        assert_eq!(without, ["g2o_se3_line3d", "g2o_se3_plane_calib"]);
        assert!(registry.kernel_crate().is_some());
    }

    /// Every factor `slamjac` ships is registered for `solve`.
    #[cfg(feature = "solve")]
    #[test]
    fn every_shipped_factor_can_be_solved() {
        for entry in shipped().factors() {
            assert!(entry.solve.is_some(), "{}", entry.name);
        }
    }
}
