//! The C++ of `user-kernels/cpp` (`user-cli generate --lang cpp`) against
//! the Rust, when a C++ compiler is present (`g++`, or `$CXX`): every
//! emitted function, in `double` and `float`, compiles with `-Wall -Wextra
//! -Werror`; each factor's kernel in `double` equals its Rust kernel
//! within 1e-13 relative at 2000 configurations; the ambient kernels and
//! the charts of the crate's own Sim(3) and S² (and of `factor-core`'s
//! poses and rotations) equal their Rust definitions and dual numbers at
//! 200.
#![cfg(feature = "kernels")]

use std::path::Path;

use factor_testing::cpp::{Driver, calls, compiler, expected};
use factor_testing::samples::Sampler;
use user_factors::{Direction, PointToPlane, RelativePose, RelativeSim3, ScaledRangeBearing};

use crate::generated::{point_to_plane, relative_pose, scaled_range_bearing};
use crate::manifold_factors::{direction, relative_sim3};

const CONFIGURATIONS: usize = 2000;
const FEW: usize = 200;

/// `CONFIGURATIONS` samples from `sample`, seeded.
fn samples<F>(seed: u64, sample: fn(&mut Sampler, usize) -> F) -> Vec<F> {
    let mut sampler = Sampler::new(seed);
    (0..CONFIGURATIONS)
        .map(|i| sample(&mut sampler, i))
        .collect()
}

#[test]
fn the_generated_cpp_compiles_warning_free_and_equals_the_rust_kernels() {
    let Some(compiler) = compiler() else {
        eprintln!("no C++ compiler (g++, or $CXX): user-kernels/cpp is not compiled here");
        return;
    };
    let include = Path::new(env!("CARGO_MANIFEST_DIR")).join("../user-kernels/cpp");
    let library = include.join("user_kernels");
    let mut all = calls::<RelativePose>(&library);
    all.extend(calls::<PointToPlane>(&library));
    all.extend(calls::<ScaledRangeBearing>(&library));
    all.extend(calls::<Direction>(&library));
    all.extend(calls::<RelativeSim3>(&library));
    for chart in ["sim3_left", "unit_vector3_left", "so3_left", "se3_left"] {
        let retract = format!("{chart}_retract");
        assert!(
            all.iter().any(|c| c.function == retract),
            "{chart} is not checked"
        );
    }
    let dir = std::env::temp_dir().join(format!("user-factors-cpp-{}", std::process::id()));
    // The compiler runs while the Rust side is computed.
    let pending = Driver::spawn(
        &compiler,
        &include,
        "user_kernels/kernels.h",
        "user_kernels",
        all,
        &dir,
    )
    .unwrap_or_else(|e| panic!("the C++ compiler does not start: {e}"));
    let expected = [
        expected(&samples(31, relative_pose), FEW),
        expected(&samples(32, point_to_plane), FEW),
        expected(&samples(33, scaled_range_bearing), FEW),
        expected(&samples(34, direction), FEW),
        expected(&samples(35, relative_sim3), FEW),
    ];
    let driver = pending
        .wait()
        .unwrap_or_else(|diagnostics| panic!("user-kernels/cpp does not compile:\n{diagnostics}"));
    let checks = expected.iter().map(|e| (e.name(), e.check(&driver)));
    for (name, check) in checks {
        eprintln!("{name}: {check:?}");
        assert!(check.kernel <= 1e-13, "{name}: {check:?}");
        assert!(check.kernel_float <= 1e-4, "{name}: {check:?}");
        assert!(check.worst_double() <= 1e-12, "{name}: {check:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
