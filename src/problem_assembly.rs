//! How a problem file's factor entries become factors of an apex-solver
//! problem (feature `solve`): the adder a registry keeps per factor
//! ([`AddFn`]: through the factor's generated kernel in apex-solver's
//! chart, or dual numbers in that chart), the problem variables they create
//! and the problem being assembled. `crate::solve::problem_file` reads the
//! file and drives it; [`crate::registry`] stores the adders.

use std::collections::HashMap;

use factor_apex::builder::{AnyVariable, Noise, ProblemBuilder, Values, stored_value_of};
use factor_apex::problems::{BuildError, Robust};
use factor_core::FieldInfo;
use factor_core::host::{Apex, HostFactor, HostKernel, HostManifold};

use crate::decode::decode;
use crate::error::CliError;
use crate::input::Object;
use crate::observability::tangent_columns;

/// Reads a variable's stored scalars back from a solution.
pub(crate) type ReadBack = fn(&Values, &AnyVariable, usize) -> Vec<f64>;

/// A problem variable once a factor has created it.
pub(crate) struct Created {
    pub(crate) variable: AnyVariable,
    /// The factor variable it was created as: its field (layouts) and how
    /// to read it back.
    pub(crate) field: FieldInfo,
    pub(crate) index: usize,
    pub(crate) read_back: ReadBack,
    /// Its tangent coordinates in apex-solver's chart, named (the
    /// observability check's columns).
    pub(crate) columns: Vec<String>,
}

/// What a factor entry needs while it is added.
pub(crate) struct Assembly {
    pub(crate) builder: ProblemBuilder,
    pub(crate) created: HashMap<String, Created>,
    /// How many factors go through generated kernels, how many through
    /// dual numbers, so far.
    pub(crate) linearized_by: [usize; 2],
    /// Whether factors with a kernel go through it (not `--kernels dual`).
    pub(crate) kernels: bool,
}

/// One factor entry of a problem file, checked: its `variables` (by
/// field, the problem variables' values) and `constants` objects, the
/// problem variable named for each variable field, its noise model and
/// loss.
pub(crate) struct Entry<'a> {
    pub(crate) variables: &'a Object<'a>,
    pub(crate) constants: &'a Object<'a>,
    pub(crate) names: &'a [(String, String)],
    pub(crate) noise: &'a Noise,
    pub(crate) loss: Option<Robust>,
}

/// How a registered factor is added from a problem file
/// ([`crate::registry::Registry::solve_with_kernel`],
/// [`crate::registry::Registry::solve_with_dual`]).
pub(crate) type AddFn = fn(&mut Assembly, &Entry) -> Result<(), CliError>;

/// The factor's variables as problem variables: created from the factor's
/// value of them at the first factor that names them.
fn variables_of<F: HostFactor<Apex> + 'static>(
    assembly: &mut Assembly,
    factor: &F,
    names: &[(String, String)],
) -> Vec<AnyVariable> {
    let fields = F::fields();
    names
        .iter()
        .enumerate()
        .map(|(index, (_, name))| {
            if let Some(created) = assembly.created.get(name) {
                return created.variable.clone();
            }
            let variable = assembly.builder.add_variable_of(factor, index);
            let field = fields
                .iter()
                .find(|f| f.variable == Some(index))
                .cloned()
                .expect("every variable is a field");
            let parts = F::host_parts(index);
            let columns = parts
                .iter()
                .flat_map(|part| {
                    let columns =
                        tangent_columns(part.manifold.tangent_description(), part.manifold.dof());
                    columns.into_iter().map(move |c| {
                        if part.name.is_empty() {
                            c
                        } else {
                            format!("{}.{c}", part.name)
                        }
                    })
                })
                .collect();
            assembly.created.insert(
                name.clone(),
                Created {
                    variable: variable.clone(),
                    field,
                    index,
                    read_back: stored_value_of::<F>,
                    columns,
                },
            );
            variable
        })
        .collect()
}

/// [`AddFn`] through `F`'s generated kernel in apex-solver's chart.
pub(crate) fn add_kernel<F: HostKernel<Apex> + 'static>(
    assembly: &mut Assembly,
    entry: &Entry,
) -> Result<(), CliError> {
    add_with(assembly, entry, ProblemBuilder::add_factor::<F>)
}

/// [`AddFn`] through dual numbers in apex-solver's chart.
pub(crate) fn add_dual<F: HostFactor<Apex> + 'static>(
    assembly: &mut Assembly,
    entry: &Entry,
) -> Result<(), CliError> {
    add_with(assembly, entry, ProblemBuilder::add_factor_dual::<F>)
}

/// How [`ProblemBuilder`] adds a factor of type `F`.
type BuilderAdd<F> =
    fn(&mut ProblemBuilder, &F, &[AnyVariable], &Noise, Option<Robust>) -> Result<(), BuildError>;

/// Decodes `F` from `entry`, creates its variables, and adds it by `add`.
fn add_with<F: HostFactor<Apex> + 'static>(
    assembly: &mut Assembly,
    entry: &Entry,
    add: BuilderAdd<F>,
) -> Result<(), CliError> {
    let factor: F = decode(entry.variables, entry.constants)?;
    let keys = variables_of(assembly, &factor, entry.names);
    add(
        &mut assembly.builder,
        &factor,
        &keys,
        entry.noise,
        entry.loss,
    )
    .map_err(build_error)
}

/// A builder's refusal as the command line reports it.
pub(crate) fn build_error(error: BuildError) -> CliError {
    match error {
        BuildError::Degenerate { error, .. } => CliError::Factor(error),
        other => CliError::Solve(other.to_string()),
    }
}
