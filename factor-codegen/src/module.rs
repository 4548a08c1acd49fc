//! A factor's kernel from its trace to its formatted module source.

use crate::emit::module_source;
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
    /// The generator its header names, and the crate's `lib.rs` with it.
    pub provenance: Provenance,
}

/// Operation counts of `spec`'s kernel without emitting it: the whole kernel
/// (residual and every block), and the residual alone.
pub fn operation_counts(spec: &KernelSpec) -> (OpCounts, OpCounts) {
    let kernel = (spec.trace)();
    let blocks: Vec<Vec<_>> = kernel.blocks.iter().map(|b| b.entries.clone()).collect();
    let lowered = lower(&kernel.graph, &kernel.residual, &blocks);
    (
        lowered.counts(&lowered.outputs()),
        lowered.counts(&lowered.residual),
    )
}

/// Lowers, schedules, emits and formats `kernel` as described by `spec`,
/// naming `provenance`'s generator.
pub fn generate_module(
    kernel: &SymbolicKernel,
    spec: &KernelSpec,
    provenance: &Provenance,
) -> GeneratedModule {
    let blocks: Vec<Vec<_>> = kernel.blocks.iter().map(|b| b.entries.clone()).collect();
    let lowered = lower(&kernel.graph, &kernel.residual, &blocks);
    let schedule = schedule(&lowered);
    GeneratedModule {
        name: spec.name,
        source_type: spec.source_type,
        source: module_source(kernel, spec, provenance, &lowered, &schedule),
        counts: lowered.counts(&lowered.outputs()),
        residual_counts: lowered.counts(&lowered.residual),
        provenance: *provenance,
    }
}

/// Traces the factor of `spec` and generates its module for a crate written
/// by `provenance`'s generator: the entry point for a user's own factors
/// (see the crate documentation). Pass the modules of one crate, all with the same
/// provenance, to [`crate::write_crate`] or [`crate::check_crate`].
///
/// # Panics
///
/// If the traced factor's name is not `spec.name`, or a field has no layout
/// in `spec.inputs`, or a field's name collides with one the kernel uses
/// (`residual`, `d_<variable>`, `v<n>`, `T`).
pub fn generate_with(spec: &KernelSpec, provenance: &Provenance) -> GeneratedModule {
    let kernel = (spec.trace)();
    assert_eq!(
        kernel.name, spec.name,
        "the spec names the factor's kernel after the factor"
    );
    for field in &kernel.fields {
        assert!(
            spec.inputs.iter().any(|(name, _)| *name == field.name),
            "{}: no input layout for field `{}`",
            spec.name,
            field.name
        );
    }
    assert_eq!(
        spec.inputs.len(),
        kernel.fields.len(),
        "{}: one input layout per field",
        spec.name
    );
    generate_module(&kernel, spec, provenance)
}
