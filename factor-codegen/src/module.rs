//! A factor's kernel from its trace to its formatted module source.

use crate::emit::{HostParts, ModuleParts, module_source};
use crate::error::CodegenError;
use crate::ir::OpCounts;
use crate::kernel::SymbolicKernel;
use crate::lower::lower;
use crate::normal::{MAX_VARIABLES, lower_normal};
use crate::schedule::schedule;
use crate::spec::{KernelSpec, Provenance};

/// One generated module: `src/<name>.rs` of the generated crate.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GeneratedModule {
    /// The module's (and its function's) name.
    pub name: &'static str,
    /// The factor type's path.
    pub source_type: &'static str,
    /// The formatted source.
    pub source: String,
    /// Operation counts of the whole kernel (residual and every block).
    pub counts: OpCounts,
    /// Operation counts when every Jacobian argument is `None`.
    pub residual_counts: OpCounts,
    /// Operation counts of the whole normal-equation kernel, when the spec
    /// asks for it ([`KernelSpec::with_normal_equations`]).
    pub normal_counts: Option<OpCounts>,
}

/// Operation counts of `spec`'s kernel without emitting it: the whole kernel
/// (residual and every block), and the residual alone.
pub fn operation_counts(spec: &KernelSpec) -> (OpCounts, OpCounts) {
    let kernel = (spec.trace)();
    let lowered = lower_kernel(&kernel);
    (
        lowered.counts(&lowered.outputs()),
        lowered.counts(&lowered.residual),
    )
}

/// The residual and every block of `kernel` lowered into one program.
fn lower_kernel(kernel: &SymbolicKernel) -> crate::lower::LoweredKernel {
    let blocks: Vec<Vec<_>> = kernel.blocks.iter().map(|b| b.entries.clone()).collect();
    lower(&kernel.graph, &kernel.residual, &blocks)
}

/// Lowers, schedules, emits and formats `kernel` as described by `spec`,
/// naming `provenance`'s generator.
///
/// # Errors
///
/// [`CodegenError::NameCollision`] when a field's name is one the kernel
/// uses for itself; [`CodegenError::TooManyVariables`] for a normal-equation
/// kernel of more than [`MAX_VARIABLES`] variables.
pub fn generate_module(
    kernel: &SymbolicKernel,
    spec: &KernelSpec,
    provenance: &Provenance,
) -> Result<GeneratedModule, CodegenError> {
    let lowered = lower_kernel(kernel);
    let schedule = schedule(&lowered);
    let normal = if spec.normal_equations {
        let variables = kernel.blocks.len();
        if variables > MAX_VARIABLES {
            return Err(CodegenError::TooManyVariables {
                kernel: spec.name,
                variables,
            });
        }
        let tangents: Vec<usize> = kernel
            .blocks
            .iter()
            .map(|b| b.variable.tangent_dim)
            .collect();
        let weight = u32::try_from(kernel.input_len()).expect("fewer than 2³² inputs");
        let normal = lower_normal(&lowered, weight, &tangents);
        let normal_schedule = crate::schedule::schedule(&normal);
        Some((normal, normal_schedule))
    } else {
        None
    };
    let host_programs: Vec<_> = spec
        .hosts
        .iter()
        .map(|host| {
            let trace = (host.trace)();
            let lowered = lower_kernel(&trace.kernel);
            let host_schedule = crate::schedule::schedule(&lowered);
            (trace, lowered, host_schedule)
        })
        .collect();
    let hosts: Vec<HostParts> = host_programs
        .iter()
        .map(|(trace, lowered, schedule)| HostParts {
            trace,
            lowered,
            schedule,
        })
        .collect();
    let parts = ModuleParts {
        kernel,
        spec,
        provenance,
        lowered: &lowered,
        schedule: &schedule,
        normal: normal.as_ref().map(|(n, s)| (n, s)),
        hosts: &hosts,
    };
    Ok(GeneratedModule {
        name: spec.name,
        source_type: spec.source_type,
        source: module_source(&parts)?,
        counts: lowered.counts(&lowered.outputs()),
        residual_counts: lowered.counts(&lowered.residual),
        normal_counts: normal.as_ref().map(|(n, _)| n.counts(&n.outputs())),
    })
}

/// Traces the factor of `spec` and generates its module for a crate written
/// by `provenance`'s generator: the entry point for a user's own factors
/// (see the crate documentation). [`crate::GeneratedCrate`] assembles the
/// modules of one crate.
///
/// # Errors
///
/// As [`generate_module`].
pub fn generate_with(
    spec: &KernelSpec,
    provenance: &Provenance,
) -> Result<GeneratedModule, CodegenError> {
    generate_module(&(spec.trace)(), spec, provenance)
}
