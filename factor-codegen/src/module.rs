//! A factor's kernel from its trace to its formatted module source.

use crate::emit::module_source;
use crate::error::CodegenError;
use crate::ir::OpCounts;
use crate::kernel::SymbolicKernel;
use crate::lower::lower;
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
/// uses for itself.
pub fn generate_module(
    kernel: &SymbolicKernel,
    spec: &KernelSpec,
    provenance: &Provenance,
) -> Result<GeneratedModule, CodegenError> {
    let lowered = lower_kernel(kernel);
    let schedule = schedule(&lowered);
    Ok(GeneratedModule {
        name: spec.name,
        source_type: spec.source_type,
        source: module_source(kernel, spec, provenance, &lowered, &schedule)?,
        counts: lowered.counts(&lowered.outputs()),
        residual_counts: lowered.counts(&lowered.residual),
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
