//! A problem of any derived factors, the user's own included, built for
//! apex-solver: variables with initial values (fixed, partly fixed, or
//! eliminated by the Schur complement), factors with a noise model and a
//! robust loss each; then [`crate::solve::solve`] runs it and
//! [`crate::solve::Outcome::value`] reads the solution back.
//!
//! ```
//! use factor_apex::builder::{Noise, ProblemBuilder};
//! use factor_apex::solve::{SolveOptions, solve};
//! use factor_core::geometry::Intrinsics;
//! use factor_core::lie::{Se3, So3};
//! use nalgebra::{Vector2, Vector3};
//! use slam_factors::PointReprojection;
//!
//! // Two cameras, held fixed, triangulate a point: document 000's point
//! // factor (a left-perturbed pose) served in apex's own chart.
//! let truth = Vector3::new(0.2, -0.1, 4.0);
//! let start = Vector3::new(0.0, 0.0, 3.0);
//! let intrinsics = Intrinsics::new(500.0, 500.0, 320.0, 240.0);
//! let mut problem = ProblemBuilder::new();
//! let point = problem.add_variable(&start);
//! for x in [-0.5, 0.5] {
//!     let pose = Se3::new(So3::identity(), Vector3::new(x, 0.0, 0.0));
//!     let camera = problem.add_variable(&pose);
//!     problem.fix_variable(&camera)?;
//!     let p = pose.transform_point(&truth);
//!     let factor = PointReprojection {
//!         intrinsics,
//!         observed: Vector2::new(500.0 * p.x / p.z + 320.0, 500.0 * p.y / p.z + 240.0),
//!         pose,
//!         point: start,
//!     };
//!     problem.add_factor(&factor, &[camera.erase(), point.erase()], &Noise::Sigma(1.0), None)?;
//! }
//! let mut built = problem.build()?;
//! let outcome = solve(&mut built, &SolveOptions::converged(50), |_| {})?;
//! let estimate: Vector3<f64> = outcome.value(&point);
//! assert!((estimate - truth).norm() < 1e-9);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::any::TypeId;
use std::collections::HashMap;
use std::marker::PhantomData;
use std::sync::Arc;

use apex_solver::NoiseModel;
use apex_solver::core::VarKey;
use apex_solver::core::problem::Problem;
use apex_solver::factors::Factor;
use apex_solver::linalg::{JacobianMode, LinearSolverType};
use factor_core::host::{Apex, HostFactor, HostKernel, HostManifold, HostMap};
use factor_core::{FactorError, Storage};
use slam_problems::ProblemError;
use slotmap::SlotMap;

use crate::adapter::{ApexFactor, Kernels, Rejections};
use crate::built::{Built, Damping, KeptBlock};
use crate::losses::apex_loss;
use crate::options::{BuildError, BuildOptions, FactorChoice, Robust};
use crate::timing::{Marks, PhaseClock, Timed};
use crate::variables::{manifold_type, split_parts, to_apex};

/// A variable of type `V` in a problem: its apex variables' keys (one per
/// host part of `V`, [`HostMap::PARTS`]).
#[derive(Debug, Clone)]
pub struct Variable<V> {
    keys: Vec<VarKey>,
    _type: PhantomData<fn() -> V>,
}

impl<V: HostMap<Apex> + 'static> Variable<V> {
    /// The apex keys, one per host part.
    pub fn keys(&self) -> &[VarKey] {
        &self.keys
    }

    /// The variable as a factor's argument ([`ProblemBuilder::add_factor`]).
    pub fn erase(&self) -> AnyVariable {
        AnyVariable {
            keys: self.keys.clone(),
            type_id: TypeId::of::<V>(),
            type_name: std::any::type_name::<V>(),
            dofs: V::PARTS.iter().map(|p| p.manifold.dof()).collect(),
        }
    }
}

/// A variable of any type, as a factor's argument: its keys and its type,
/// checked against the factor's variable when the factor is added.
#[derive(Debug, Clone)]
pub struct AnyVariable {
    keys: Vec<VarKey>,
    type_id: TypeId,
    type_name: &'static str,
    dofs: Vec<usize>,
}

impl AnyVariable {
    /// The apex keys, one per host part.
    pub fn keys(&self) -> &[VarKey] {
        &self.keys
    }

    /// The tangent dimension of each key's variable.
    pub fn dofs(&self) -> &[usize] {
        &self.dofs
    }
}

pub use factor_core::noise::Noise;

/// apex's noise model of `noise` for a residual of `dim` components.
pub(crate) fn model(noise: &Noise, dim: usize) -> Result<Option<NoiseModel>, String> {
    noise.check(dim)?;
    let sigmas = |sigmas: &[f64]| NoiseModel::from_sigmas(sigmas).map_err(|e| e.to_string());
    match noise {
        Noise::Unit => Ok(None),
        Noise::Sigma(sigma) => sigmas(&vec![*sigma; dim]).map(Some),
        Noise::Sigmas(values) => sigmas(values).map(Some),
        Noise::SqrtInformation(s) => {
            let s = nalgebra_apex::DMatrix::from_column_slice(dim, dim, s.as_slice());
            NoiseModel::from_sqrt_info(s)
                .map(Some)
                .map_err(|e| e.to_string())
        }
    }
}

/// A residual block waiting to be added to the problem.
struct Pending {
    keys: Vec<VarKey>,
    factor: Arc<dyn Factor + Send + Sync>,
    noise: NoiseModel,
    loss: Option<Robust>,
}

/// An apex problem under construction. Each variable's initial value is
/// kept, so that each block's initial cost is known as it is added (apex
/// computes it too, but inside its solve, after the first report is due);
/// blocks are handed to apex by [`ProblemBuilder::build`], each wrapped in
/// [`Timed`], the first and the last marking the passes on the problem's
/// clock.
pub struct ProblemBuilder {
    problem: Problem,
    initial: HashMap<VarKey, Vec<f64>>,
    options: BuildOptions,
    cost: f64,
    pending: Vec<Pending>,
    eliminated: bool,
    damping: Damping,
    rejections: Arc<Rejections>,
}

impl Default for ProblemBuilder {
    fn default() -> Self {
        ProblemBuilder::new()
    }
}

impl ProblemBuilder {
    /// An empty problem whose factors are linearized through their
    /// generated apex kernels.
    pub fn new() -> Self {
        ProblemBuilder::with_options(&BuildOptions {
            factors: FactorChoice::Ours(Kernels::Generated),
            robust: None,
            keep_blocks: false,
        })
    }

    /// An empty problem built with `options` (its `robust` loss is the one
    /// the data-set builders give every block).
    pub fn with_options(options: &BuildOptions) -> Self {
        ProblemBuilder {
            problem: Problem::new(JacobianMode::Sparse),
            initial: HashMap::new(),
            options: *options,
            cost: 0.0,
            pending: Vec::new(),
            eliminated: false,
            damping: Damping::default(),
            rejections: Rejections::new(),
        }
    }

    /// The record of rejected evaluations this problem's factors share.
    pub fn rejections(&self) -> Arc<Rejections> {
        Arc::clone(&self.rejections)
    }

    /// A variable of type `V` with initial value `value`: one apex variable
    /// per host part of `V`.
    pub fn add_variable<V: HostMap<Apex> + Storage<f64> + 'static>(
        &mut self,
        value: &V,
    ) -> Variable<V> {
        let keys = V::PARTS
            .iter()
            .zip(to_apex(value))
            .map(|(part, params)| self.variable(manifold_type(part.manifold), params))
            .collect();
        Variable {
            keys,
            _type: PhantomData,
        }
    }

    /// Variable `variable` of `factor` as a new variable of the problem,
    /// its initial value the factor's: the typed [`ProblemBuilder::add_variable`]
    /// for a caller that knows the variable's type only through a factor
    /// (a problem read from a file). Its value is read back with
    /// [`stored_value_of`].
    ///
    /// # Panics
    ///
    /// If `F` has no variable `variable`.
    pub fn add_variable_of<F: HostFactor<Apex> + 'static>(
        &mut self,
        factor: &F,
        variable: usize,
    ) -> AnyVariable {
        let stored = factor.to_scalars();
        let range = stored_range::<F>(variable);
        let parts = F::host_parts(variable);
        let mut host = vec![0.0; parts.iter().map(|p| p.manifold.parameters()).sum()];
        F::host_from_stored(variable, &stored[range], &mut host);
        let keys = parts
            .iter()
            .zip(split_parts(parts, &host))
            .map(|(part, params)| self.variable(manifold_type(part.manifold), params))
            .collect();
        AnyVariable {
            keys,
            type_id: F::variable_type(variable),
            type_name: F::variables()[variable].type_name,
            dofs: parts.iter().map(|p| p.manifold.dof()).collect(),
        }
    }

    /// Holds `variable` fixed (every part, every tangent coordinate).
    ///
    /// # Errors
    ///
    /// apex's refusal.
    pub fn fix_any(&mut self, variable: &AnyVariable) -> Result<(), BuildError> {
        for (key, dof) in variable.keys.iter().zip(&variable.dofs) {
            self.fix(*key, *dof)?;
        }
        Ok(())
    }

    /// Holds `variable` fixed (every part, every tangent coordinate).
    ///
    /// # Errors
    ///
    /// apex's refusal.
    pub fn fix_variable<V: HostMap<Apex>>(
        &mut self,
        variable: &Variable<V>,
    ) -> Result<(), BuildError> {
        for (key, part) in variable.keys.iter().zip(V::PARTS) {
            self.fix(*key, part.manifold.dof())?;
        }
        Ok(())
    }

    /// Holds part `part` of `variable` fixed (the `SO2` of an orthonormal
    /// line, say), the others free.
    ///
    /// # Errors
    ///
    /// [`ProblemError::Data`] (in [`BuildError::Problem`]) for a part `V`
    /// does not have; apex's refusal.
    pub fn fix_part<V: HostMap<Apex>>(
        &mut self,
        variable: &Variable<V>,
        part: usize,
    ) -> Result<(), BuildError> {
        let (Some(key), Some(host)) = (variable.keys.get(part), V::PARTS.get(part)) else {
            return Err(ProblemError::Data(format!(
                "part {part} of a variable with {} parts",
                V::PARTS.len()
            ))
            .into());
        };
        self.fix(*key, host.manifold.dof())
    }

    /// Marks `variable` for elimination by the Schur complement (landmarks
    /// of a bundle adjustment); the problem is then solved by apex's sparse
    /// Schur solver.
    pub fn eliminate_variable<V>(&mut self, variable: &Variable<V>) {
        for key in &variable.keys {
            self.eliminate(*key);
        }
    }

    /// Adds `factor` on `variables` (its variables in declaration order),
    /// linearized through its generated apex kernel (or dual numbers, as
    /// [`ProblemBuilder::with_options`] chose), whitened by `noise`, under
    /// `loss` (least squares when `None`).
    ///
    /// # Errors
    ///
    /// [`BuildError::Problem`]: [`ProblemError::Data`] when `variables` are
    /// not the factor's (count or types) or the noise model does not fit its
    /// residual, [`ProblemError::Degenerate`] when the factor is degenerate at the
    /// initial values (or its outputs are not finite there);
    /// [`BuildError::StaleKernel`], in a debug build, when its generated
    /// kernel no longer matches its definition; the adapter's and apex's
    /// refusals.
    pub fn add_factor<F: HostKernel<Apex> + 'static>(
        &mut self,
        factor: &F,
        variables: &[AnyVariable],
        noise: &Noise,
        loss: Option<Robust>,
    ) -> Result<(), BuildError> {
        let kernels = match self.options.factors {
            FactorChoice::Ours(kernels) => kernels,
            FactorChoice::Apex => Kernels::Generated,
        };
        let served = ApexFactor::new(factor, kernels)?;
        self.add_served(factor, served, variables, noise, loss)
    }

    /// [`ProblemBuilder::add_factor`] for a factor without a generated apex
    /// kernel: linearized by dual numbers in apex's chart.
    ///
    /// # Errors
    ///
    /// As [`ProblemBuilder::add_factor`].
    pub fn add_factor_dual<F: HostFactor<Apex> + 'static>(
        &mut self,
        factor: &F,
        variables: &[AnyVariable],
        noise: &Noise,
        loss: Option<Robust>,
    ) -> Result<(), BuildError> {
        let served = ApexFactor::dual(factor)?;
        self.add_served(factor, served, variables, noise, loss)
    }

    fn add_served<F: HostFactor<Apex> + 'static>(
        &mut self,
        factor: &F,
        served: ApexFactor<F>,
        variables: &[AnyVariable],
        noise: &Noise,
        loss: Option<Robust>,
    ) -> Result<(), BuildError> {
        let declared = F::variables();
        if variables.len() != declared.len() {
            return Err(ProblemError::Data(format!(
                "{}: {} variables given, the factor has {}",
                F::NAME,
                variables.len(),
                declared.len()
            ))
            .into());
        }
        for (k, (given, info)) in variables.iter().zip(&declared).enumerate() {
            if given.type_id != F::variable_type(k) {
                return Err(ProblemError::Data(format!(
                    "{}: variable `{}` is a `{}`, given a `{}`",
                    F::NAME,
                    info.name,
                    info.type_name,
                    given.type_name
                ))
                .into());
            }
        }
        served.linearize_at(factor).map_err(|error| match error {
            FactorError::StaleKernel { .. } => BuildError::StaleKernel {
                which: format!("{} at the initial values", F::NAME),
                error,
            },
            error => ProblemError::at_initial_values(F::NAME, error).into(),
        })?;
        let noise = model(noise, F::RESIDUAL_DIM)
            .map_err(|e| ProblemError::Data(format!("{}: noise model: {e}", F::NAME)))?;
        let keys: Vec<VarKey> = variables.iter().flat_map(|v| v.keys.clone()).collect();
        let served = served.with_rejections(self.rejections());
        self.block_with_loss(&keys, Arc::new(served), noise, loss)?;
        // The blocks before were finite (each is checked as it is added):
        // this one is the first whose cost is not.
        if !self.cost.is_finite() {
            let error = FactorError::NonFinite {
                factor: F::NAME,
                what: "cost: its whitened residual, squared, is beyond the range of f64".into(),
            };
            return Err(ProblemError::at_initial_values(F::NAME, error).into());
        }
        Ok(())
    }

    /// Damps the solve's steps with `damping` (by default
    /// [`Damping::Diagonal`]).
    pub fn damping(&mut self, damping: Damping) {
        self.damping = damping;
    }

    /// The problem, ready for [`crate::solve::solve`]: solved by apex's
    /// sparse Schur solver when a variable was marked for elimination, by
    /// its sparse Cholesky solver otherwise.
    ///
    /// # Errors
    ///
    /// apex's refusal of a block.
    pub fn build(self) -> Result<Built<()>, BuildError> {
        let linear_solver = if self.eliminated {
            LinearSolverType::ExplicitSparseSchur
        } else {
            LinearSolverType::SparseCholesky
        };
        self.finish((), linear_solver)
    }

    /// A variable with initial value `value` (apex's parameters).
    pub(crate) fn variable(
        &mut self,
        manifold: apex_solver::ManifoldType,
        value: Vec<f64>,
    ) -> VarKey {
        let key = self
            .problem
            .add_variable(manifold, nalgebra_apex::DVector::from_column_slice(&value));
        self.initial.insert(key, value);
        key
    }

    /// Marks `key` for elimination by the Schur complement.
    pub(crate) fn eliminate(&mut self, key: VarKey) {
        self.eliminated = true;
        self.problem.mark_for_elimination(key);
    }

    /// Holds every tangent coordinate of `key` fixed.
    pub(crate) fn fix(&mut self, key: VarKey, dof: usize) -> Result<(), BuildError> {
        for coordinate in 0..dof {
            self.problem
                .try_fix_variable(key, coordinate)
                .map_err(|e| BuildError::Solver(e.to_string()))?;
        }
        Ok(())
    }

    /// Registers a block on `keys` under the options' robust loss.
    pub(crate) fn block(
        &mut self,
        keys: &[VarKey],
        factor: Arc<dyn Factor + Send + Sync>,
        noise: Option<NoiseModel>,
    ) -> Result<(), BuildError> {
        self.block_with_loss(keys, factor, noise, self.options.robust)
    }

    /// Registers a block on `keys` and adds its initial cost `½ ρ(‖S r‖²)`
    /// (apex's objective: `S` the noise model's square root, `ρ` the loss).
    pub(crate) fn block_with_loss(
        &mut self,
        keys: &[VarKey],
        factor: Arc<dyn Factor + Send + Sync>,
        noise: Option<NoiseModel>,
        loss: Option<Robust>,
    ) -> Result<(), BuildError> {
        let params: Vec<&[f64]> = keys
            .iter()
            .map(|key| self.initial.get(key).map_or(&[][..], Vec::as_slice))
            .collect();
        let mut residual = vec![0.0; factor.residual_dim()];
        factor.linearize(&params, &mut residual, None);
        let noise = noise.unwrap_or_else(NoiseModel::null);
        noise.whiten_residual(&mut residual);
        let squared: f64 = residual.iter().map(|r| r * r).sum();
        let evaluated = loss.map(apex_loss).transpose()?;
        self.cost += 0.5
            * evaluated
                .as_ref()
                .map_or(squared, |l| l.evaluate(squared)[0]);
        self.pending.push(Pending {
            keys: keys.to_vec(),
            factor,
            noise,
            loss,
        });
        Ok(())
    }

    /// The problem, for `linear_solver`: every pending block handed to apex
    /// in the order added, the first and the last marking the passes.
    pub(crate) fn finish<K>(
        mut self,
        keys: K,
        linear_solver: LinearSolverType,
    ) -> Result<Built<K>, BuildError> {
        let clock = PhaseClock::new();
        let count = self.pending.len();
        let mut kept = self.options.keep_blocks.then(Vec::new);
        for (index, block) in std::mem::take(&mut self.pending).into_iter().enumerate() {
            if let Some(kept) = &mut kept {
                kept.push(KeptBlock {
                    factor: Arc::clone(&block.factor),
                    keys: block.keys.clone(),
                    params: block
                        .keys
                        .iter()
                        .map(|key| self.initial.get(key).cloned().unwrap_or_default())
                        .collect(),
                    noise: block.noise.clone(),
                });
            }
            let timed = Timed {
                factor: block.factor,
                marks: Marks::of_block(&clock, index, count),
            };
            let loss = block.loss.map(apex_loss).transpose()?;
            self.problem
                .try_add_residual_block_with_noise(&block.keys, Box::new(timed), loss, block.noise)
                .map_err(|e| BuildError::Solver(e.to_string()))?;
        }
        Ok(Built {
            problem: self.problem,
            keys,
            linear_solver,
            damping: self.damping,
            blocks: count,
            initial_cost: self.cost,
            clock,
            rejections: self.rejections,
            kept,
        })
    }
}

/// A solution's variables ([`crate::solve::Outcome::values`]).
pub type Values = SlotMap<VarKey, Box<dyn apex_solver::core::variable::ManifoldVariable>>;

/// The range of variable `variable`'s stored scalars in `F`'s storage.
fn stored_range<F: HostFactor<Apex>>(variable: usize) -> std::ops::Range<usize> {
    let mut offset = 0;
    for field in F::fields() {
        if field.variable == Some(variable) {
            return offset..offset + field.scalars;
        }
        offset += field.scalars;
    }
    panic!("{} has no variable {variable}", F::NAME)
}

/// The stored scalars of `variable`, added as variable `index` of factor
/// type `F` ([`ProblemBuilder::add_variable_of`]), in a solution's
/// variables.
///
/// # Panics
///
/// If a key of `variable` is not among `values`, or `F`'s variable `index`
/// is not of `variable`'s type.
pub fn stored_value_of<F: HostFactor<Apex>>(
    values: &Values,
    variable: &AnyVariable,
    index: usize,
) -> Vec<f64> {
    assert_eq!(
        F::variable_type(index),
        variable.type_id,
        "the variable's type"
    );
    let host: Vec<f64> = variable
        .keys
        .iter()
        .flat_map(|key| {
            values
                .get(*key)
                .expect("the variable is one of the problem's")
                .as_param_slice()
                .to_vec()
        })
        .collect();
    let mut stored = vec![0.0; stored_range::<F>(index).len()];
    F::stored_from_host(index, &host, &mut stored);
    stored
}

/// The value of `variable` in a solution's variables.
///
/// # Panics
///
/// If a key of `variable` is not among `values` (a variable of another
/// problem).
pub fn value_of<V: HostMap<Apex> + Storage<f64>>(
    values: &SlotMap<VarKey, Box<dyn apex_solver::core::variable::ManifoldVariable>>,
    variable: &Variable<V>,
) -> V {
    let parts: Vec<&[f64]> = variable
        .keys
        .iter()
        .map(|key| {
            values
                .get(*key)
                .expect("the variable is one of the problem's")
                .as_param_slice()
        })
        .collect();
    crate::variables::from_apex(&parts)
}
