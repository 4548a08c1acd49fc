//! `user-cli`: the command line of `user-factors`' six factors, from
//! slamjac's command-line library (`slamjac::cli`): `list`, `eval`,
//! `generate` and `check` of their kernels in `user-kernels`, and with the
//! feature `solve`, `solve` of problem files whose factors are these.
//!
//! ```sh
//! cargo run -p user-cli --no-default-features -- generate   # rewrite ../user-kernels/src and cpp/
//! cargo run -p user-cli --no-default-features -- check      # exit 1, naming the files, when stale
//! cargo run -p user-cli -- list
//! cargo run -p user-cli -- eval INPUT.json
//! cargo run --release -p user-cli --features solve -- solve PROBLEM.json [--output FILE]
//! ```
//!
//! `generate` and `check` build without the feature `kernels`: the factors
//! then linearize by dual numbers and `user-kernels` is not compiled, so
//! they work when the kernels are missing or no longer compile.
//!
//! The two factors over the crate's own manifolds, `direction` (S²) and
//! `relative_sim3` (Sim(3)), also get kernels in apex-solver's chart
//! (`hosts(apex)`, through `user_factors::apex_chart`) and are solved
//! through them; the four over slamjac's types are solved through dual
//! numbers in that chart.

use std::process::ExitCode;

use slamjac::cli::{Apex, CommandLine, HostSpec, KernelCrate, KernelSpec, Provenance, Registry};
use user_factors::{
    Direction, InverseDepthProjection, PointToPlane, RelativePose, RelativeSim3, ScaledRangeBearing,
};

/// The crate `generate` writes and `check` compares.
const KERNELS: KernelCrate = KernelCrate {
    package: "user-kernels",
    dir: concat!(env!("CARGO_MANIFEST_DIR"), "/../user-kernels"),
    provenance: Provenance::new(
        "Residual-and-Jacobian kernels of the factors of `user-factors`, generated from\n\
         their definitions there.",
        "cargo run -p user-cli --no-default-features -- generate",
        "cargo run -p user-cli --no-default-features -- check",
    ),
};

fn main() -> ExitCode {
    // Every factor also gets, in `generate --lang cpp`'s C++ (`../user-kernels/cpp`),
    // a Ceres cost function and a Ceres manifold per variable type
    // (`with_ceres()`; the crate's Sim(3) and S² give `Manifold::local`).
    let registry = Registry::new()
        .solve_with_dual::<RelativePose>()
        .solve_with_dual::<PointToPlane>()
        .solve_with_dual::<ScaledRangeBearing>()
        .solve_with_dual::<InverseDepthProjection>()
        // `RelativePose` and `Direction` also get the fused normal-equation
        // kernel (`JᵀwJ`, `Jᵀwr`) the batch evaluators of `factor-batch` use.
        .with_spec(
            KernelSpec::of::<RelativePose>()
                .with_normal_equations()
                .with_ceres(),
        )
        .with_spec(KernelSpec::of::<PointToPlane>().with_ceres())
        .with_spec(KernelSpec::of::<ScaledRangeBearing>().with_ceres())
        .with_spec(KernelSpec::of::<InverseDepthProjection>().with_ceres())
        .with_spec(
            KernelSpec::of::<Direction>()
                .with_normal_equations()
                .with_host(HostSpec::of::<Direction, Apex>())
                .with_ceres(),
        )
        .with_spec(
            KernelSpec::of::<RelativeSim3>()
                .with_host(HostSpec::of::<RelativeSim3, Apex>())
                .with_ceres(),
        );
    // The apex kernels exist in builds with the kernels only; `generate`'s
    // build solves (were it asked to) by dual numbers.
    #[cfg(feature = "kernels")]
    let registry = registry
        .solve_with_kernel::<Direction>()
        .solve_with_kernel::<RelativeSim3>();
    #[cfg(not(feature = "kernels"))]
    let registry = registry
        .solve_with_dual::<Direction>()
        .solve_with_dual::<RelativeSim3>();
    registry.with_kernel_crate(KERNELS).run("user-cli")
}
