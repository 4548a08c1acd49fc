//! Kernels in a host solver's chart and layout ([`factor_core::host`]).
//!
//! The residual is traced as [`factor_core::host::host_residual`] computes
//! it: every host part's parameters are inputs, each retracted to first
//! order in the host's chart by its slice of a symbolic tangent, mapped to
//! the variable's stored scalars by its [`factor_core::host::HostMap`], and
//! the factor's own residual evaluated there. Differentiated at `δ = 0`
//! (with the same cheapest-form search as the factor's own kernel), each
//! host part's block is exact in the host's tangent, whatever chart the
//! factor was written in; the blocks are column-major, so consecutive ones
//! tile the host's column-major Jacobian.

use factor_core::host::{Host, HostFactor, HostInput, HostLayout, HostManifold, host_residual};
use factor_core::{FieldInfo, Perturbation, VariableInfo};
use factor_symbolic::trace::Traced;
use factor_symbolic::{Expr, Tracer};

use crate::kernel::{BlockOrder, SymbolicKernel, assemble};

/// One input array of a host kernel, as its documentation describes it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HostInputDoc {
    /// The argument's name: the field, or `<field>_<part>`.
    pub name: String,
    /// How many scalars.
    pub scalars: usize,
    /// What it holds: a constant's stored layout, or the host manifold with
    /// its parameter layout.
    pub holds: String,
    /// Where a solver's entry takes it from.
    pub source: HostSource,
}

/// Where the host entry (`<factor>_<host>_host`) takes an input array from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum HostSource {
    /// A constant: this range of the factor's stored scalars.
    Stored(std::ops::Range<usize>),
    /// A host part: the parameter slice of this index.
    Part(usize),
}

/// One Jacobian block of a host kernel.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HostBlockDoc {
    /// The argument's name, `d_<input>`.
    pub name: String,
    /// The host manifold (`SE3`).
    pub manifold: String,
    /// Its tangent columns.
    pub columns: usize,
    /// The tangent in words.
    pub tangent: &'static str,
}

/// A factor traced in a host's chart.
#[derive(Debug, Clone)]
pub struct HostTrace {
    /// The host's [`Host::NAME`].
    pub host: &'static str,
    /// The solver, in words.
    pub solver: &'static str,
    /// Residual and column-major blocks over the host inputs. Its `fields`
    /// hold one entry per input array and its `blocks` one per host part
    /// (their names are the factor's fields'; [`HostTrace::inputs`] and
    /// [`HostTrace::blocks`] name them in the kernel).
    pub kernel: SymbolicKernel,
    /// The input arrays in order.
    pub inputs: Vec<HostInputDoc>,
    /// The blocks in order.
    pub blocks: Vec<HostBlockDoc>,
    /// The factor's stored scalars (the host entry's `stored`).
    pub stored: usize,
}

/// Traces factor `F` in host `H`'s chart (see the module documentation).
pub fn trace_on_host<F: HostFactor<H>, H: Host>() -> HostTrace {
    let layout = HostLayout::of::<F, H>();
    let tracer = Tracer::new();
    let mut next = 0u32;
    let inputs: Vec<Vec<Expr>> = layout
        .inputs
        .iter()
        .map(|input| {
            (0..input.len())
                .map(|_| {
                    next += 1;
                    Expr::input(next - 1)
                })
                .collect()
        })
        .collect();
    let input_len = next;
    let columns = u32::try_from(layout.columns()).expect("fewer than 2³² columns");
    let delta: Vec<Expr> = (0..columns).map(|j| Expr::input(input_len + j)).collect();
    let slices: Vec<&[Expr]> = inputs.iter().map(Vec::as_slice).collect();
    let residual = host_residual::<F, H, Expr>(&layout, &slices, &delta);
    let at_zero = delta.iter().map(|d| (*d, Expr::constant(0.0))).collect();
    let traced = Traced {
        residual,
        delta,
        input_len,
        at_zero,
    };
    let fields = F::fields();
    let field_named = |name: &str| {
        fields
            .iter()
            .find(|f| f.name == name)
            .expect("a layout's field is one of the factor's")
    };
    let mut kernel_fields = Vec::with_capacity(layout.inputs.len());
    let mut parts = Vec::with_capacity(layout.parts.len());
    let mut docs = Vec::with_capacity(layout.inputs.len());
    let mut blocks = Vec::with_capacity(layout.parts.len());
    for input in &layout.inputs {
        let (field, holds, source) = match input {
            HostInput::Constant { field, stored } => {
                let info = field_named(field);
                (
                    *field,
                    format!("`{}`", info.layout),
                    HostSource::Stored(stored.clone()),
                )
            }
            HostInput::Part {
                field, part, index, ..
            } => {
                let holds = format!("{} `{}`", part.manifold, part.manifold.parameter_layout());
                parts.push(VariableInfo {
                    name: field,
                    type_name: field_named(field).name,
                    tangent_dim: part.manifold.dof(),
                    perturbation: Perturbation::Right,
                    tangent: part.manifold.tangent_description(),
                });
                blocks.push(HostBlockDoc {
                    name: format!("d_{}", input.name()),
                    manifold: part.manifold.to_string(),
                    columns: part.manifold.dof(),
                    tangent: part.manifold.tangent_description(),
                });
                (*field, holds, HostSource::Part(*index))
            }
        };
        let info = field_named(field);
        kernel_fields.push(FieldInfo {
            scalars: input.len(),
            ..info.clone()
        });
        docs.push(HostInputDoc {
            name: input.name(),
            scalars: input.len(),
            holds,
            source,
        });
    }
    HostTrace {
        host: H::NAME,
        solver: H::SOLVER,
        kernel: assemble(
            tracer,
            F::NAME,
            kernel_fields,
            parts,
            traced,
            BlockOrder::ColumnMajor,
        ),
        inputs: docs,
        blocks,
        stored: layout.stored,
    }
}

/// What to generate for one host: its name and its trace.
#[derive(Debug, Clone, Copy)]
pub struct HostSpec {
    /// The host's [`Host::NAME`]: the kernel is `<factor>_<name>`.
    pub name: &'static str,
    /// Traces the factor in the host's chart.
    pub trace: fn() -> HostTrace,
}

impl HostSpec {
    /// Factor `F` in host `H`'s chart.
    pub fn of<F: HostFactor<H>, H: Host>() -> HostSpec {
        HostSpec {
            name: H::NAME,
            trace: trace_on_host::<F, H>,
        }
    }
}
