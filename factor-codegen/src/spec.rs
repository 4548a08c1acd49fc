//! What gets generated: one [`KernelSpec`] per factor, and the
//! [`Provenance`] the generated files name.

use factor_core::Factor;

use crate::ambient::trace_ambient;
use crate::chart::{ChartTrace, trace_charts};
use crate::error::CodegenError;
use crate::host::HostSpec;
use crate::kernel::{SymbolicKernel, trace};

/// A factor to generate a kernel for: [`KernelSpec::of`] for any factor
/// type; everything the kernel's module says about its inputs comes from the
/// factor's own definition (each field's [`factor_core::Storage`] layout and
/// documentation).
#[derive(Debug, Clone)]
pub struct KernelSpec {
    /// The module and function name in the generated crate: the factor's
    /// [`factor_core::Factor::NAME`].
    pub name: &'static str,
    /// The factor type's path, for the module header.
    pub source_type: &'static str,
    /// Where the residual comes from, for the module header: by default the
    /// first paragraph of the factor type's documentation.
    pub source: &'static str,
    /// Traces the factor type.
    pub trace: fn() -> SymbolicKernel,
    /// Whether the module also holds the fused normal-equation kernel
    /// ([`KernelSpec::with_normal_equations`]).
    pub normal_equations: bool,
    /// The host charts the module also has kernels for
    /// ([`KernelSpec::with_host`]).
    pub hosts: Vec<HostSpec>,
    /// Traces the factor's ambient kernel ([`crate::ambient`]), for its
    /// Ceres cost function.
    pub ambient: fn() -> SymbolicKernel,
    /// Traces its variables' charts ([`crate::chart`]), for their Ceres
    /// manifolds.
    pub charts: fn() -> Result<Vec<ChartTrace>, CodegenError>,
    /// Whether its C++ has a Ceres cost function and manifolds
    /// ([`KernelSpec::with_ceres`]).
    pub ceres: bool,
}

impl KernelSpec {
    /// The spec of factor type `F`.
    pub fn of<F: Factor>() -> KernelSpec {
        KernelSpec {
            name: F::NAME,
            source_type: F::TYPE_PATH,
            source: F::DESCRIPTION,
            trace: trace::<F>,
            normal_equations: false,
            hosts: Vec::new(),
            ambient: trace_ambient::<F>,
            charts: trace_charts::<F>,
            ceres: false,
        }
    }

    /// The same spec naming `source` (a document and its equations, say) as
    /// where the residual comes from.
    pub fn with_source(self, source: &'static str) -> KernelSpec {
        KernelSpec { source, ..self }
    }

    /// The same spec with the fused normal-equation kernel
    /// `<name>_normal` beside the Jacobian kernel ([`crate::normal`]): for a
    /// per-factor weight `w`, the cost `½ w rᵀr`, the gradient blocks
    /// `Jᵢᵀ w r` and the upper triangle of `JᵀwJ`, block by block.
    pub fn with_normal_equations(self) -> KernelSpec {
        KernelSpec {
            normal_equations: true,
            ..self
        }
    }
}

impl KernelSpec {
    /// The same spec with a kernel in a host's chart and layout beside the
    /// factor's own ([`crate::host`]): `<name>_<host>`, reading the host's
    /// parameter arrays and writing column-major blocks, one per host part
    /// (`HostSpec::of::<F, Apex>()` for apex-solver). The factor names the
    /// host in `#[factor(kernel = …, hosts(apex))]`.
    pub fn with_host(mut self, host: HostSpec) -> KernelSpec {
        self.hosts.push(host);
        self
    }

    /// The same spec with, in its C++ (`generate --lang cpp`,
    /// [`crate::cpp`]), a Ceres cost function whose parameter blocks are the
    /// variables' stored scalars and a Ceres manifold per variable type in
    /// the factor's own chart. Every variable's type must give
    /// [`factor_core::Manifold::local`] (the C++ generation refuses it
    /// otherwise, naming the type).
    pub fn with_ceres(self) -> KernelSpec {
        KernelSpec {
            ceres: true,
            ..self
        }
    }
}

/// Where a generated crate comes from, as its files say: what the crate
/// holds, and the commands that regenerate and check it.
///
/// A crate of kernels names its generator with [`Provenance::new`] (see the
/// crate documentation, "Kernels of your own factors").
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
}

impl Provenance {
    /// A crate holding `description`, written by the command `generate` and
    /// checked by `check`. Each module's header states the conventions of
    /// its own inputs and variables (quaternion order, each block's tangent).
    pub const fn new(
        description: &'static str,
        generate: &'static str,
        check: &'static str,
    ) -> Provenance {
        Provenance {
            description,
            generate,
            check,
        }
    }
}
