//! The C++ of `generated/cpp` (`slamjac generate --lang cpp`) against the
//! Rust, when a C++ compiler is present (`g++`, or `$CXX`; CI has one):
//!
//! - every emitted function template, instantiated in `double` and `float`
//!   by one driver, compiles with `-std=c++17 -Wall -Wextra -Werror`;
//! - each shipped factor's kernel in `double` equals its Rust kernel within
//!   1e-13 relative (per output array) at 10⁴ seeded configurations, and in
//!   `float` within single precision's rounding of it;
//! - its ambient kernel (the Ceres cost functions' Jacobians) equals dual
//!   numbers through the residual with the stored scalars perturbed, and
//!   each variable chart's four maps equal the type's own `retract` and
//!   `local` and their dual-number derivatives, at 200 configurations.
//!
//! Ceres itself is not needed here; `bench-peers/ceres_host/` runs Ceres'
//! own checks and solves.

use std::path::Path;

use factor_core::Factor;
use factor_testing::cpp::{Driver, Expected, calls, compiler, expected};
use factor_testing::samples::Sampler;
use slam_factors::{
    BetweenFactor, FreeLineFactor, G2oSe3Edge, LineObservation, LineReprojection, PlaneFactor,
    PluckerLineReprojection, PointReprojection, SnavelyReprojection, StereoReprojection,
};
use slamjac::kernels::shipped_kernels;

use crate::common::temp_dir;

/// Configurations per factor at which its kernel is compared.
const CONFIGURATIONS: usize = 10_000;
/// Configurations per factor at which the ambient kernel and the charts
/// are compared (their references are dual numbers, slow in a debug build).
const FEW: usize = 200;

/// The C++ kernels in `double` against the Rust ones: the bound.
const KERNEL_TOLERANCE: f64 = 1e-13;
/// Against dual numbers, whose operations are ordered otherwise: rounding.
const DUAL_TOLERANCE: f64 = 1e-12;
/// `float` against the `f64` Rust kernel: single precision's rounding,
/// amplified by the kernels' cancellations (a line residual sums pixel
/// coordinates of order 500 down to a fraction of a pixel).
const FLOAT_TOLERANCE: f64 = 1e-4;

/// `CONFIGURATIONS` seeded samples of a shipped factor.
fn samples<F>(seed: u64, sample: fn(&mut Sampler) -> F) -> Vec<F> {
    let mut sampler = Sampler::new(seed);
    (0..CONFIGURATIONS).map(|_| sample(&mut sampler)).collect()
}

/// Every shipped factor with a kernel, in `shipped_kernels` order, with
/// its sampler: the calls of each, and the Rust side of each's comparison.
macro_rules! shipped {
    ($($factor:ty => $sampler:ident),* $(,)?) => {
        fn all_calls(library: &Path) -> Vec<factor_testing::cpp::Call> {
            let mut all = Vec::new();
            $(all.extend(calls::<$factor>(library));)*
            all
        }

        fn names() -> Vec<&'static str> {
            vec![$(<$factor>::NAME),*]
        }

        fn all_expected() -> Vec<Expected> {
            let mut seed = 0;
            vec![$({
                seed += 1;
                expected::<$factor>(&samples(seed, Sampler::$sampler), FEW)
            }),*]
        }
    };
}

shipped!(
    PointReprojection => point_reprojection,
    LineReprojection => line_reprojection,
    PluckerLineReprojection => plucker_line_reprojection,
    PlaneFactor => plane,
    LineObservation => line_observation,
    FreeLineFactor => free_line,
    SnavelyReprojection => snavely_reprojection,
    StereoReprojection => stereo_reprojection,
    BetweenFactor => between,
    G2oSe3Edge => g2o_se3,
);

#[test]
fn the_generated_cpp_compiles_warning_free_and_equals_the_rust_kernels() {
    let shipped: Vec<&str> = shipped_kernels().iter().map(|s| s.name).collect();
    assert_eq!(names(), shipped, "every shipped kernel is checked");
    let Some(compiler) = compiler() else {
        eprintln!("no C++ compiler (g++, or $CXX): generated/cpp is not compiled here");
        return;
    };
    let include = Path::new(env!("CARGO_MANIFEST_DIR")).join("generated/cpp");
    let library = include.join("factor_generated");
    let calls = all_calls(&library);
    // Every chart the library has is called (and so checked below).
    for entry in std::fs::read_dir(library.join("charts")).expect("generated/cpp has charts") {
        let path = entry.expect("a chart").path();
        let chart = path
            .file_stem()
            .and_then(|s| s.to_str())
            .expect("a chart's name");
        let retract = format!("{chart}_retract");
        assert!(
            calls.iter().any(|c| c.function == retract),
            "{chart} is not checked"
        );
    }
    let dir = temp_dir("cpp", "driver");
    // The compiler runs while the Rust side is computed.
    let pending = Driver::spawn(
        &compiler,
        &include,
        "factor_generated/kernels.h",
        "factor_generated",
        calls,
        &dir,
    )
    .unwrap_or_else(|e| panic!("the C++ compiler does not start: {e}"));
    let expected = all_expected();
    let driver = pending
        .wait()
        .unwrap_or_else(|diagnostics| panic!("generated/cpp does not compile:\n{diagnostics}"));
    for (name, check) in expected.iter().map(|e| (e.name(), e.check(&driver))) {
        eprintln!("{name}: {check:?}");
        assert_eq!(check.configurations, CONFIGURATIONS);
        assert!(check.kernel <= KERNEL_TOLERANCE, "{name}: {check:?}");
        assert!(check.kernel_float <= FLOAT_TOLERANCE, "{name}: {check:?}");
        for (what, error) in [
            ("ambient", check.ambient),
            ("retract", check.retract),
            ("retract_jacobian", check.retract_jacobian),
            ("local", check.local),
            ("local_jacobian", check.local_jacobian),
        ] {
            assert!(error <= DUAL_TOLERANCE, "{name}: {what} {error:e}");
        }
        // The identity holds on the manifold. g2o's poses are sampled as its
        // six-digit files hold them, quaternions of norm 1 ± 1e-6, where
        // `t ← t + R(q) δρ` and its inverse scale by |q|⁴ (`between`
        // checks the same chart at unit quaternions).
        let inverse = if name == G2oSe3Edge::NAME {
            1e-5
        } else {
            DUAL_TOLERANCE
        };
        assert!(check.inverse <= inverse, "{name}: {check:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
