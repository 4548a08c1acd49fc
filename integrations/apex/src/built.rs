//! A built problem ([`Built`]): apex's problem with what the solve and the
//! caller need beside it: the variables' keys, the linear solver and the
//! damping it is meant for ([`Damping`]), the initial cost, the clock of
//! the passes and, on request, every block ([`KeptBlock`]).

use std::sync::Arc;

use apex_solver::NoiseModel;
use apex_solver::core::VarKey;
use apex_solver::core::problem::Problem;
use apex_solver::factors::Factor;
use apex_solver::linalg::LinearSolverType;

use crate::adapter::Rejections;
use crate::timing::PhaseClock;
pub use factor_minimizer::Damping;

/// An apex problem, built from a data set ([`crate::problems::build`],
/// `K` = [`crate::problems::Keys`]) or by the typed builder
/// ([`crate::builder::ProblemBuilder::build`], `K` = `()`: the variables'
/// handles are the caller's).
pub struct Built<K> {
    /// The problem, ready to solve.
    pub problem: Problem,
    /// Where each entity's variable is.
    pub keys: K,
    /// The linear solver the problem is meant for.
    pub linear_solver: LinearSolverType,
    /// How Levenberg–Marquardt damps its steps on this problem.
    pub damping: Damping,
    /// The residual blocks (observations or edges).
    pub blocks: usize,
    /// The cost at the initial values, `Σ ½ ρ(‖S r‖²)`.
    pub initial_cost: f64,
    /// The times of the latest passes.
    pub clock: Arc<PhaseClock>,
    /// Evaluations this project's factors rejected.
    pub rejections: Arc<Rejections>,
    /// Every block, when
    /// [`BuildOptions::keep_blocks`](crate::options::BuildOptions::keep_blocks)
    /// asked for them.
    pub kept: Option<Vec<KeptBlock>>,
}

impl<K> Built<K> {
    /// The same problem with its keys mapped by `f` (a data set's keys
    /// into [`crate::problems::Keys`]).
    pub fn map_keys<L>(self, f: impl FnOnce(K) -> L) -> Built<L> {
        Built {
            problem: self.problem,
            keys: f(self.keys),
            linear_solver: self.linear_solver,
            damping: self.damping,
            blocks: self.blocks,
            initial_cost: self.initial_cost,
            clock: self.clock,
            rejections: self.rejections,
            kept: self.kept,
        }
    }
}

/// A residual block kept for direct calls (benchmarks, the observability
/// check of a problem file): its factor, its variables' keys and initial
/// apex parameters and its noise model.
pub struct KeptBlock {
    /// The factor, as registered.
    pub factor: Arc<dyn Factor + Send + Sync>,
    /// Its variables' keys, in the factor's order.
    pub keys: Vec<VarKey>,
    /// Each variable's initial parameters.
    pub params: Vec<Vec<f64>>,
    /// The noise model apex whitens the block with.
    pub noise: NoiseModel,
}

impl KeptBlock {
    /// The whitened Jacobian `S J` at the initial parameters, as apex
    /// linearizes the block: its rows and its entries column-major, the
    /// columns those of the keys' tangents in order.
    pub fn whitened_jacobian(&self) -> (usize, Vec<f64>) {
        let params: Vec<&[f64]> = self.params.iter().map(Vec::as_slice).collect();
        self.whitened_jacobian_at(&params)
    }

    /// [`Self::whitened_jacobian`] at the parameters `params` (one slice
    /// per key, as apex-solver stores them: a solution's values).
    pub fn whitened_jacobian_at(&self, params: &[&[f64]]) -> (usize, Vec<f64>) {
        let (rows, columns) = self.factor.jacobian_shape();
        let mut residual = vec![0.0; rows];
        let mut jacobian = vec![0.0; rows * columns];
        self.factor.linearize(
            params,
            &mut residual,
            Some(faer::MatMut::from_column_major_slice_mut(
                &mut jacobian,
                rows,
                columns,
            )),
        );
        self.noise.whiten_jacobian(&mut jacobian, rows, columns);
        (rows, jacobian)
    }
}
