//! The document factors' kernels: what `slamjac generate` writes into
//! `generated/`, through the public generator API of `factor-codegen`, as
//! any user's generator does.

use factor_codegen::{GeneratedModule, KernelSpec, Provenance, generate_with, trace};
use factor_testing::samples::Sampler;

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

/// `[qx, qy, qz, qw, tx, ty, tz]`: an SE(3) pose as stored.
const POSE: &str = "[qx, qy, qz, qw, tx, ty, tz] (unit quaternion [x, y, z, w], then translation)";
/// `[fu, fv, cu, cv]`.
const INTRINSICS: &str = "[fu, fv, cu, cv]";
/// A pixel.
const PIXEL: &str = "[u, v] (pixels)";

/// The five factors of `factor_core::factors`, in the order `list` shows them.
pub fn document_kernels() -> Vec<KernelSpec> {
    vec![
        KernelSpec {
            name: "point_reprojection",
            source_type: "slam_factors::PointReprojection",
            document: "document 000 §II (2)–(5)",
            inputs: &[
                ("intrinsics", INTRINSICS),
                ("observed", PIXEL),
                ("pose", POSE),
                ("point", "[X, Y, Z] (world)"),
            ],
            trace: || trace(&Sampler::new(0).point_reprojection()),
        },
        KernelSpec {
            name: "line_reprojection",
            source_type: "slam_factors::LineReprojection",
            document: "document 000 §III (6)–(12)",
            inputs: &[
                ("intrinsics", INTRINSICS),
                ("start", PIXEL),
                ("end", PIXEL),
                ("pose", POSE),
                (
                    "line",
                    "[ux, uy, uz, uw, w1, w2] (U ∈ SO(3) as a unit quaternion [x, y, z, w], \
                     W ∈ SO(2) as (cos, sin))",
                ),
            ],
            trace: || trace(&Sampler::new(0).line_reprojection()),
        },
        KernelSpec {
            name: "plucker_line_reprojection",
            source_type: "slam_factors::PluckerLineReprojection",
            document: "document 000 §III (6)–(8), raw Plücker [n, v]",
            inputs: &[
                ("intrinsics", INTRINSICS),
                ("start", PIXEL),
                ("end", PIXEL),
                ("pose", POSE),
                (
                    "line",
                    "[nx, ny, nz, vx, vy, vz] (Plücker normal n, direction v)",
                ),
            ],
            trace: || trace(&Sampler::new(0).plucker_line_reprojection()),
        },
        KernelSpec {
            name: "plane",
            source_type: "slam_factors::PlaneFactor",
            document: "document 000 §IV (13)",
            inputs: &[
                ("measured", "[a, b, c, d] (camera frame, any scale)"),
                ("pose", POSE),
                (
                    "plane",
                    "[qx, qy, qz, qw] (the plane as a unit quaternion q_w)",
                ),
            ],
            trace: || trace(&Sampler::new(0).plane()),
        },
        KernelSpec {
            name: "free_line",
            source_type: "slam_factors::FreeLineFactor",
            document: "document 001 §3–4",
            inputs: &[
                ("extrinsics", "[qx, qy, qz, qw, tx, ty, tz] (T_CB)"),
                ("bearing_start", "[x, y, z] (camera frame)"),
                ("bearing_end", "[x, y, z] (camera frame)"),
                ("body_pose", "[qx, qy, qz, qw, tx, ty, tz] (T_BW)"),
                (
                    "line",
                    "[qx, qy, qz, qw, d] (q_WL as [x, y, z, w], then d_L)",
                ),
            ],
            trace: || trace(&Sampler::new(0).free_line()),
        },
    ]
}

/// The spec of the document factor named `name`.
pub fn find(name: &str) -> Option<KernelSpec> {
    document_kernels()
        .into_iter()
        .find(|spec| spec.name == name)
}

/// Every document kernel, generated in [`document_kernels`] order.
pub fn generate_all() -> Vec<GeneratedModule> {
    document_kernels()
        .iter()
        .map(|spec| generate_with(spec, &PROVENANCE))
        .collect()
}
