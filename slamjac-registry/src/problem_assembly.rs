//! How a problem file's factor entries become factors of an apex-solver
//! problem (feature `solve`): the adder a registry keeps per factor
//! ([`AddFn`]: through the factor's generated kernel in apex-solver's
//! chart, or dual numbers in that chart), the problem variables they create
//! and the problem being assembled. `slamjac_solve::problem_file` reads the
//! file and drives it; [`crate::registry`] stores the adders.

use std::collections::HashMap;

use factor_apex::builder::{AnyVariable, Noise, ProblemBuilder, Values, stored_value_of};
use factor_apex::problems::BuildError;
use factor_core::FieldInfo;
use factor_core::dual::Dual;
use factor_core::host::{Apex, HostFactor, HostKernel, HostManifold};
use factor_core::manifold::ChartMap;
use factor_core::nalgebra::DMatrix;
use slam_problems::{ProblemError, Robust};
use slamjac_problem::decode::{FieldsCache, decode_with};
use slamjac_problem::input::Object;
use slamjac_problem::observability::tangent_columns;

use crate::error::RegistryError;

/// Reads a variable's stored scalars back from a solution.
pub type ReadBack = fn(&Values, &AnyVariable, usize) -> Vec<f64>;

/// A variable's own tangent in its host coordinates at given host
/// parameters (`own_tangent_in_host`).
pub type InHost = fn(usize, &[f64]) -> DMatrix<f64>;

/// A problem variable once a factor has created it.
pub struct Created {
    pub variable: AnyVariable,
    /// The factor variable it was created as: its field (layouts) and how
    /// to read it back.
    pub field: FieldInfo,
    pub index: usize,
    pub read_back: ReadBack,
    /// The observability check's columns, named: its tangent coordinates
    /// in apex-solver's chart, or its own tangent's where apex holds it in
    /// more coordinates than its dimension (a direction on S² as `Rn(3)`).
    pub columns: Vec<String>,
    /// Its own tangent in apex's coordinates, where those are more than its
    /// dimension (`own_tangent_in_host` for its factor type).
    pub in_host: Option<InHost>,
}

/// What a factor entry needs while it is added.
pub struct Assembly {
    pub builder: ProblemBuilder,
    pub created: HashMap<String, Created>,
    /// How many factors go through generated kernels, how many through
    /// dual numbers, so far.
    pub linearized_by: [usize; 2],
    /// Whether factors with a kernel go through it (not `--kernels dual`).
    pub kernels: bool,
    pub fields: FieldsCache,
}

/// One factor entry of a problem file, checked: its `variables` (by
/// field, the problem variables' values) and `constants` objects, the
/// problem variable named for each variable field, its noise model and
/// loss.
pub struct Entry<'a> {
    pub variables: &'a Object<'a>,
    pub constants: &'a Object<'a>,
    pub names: &'a [(&'static str, &'a str)],
    pub noise: &'a Noise,
    pub loss: Option<Robust>,
}

/// How a registered factor is added from a problem file
/// ([`crate::registry::Registry::solve_with_kernel`],
/// [`crate::registry::Registry::solve_with_dual`]).
pub type AddFn = fn(&mut Assembly, &Entry) -> Result<(), RegistryError>;

/// The factor's variables as problem variables: created from the factor's
/// value of them at the first factor that names them.
fn variables_of<F: HostFactor<Apex> + 'static>(
    assembly: &mut Assembly,
    factor: &F,
    fields: &[FieldInfo],
    names: &[(&'static str, &str)],
) -> Vec<AnyVariable> {
    names
        .iter()
        .enumerate()
        .map(|(index, (_, name))| {
            if let Some(created) = assembly.created.get(*name) {
                return created.variable.clone();
            }
            let variable = assembly.builder.add_variable_of(factor, index);
            let field = fields
                .iter()
                .find(|f| f.variable == Some(index))
                .cloned()
                .expect("every variable is a field");
            let parts = F::host_parts(index);
            let own = &F::variables()[index];
            let host_dof: usize = parts.iter().map(|p| p.manifold.dof()).sum();
            let reduced = host_dof > own.tangent_dim;
            let columns = if reduced {
                tangent_columns(own.tangent, own.tangent_dim)
            } else {
                parts
                    .iter()
                    .flat_map(|part| {
                        let columns = tangent_columns(
                            part.manifold.tangent_description(),
                            part.manifold.dof(),
                        );
                        columns.into_iter().map(move |c| {
                            if part.name.is_empty() {
                                c
                            } else {
                                format!("{}.{c}", part.name)
                            }
                        })
                    })
                    .collect()
            };
            assembly.created.insert(
                (*name).to_owned(),
                Created {
                    variable: variable.clone(),
                    field,
                    index,
                    read_back: stored_value_of::<F>,
                    columns,
                    in_host: reduced.then_some(own_tangent_in_host::<F> as InHost),
                },
            );
            variable
        })
        .collect()
}

/// Variable `variable` of `F`'s own tangent in apex's coordinates at the
/// host parameters `host` (its parts' end to end): the matrix `B` (apex's
/// tangent × its own) that moves the variable as its own retraction does,
/// `C B = A`, with `C = ∂ stored / ∂ δ_apex` (apex's first-order retraction
/// of each part, then [`HostMap::stored_from_host`](factor_core::host::HostMap::stored_from_host))
/// and `A = ∂ stored / ∂ δ_own` (its own first-order retraction), both by
/// dual numbers. A block's whitened Jacobian in apex's coordinates times
/// `B` is the block over the variable's own tangent: the directions apex
/// holds beyond it (the radius of a direction served as `Rn(3)` and
/// normalised) move no residual by construction and are no deficiency.
/// `B = C⁺ A`: where apex's coordinates could not make a move of its own
/// (`C B ≠ A`, a host map that loses a direction), the nearest move they
/// make.
fn own_tangent_in_host<F: HostFactor<Apex>>(variable: usize, host: &[f64]) -> DMatrix<f64> {
    type D = Dual<1>;
    let parts = F::host_parts(variable);
    let own = F::variables()[variable].tangent_dim;
    let stored_len = F::fields()
        .iter()
        .find(|f| f.variable == Some(variable))
        .map_or(0, |f| f.scalars);
    let host_dof: usize = parts.iter().map(|p| p.manifold.dof()).sum();
    let lifted: Vec<D> = host.iter().map(|x| D::constant(*x)).collect();
    // Column `c` of C: every part retracted with the seed on column `c`.
    let mut c_matrix = DMatrix::zeros(stored_len, host_dof);
    let mut moved = vec![D::constant(0.0); host.len()];
    let mut stored = vec![D::constant(0.0); stored_len];
    for c in 0..host_dof {
        let (mut first_parameter, mut first_column) = (0, 0);
        for part in parts {
            let (n, dof) = (part.manifold.parameters(), part.manifold.dof());
            let delta = seeded(first_column..first_column + dof, c);
            let range = first_parameter..first_parameter + n;
            part.manifold
                .retract_first_order(&lifted[range.clone()], &delta, &mut moved[range]);
            first_parameter += n;
            first_column += dof;
        }
        F::stored_from_host(variable, &moved, &mut stored);
        for (r, s) in stored.iter().enumerate() {
            c_matrix[(r, c)] = s.eps[0];
        }
    }
    let mut point = vec![0.0; stored_len];
    F::stored_from_host(variable, host, &mut point);
    let point: Vec<D> = point.iter().map(|x| D::constant(*x)).collect();
    let mut a_matrix = DMatrix::zeros(stored_len, own);
    for c in 0..own {
        let delta = seeded(0..own, c);
        F::chart_over(
            variable,
            ChartMap::RetractFirstOrder,
            &point,
            &delta,
            &mut stored,
        )
        .expect("a first-order retraction is every variable's");
        for (r, s) in stored.iter().enumerate() {
            a_matrix[(r, c)] = s.eps[0];
        }
    }
    let svd = c_matrix.svd(true, true);
    let floor = 1e-10 * svd.singular_values.max();
    svd.pseudo_inverse(floor)
        .expect("a floor of no negative singular value")
        * a_matrix
}

/// Zero tangent coordinates `columns`, coordinate `seed` (if among them)
/// carrying the one derivative of a [`Dual<1>`].
fn seeded(columns: std::ops::Range<usize>, seed: usize) -> Vec<Dual<1>> {
    columns
        .map(|k| {
            if k == seed {
                Dual::variable(0.0, 0)
            } else {
                Dual::constant(0.0)
            }
        })
        .collect()
}

/// [`AddFn`] through `F`'s generated kernel in apex-solver's chart.
pub fn add_kernel<F: HostKernel<Apex> + 'static>(
    assembly: &mut Assembly,
    entry: &Entry,
) -> Result<(), RegistryError> {
    add_with(assembly, entry, ProblemBuilder::add_factor::<F>)
}

/// [`AddFn`] through dual numbers in apex-solver's chart.
pub fn add_dual<F: HostFactor<Apex> + 'static>(
    assembly: &mut Assembly,
    entry: &Entry,
) -> Result<(), RegistryError> {
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
) -> Result<(), RegistryError> {
    let fields = assembly.fields.of::<F>();
    let factor: F = decode_with(&fields, entry.variables, entry.constants)?;
    let keys = variables_of(assembly, &factor, &fields, entry.names);
    add(
        &mut assembly.builder,
        &factor,
        &keys,
        entry.noise,
        entry.loss,
    )
    .map_err(build_error)
}

/// A builder's refusal as the command line reports it: a factor that cannot
/// be linearized at the initial values (degenerate, or its generated kernel
/// stale in a debug build) is the factor's error, as `eval` reports it (exit
/// 1); anything else the solver's refusal.
pub fn build_error(error: BuildError) -> RegistryError {
    match error {
        BuildError::Problem(ProblemError::Degenerate { error, .. })
        | BuildError::StaleKernel { error, .. } => RegistryError::Factor(error),
        other => RegistryError::Solve(other.to_string()),
    }
}
