//! What gets generated: one [`KernelSpec`] per factor ([`document_kernels`]
//! for the document factors), and the [`Provenance`] the generated files
//! name.

use crate::symbolic::{SymbolicKernel, trace};
use crate::testing::samples::Sampler;

/// A factor to generate a kernel for.
///
/// For a factor `F` of any crate: `name: <F as Factor>::NAME`, and
/// `trace: || factor_core::symbolic::trace(&template)` with any value
/// `template: F` (only its type is traced).
#[derive(Debug, Clone, Copy)]
pub struct KernelSpec {
    /// The module and function name in the generated crate: the factor's
    /// [`crate::Factor::NAME`].
    pub name: &'static str,
    /// The factor type's path, for the module header.
    pub source_type: &'static str,
    /// Where the residual is defined: document and section, equations.
    pub document: &'static str,
    /// Each field's input layout, in declaration order: the field name and
    /// its scalars in [`crate::MapScalars`] order.
    pub inputs: &'static [(&'static str, &'static str)],
    /// Traces the factor type (the values of the template are irrelevant).
    pub trace: fn() -> SymbolicKernel,
}

/// Where a generated crate comes from, as its files say: what the crate
/// holds, and the commands that regenerate and check it.
///
/// [`Provenance::SLAMJAC`] is that of `generated/` (the document factors,
/// `slamjac generate`); a crate of a user's own factors names its own
/// generator with [`Provenance::new`] (see [`crate::codegen`], "Kernels of
/// your own factors").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Provenance {
    /// What the crate holds: the first paragraph of its `lib.rs`
    /// documentation, Markdown, one `//!` line per `\n`-separated line.
    pub description: &'static str,
    /// The command that writes the crate, quoted in every file's
    /// "do not edit" note.
    pub generate: &'static str,
    /// The command that fails when the crate is stale.
    pub check: &'static str,
    /// The conventions paragraph of each module's header.
    pub conventions: &'static str,
}

impl Provenance {
    /// `generated/`, the kernels of the document factors.
    pub const SLAMJAC: Provenance = Provenance {
        description: "Residual-and-Jacobian kernels of the document factors, generated from their\n\
                      definitions in `factor-core`.",
        generate: "slamjac generate",
        check: "slamjac check",
        conventions: "Conventions: quaternions `[x, y, z, w]`, Hamilton product, active rotation; \
                      poses of document 000 map world to camera (`X_c = R X_w + t`); pose \
                      tangents `[δω, δρ]`, rotation first; each block is the derivative of \
                      `r(x ⊞ δ)` at `δ = 0` on the variable's perturbation side.",
    };

    /// The conventions every factor built on `factor_core`'s types follows.
    pub const CONVENTIONS: &'static str = "Conventions: quaternions `[x, y, z, w]`, Hamilton \
        product, active rotation; pose tangents `[δω, δρ]`, rotation first; each block is the \
        derivative of `r(x ⊞ δ)` at `δ = 0` on the variable's perturbation side.";

    /// A crate holding `description`, written by the command `generate` and
    /// checked by `check`, with the library's [`Provenance::CONVENTIONS`].
    pub const fn new(
        description: &'static str,
        generate: &'static str,
        check: &'static str,
    ) -> Provenance {
        Provenance {
            description,
            generate,
            check,
            conventions: Provenance::CONVENTIONS,
        }
    }
}

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
            source_type: "factor_core::factors::PointReprojection",
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
            source_type: "factor_core::factors::LineReprojection",
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
            source_type: "factor_core::factors::PluckerLineReprojection",
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
            source_type: "factor_core::factors::PlaneFactor",
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
            source_type: "factor_core::factors::FreeLineFactor",
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

/// The spec named `name`.
pub fn find(name: &str) -> Option<KernelSpec> {
    document_kernels()
        .into_iter()
        .find(|spec| spec.name == name)
}
