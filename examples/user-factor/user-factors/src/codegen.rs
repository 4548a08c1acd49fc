//! What `generate-kernels` generates: one [`KernelSpec`] per factor of this
//! crate, named by [`PROVENANCE`], written into the crate `user-kernels`.
//!
//! A new factor with a kernel needs an entry in [`kernel_specs`] and a
//! `#[cfg_attr(feature = "kernels", factor(kernel = user_kernels::<name>::<name>))]`
//! on its struct; then regenerate (see the crate documentation).

use std::path::{Path, PathBuf};

use factor_codegen::trace;
use factor_codegen::{self as codegen, GeneratedModule, KernelSpec, Provenance};
use factor_core::Factor;
use factor_core::lie::Se3;
use nalgebra::Vector3;

use crate::{PointToPlane, RelativePose, ScaledRangeBearing};

/// What the generated files say about where they come from.
pub const PROVENANCE: Provenance = Provenance::new(
    "Residual-and-Jacobian kernels of the factors of `user-factors`, generated from\n\
     their definitions there.",
    "cargo run -p user-factors --bin generate-kernels",
    "cargo run -p user-factors --bin generate-kernels -- --check",
);

/// A pose as stored: `[qx, qy, qz, qw, tx, ty, tz]`.
const POSE: &str = "[qx, qy, qz, qw, tx, ty, tz] (unit quaternion [x, y, z, w], then translation)";

/// One spec per factor with a kernel. The templates' values are irrelevant:
/// only the factor's type is traced.
pub fn kernel_specs() -> Vec<KernelSpec> {
    vec![
        KernelSpec {
            name: <RelativePose as Factor>::NAME,
            source_type: "user_factors::RelativePose",
            document: "pose-graph relative pose, r = Log(T̃_ij⁻¹ T_i⁻¹ T_j)",
            inputs: &[
                ("measured", POSE),
                ("pose_i", "[qx, qy, qz, qw, tx, ty, tz] (T_i)"),
                ("pose_j", "[qx, qy, qz, qw, tx, ty, tz] (T_j)"),
            ],
            trace: || {
                trace(&RelativePose {
                    measured: Se3::identity(),
                    pose_i: Se3::identity(),
                    pose_j: Se3::identity(),
                })
            },
        },
        KernelSpec {
            name: <PointToPlane as Factor>::NAME,
            source_type: "user_factors::PointToPlane",
            document: "point-to-plane ICP, r = nᵀ(T p − q)",
            inputs: &[
                ("point", "[x, y, z] (scan frame)"),
                ("plane_point", "[x, y, z] (map frame)"),
                ("normal", "[x, y, z] (map frame, unit)"),
                ("pose", "[qx, qy, qz, qw, tx, ty, tz] (scan to map)"),
            ],
            trace: || {
                trace(&PointToPlane {
                    point: Vector3::zeros(),
                    plane_point: Vector3::zeros(),
                    normal: Vector3::z(),
                    pose: Se3::identity(),
                })
            },
        },
        KernelSpec {
            name: <ScaledRangeBearing as Factor>::NAME,
            source_type: "user_factors::ScaledRangeBearing",
            document: "range-bearing with a range scale, r = [atan(y/x), asin(z/ρ), ln(e^λ ρ)] − measured",
            inputs: &[
                ("landmark", "[x, y, z] (world frame)"),
                ("measured", "[azimuth, elevation, log range]"),
                ("pose", "[qx, qy, qz, qw, tx, ty, tz] (world to sensor)"),
                ("log_scale", "[λ] (range scale exp(λ))"),
            ],
            trace: || {
                trace(&ScaledRangeBearing {
                    landmark: Vector3::x(),
                    measured: Vector3::zeros(),
                    pose: Se3::identity(),
                    log_scale: 0.0,
                })
            },
        },
    ]
}

/// Every kernel's module, in [`kernel_specs`] order.
pub fn generate() -> Vec<GeneratedModule> {
    kernel_specs()
        .iter()
        .map(|spec| codegen::generate_with(spec, &PROVENANCE))
        .collect()
}

/// The crate `user-kernels`, beside this crate in the source tree.
pub fn default_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the crate directory has a parent")
        .join("user-kernels")
}

/// Writes the crate's sources under `dir/src` (only files that changed;
/// stray `.rs` files there are removed).
///
/// # Errors
///
/// Any I/O error.
pub fn write(dir: &Path) -> std::io::Result<Vec<GeneratedModule>> {
    let modules = generate();
    codegen::write_crate(dir, &modules)?;
    Ok(modules)
}

/// Compares `dir/src` with what [`write()`] would write: the modules when
/// current, else every differing, missing or extra file.
pub fn check(dir: &Path) -> Result<Vec<GeneratedModule>, Vec<PathBuf>> {
    let modules = generate();
    codegen::check_crate(dir, &modules)?;
    Ok(modules)
}
