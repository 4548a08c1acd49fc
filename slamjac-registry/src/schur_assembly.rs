//! How a problem file's factor entries become factors of a `factor-schur`
//! problem (feature `solve`): the adder a registry keeps per factor
//! ([`SchurAddFn`]: [`add_schur`] for a factor whose generated kernel has
//! fused normal equations, filled by
//! [`crate::registry::Registry::solve_with_schur`]; [`add_each`] for one
//! linearized one factor at a time, by
//! [`crate::registry::Registry::solve_with_schur_each`]), the problem
//! variables they create (each held in its type's stored scalars and
//! retracted by its own manifold), and what the observability check needs
//! of each factor ([`Kept`]). `slamjac_solve::schur_file` builds the
//! problem with it, and `slamjac`'s `solve` solves it.

use std::collections::HashMap;

use factor_core::geometry::{OrthonormalLine, PluckerLine};
use factor_core::nalgebra::DMatrix;
use factor_core::noise::Noise;
use factor_core::{Factor, FactorError, FieldInfo, Storage, WithKernel};
use factor_lanes::NormalKernel;
use factor_schur::problem::Lane;
use factor_schur::{Jacobians, Problem, SchurError, VariableId};
use slam_factors::{LineReprojection, PluckerLineReprojection};
use slam_problems::{Kernels, Robust};
use slamjac_problem::decode::{FieldsCache, stored_scalars};
use slamjac_problem::observability::tangent_columns;

use crate::error::RegistryError;
use crate::method::{Method, linearize};
use crate::problem_assembly::Entry;

/// A factor's residual and Jacobian blocks over its variables' own
/// tangents (row-major, one per variable) at its stored scalars, written to
/// the slices given (`Factor::linearize_stored_into`).
pub type LinearizeAt = fn(&[f64], &mut [f64], &mut [Option<&mut [f64]>]) -> Result<(), FactorError>;

/// A problem variable once a factor has created it.
pub struct Created {
    pub id: VariableId,
    /// The factor variable it was created as (its layouts).
    pub field: FieldInfo,
    /// Its tangent coordinates' names (the observability check's columns).
    pub columns: Vec<String>,
}

/// What the observability check keeps of a factor: its stored scalars at
/// the initial values, each variable's range among them and its tangent's
/// dimension, its `S`, how to linearize it, and its Jacobian at the initial
/// values (every variable's block, row-major, end to end: the build's, for
/// the check there).
pub struct Kept {
    pub stored: Vec<f64>,
    pub variables: Vec<(VariableId, std::ops::Range<usize>, usize)>,
    pub sqrt_information: DMatrix<f64>,
    pub linearize: LinearizeAt,
    pub initial: Vec<f64>,
}

/// The Schur problem being assembled.
#[derive(Default)]
pub struct SchurAssembly {
    pub problem: Problem,
    pub created: HashMap<String, Created>,
    pub kept: Vec<Kept>,
    /// Factors with per-component or full noise (whitened through the
    /// Jacobian kernel rather than the fused one).
    pub whitened: usize,
    /// Why the Schur-complement solver cannot take the file, once a factor
    /// showed it (two factors perturbing one variable differently: that
    /// solver retracts each variable by one chart, apex-solver by its own).
    pub unsupported: Option<String>,
    /// How the factors are differentiated (`--kernels`).
    pub kernels: Kernels,
    pub fields: FieldsCache,
}

/// How a registered factor is added from a problem file to a Schur
/// problem ([`crate::registry::Registry::solve_with_schur`]).
pub type SchurAddFn = fn(&mut SchurAssembly, &Entry) -> Result<(), RegistryError>;

/// [`SchurAddFn`] of a factor `F` with fused normal-equation kernels: in
/// lane batches, or one at a time by dual numbers under `--kernels dual`
/// (`add_with`).
pub fn add_schur<F>(assembly: &mut SchurAssembly, entry: &Entry) -> Result<(), RegistryError>
where
    F: WithKernel + Send + Sync + 'static,
    F::Kernel: NormalKernel<Lane> + NormalKernel<f64>,
{
    let kernels = assembly.kernels;
    add_with::<F>(assembly, entry, |problem, factor, ids, noise, loss| {
        problem.add_by(factor, ids, noise, loss, kernels)
    })
}

/// [`SchurAddFn`] of any factor `F`, linearized one at a time: through its
/// generated kernel where it has one, else (and under `--kernels dual`) by
/// dual numbers (`add_with`).
pub fn add_each<F>(assembly: &mut SchurAssembly, entry: &Entry) -> Result<(), RegistryError>
where
    F: Factor + Send + Sync + 'static,
{
    let jacobians = Jacobians::from(assembly.kernels);
    add_with::<F>(assembly, entry, |problem, factor, ids, noise, loss| {
        problem.add_linearized(factor, ids, noise, loss, jacobians)
    })
}

/// [`SchurAddFn`] of `plucker_line_reprojection`, whose line is a free
/// 6-vector in its own manifold (it would leave the Klein quadric, and its
/// scale, which no residual sees, would be left undetermined): solved as
/// `line_reprojection`, the same residual (document 000 (6)–(8); `𝒦 n_c`
/// is divided by its own norm, so the line's scale cancels), its line in
/// the orthonormal chart, `(U, W) ∈ SO(3) × SO(2)`, 4 dof. A value off the
/// quadric is put on it first, as the apex path does
/// ([`OrthonormalLine::projected_from_plucker`]); the solved line is
/// written back as Plücker coordinates with a unit direction
/// (`slamjac::solve`'s `value_json`). A line through the world origin
/// (`n = 0`), where the chart is singular (`n = w₁ u₁` does not move as
/// `U` turns about `u₂`), goes to apex-solver, the reason kept in
/// [`SchurAssembly::unsupported`].
pub fn add_plucker_line(assembly: &mut SchurAssembly, entry: &Entry) -> Result<(), RegistryError> {
    let fields = assembly.fields.of::<PluckerLineReprojection>();
    let given = PluckerLineReprojection::from_scalars(&stored_scalars(
        &fields,
        entry.variables,
        entry.constants,
    )?);
    let line = OrthonormalLine::projected_from_plucker(&given.line);
    if line.distance() == 0.0 {
        let (_, name) = entry.names[1];
        assembly.unsupported = Some(format!(
            "variable \"{name}\": the line passes through the world origin, where its \
             orthonormal chart (this solver's) is singular"
        ));
        return Ok(());
    }
    // Refused as the factor it was given as, naming it, at the scale it
    // is solved at (a unit direction: any scale of `[n, v]` is the same
    // line).
    let given = PluckerLineReprojection {
        line: PluckerLine::new(line.moment(), line.direction()),
        ..given
    };
    linearize(&given, Method::Generated)?;
    let factor = LineReprojection {
        intrinsics: given.intrinsics,
        start: given.start,
        end: given.end,
        pose: given.pose,
        line,
    };
    let mut stored = vec![0.0; LineReprojection::<f64>::SCALARS];
    factor.write_scalars(&mut stored);
    let kernels = assembly.kernels;
    add_decoded(
        assembly,
        entry,
        factor,
        stored,
        |problem, factor, ids, noise, loss| problem.add_by(factor, ids, noise, loss, kernels),
    )
}

/// Decodes `entry` as an `F` and adds it ([`add_decoded`]).
fn add_with<F: Factor + 'static>(
    assembly: &mut SchurAssembly,
    entry: &Entry,
    add: impl FnOnce(&mut Problem, &F, &[VariableId], &Noise, Option<Robust>) -> Result<(), SchurError>,
) -> Result<(), RegistryError> {
    let fields = assembly.fields.of::<F>();
    let stored = stored_scalars(&fields, entry.variables, entry.constants)?;
    let factor = F::from_scalars(&stored);
    add_decoded(assembly, entry, factor, stored, add)
}

/// Creates the variables of `factor` (`entry`'s, whose stored scalars are
/// `stored`) at the first factor that names them, and adds it with its
/// noise and loss by `add`. A variable whose chart differs between factors
/// (`SchurError::Chart`) is not an error: the file goes to apex-solver, the
/// reason kept in [`SchurAssembly::unsupported`].
fn add_decoded<F: Factor + 'static>(
    assembly: &mut SchurAssembly,
    entry: &Entry,
    factor: F,
    stored: Vec<f64>,
    add: impl FnOnce(&mut Problem, &F, &[VariableId], &Noise, Option<Robust>) -> Result<(), SchurError>,
) -> Result<(), RegistryError> {
    let fields = assembly.fields.of::<F>();
    // Validated, finite at the initial values, and a finite whitened cost
    // (what the apex path's builder checks); the Jacobian kept for the
    // observability check there.
    let dims = assembly.fields.tangent_dims::<F>();
    let rows = F::RESIDUAL_DIM;
    let mut residual = vec![0.0; rows];
    let mut jacobian = vec![0.0; rows * dims.iter().sum::<usize>()];
    let linearized = F::linearize_stored_into(
        &stored,
        &mut residual,
        &mut blocks_of(&mut jacobian, rows, &dims),
    );
    if let Err(e) = linearized {
        // The refusal as `linearize` words it (the same validation and
        // kernel).
        return Err(linearize(&factor, Method::Generated)
            .err()
            .unwrap_or(e)
            .into());
    }
    // Checked by the file's reader.
    let s = entry.noise.sqrt_information(rows);
    let cost: f64 = (0..rows)
        .map(|r| {
            (0..rows)
                .map(|q| s[(r, q)] * residual[q])
                .sum::<f64>()
                .powi(2)
        })
        .sum();
    if !cost.is_finite() {
        return Err(RegistryError::Factor(FactorError::NonFinite {
            factor: F::NAME,
            what: "cost: its whitened residual, squared, is beyond the range of f64".into(),
        }));
    }
    // Each variable's range among the stored scalars.
    let mut ranges = vec![0..0; entry.names.len()];
    let mut start = 0;
    for field in fields.iter() {
        if let Some(k) = field.variable {
            ranges[k] = start..start + field.scalars;
        }
        start += field.scalars;
    }
    let mut ids = Vec::with_capacity(ranges.len());
    for (k, (_, name)) in entry.names.iter().enumerate() {
        let id = match assembly.created.get(*name) {
            Some(created) => created.id,
            None => {
                let id = assembly.problem.add_variable(&stored[ranges[k].clone()]);
                let field = fields
                    .iter()
                    .find(|f| f.variable == Some(k))
                    .cloned()
                    .expect("every variable is a field");
                let info = &F::variables()[k];
                let columns = tangent_columns(info.tangent, info.tangent_dim);
                assembly
                    .created
                    .insert((*name).to_owned(), Created { id, field, columns });
                id
            }
        };
        ids.push(id);
    }
    match add(
        &mut assembly.problem,
        &factor,
        &ids,
        entry.noise,
        entry.loss,
    ) {
        Ok(()) => {}
        Err(SchurError::Chart {
            variable,
            first,
            second,
        }) => {
            let name = entry
                .names
                .iter()
                .zip(&ids)
                .find(|(_, id)| id.index() == variable)
                .map_or("?", |((_, name), _)| *name);
            assembly.unsupported = Some(format!(
                "variable \"{name}\": {first}, {second}: this solver needs every factor on a \
                 variable to declare the same type, side and tangent"
            ));
            return Ok(());
        }
        Err(e) => return Err(RegistryError::Solve(e.to_string())),
    }
    if matches!(entry.noise, Noise::Sigmas(_) | Noise::SqrtInformation(_)) {
        assembly.whitened += 1;
    }
    assembly.kept.push(Kept {
        stored,
        variables: ids
            .into_iter()
            .zip(ranges)
            .zip(dims.iter())
            .map(|((id, range), d)| (id, range, *d))
            .collect(),
        sqrt_information: s,
        linearize: F::linearize_stored_into,
        initial: jacobian,
    });
    Ok(())
}

/// `jacobian` cut into its blocks of `rows` × each of `dims`.
pub fn blocks_of<'a>(
    mut jacobian: &'a mut [f64],
    rows: usize,
    dims: &[usize],
) -> Vec<Option<&'a mut [f64]>> {
    dims.iter()
        .map(|d| {
            let (block, rest) = std::mem::take(&mut jacobian).split_at_mut(rows * d);
            jacobian = rest;
            Some(block)
        })
        .collect()
}
