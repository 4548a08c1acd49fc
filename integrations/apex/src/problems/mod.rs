//! Real estimation problems as apex-solver problems.
//!
//! | data set (crate `slam-data`) | variables | factors | gauge | linear solver |
//! | --- | --- | --- | --- | --- |
//! | BAL, Bundler ([`bundle`]) | per camera an `SE3` world-to-camera pose and `Rn(3)` `[f, k1, k2]`; per point `Rn(3)` | [`SnavelyReprojection`](slam_factors::SnavelyReprojection), one per observation | camera 0's pose held fixed (the scale, the seventh dimension of the gauge, is left to the damping) | explicit sparse Schur, points eliminated |
//! | g2o, EDGE3 ([`pose_graph`]) | per vertex an `SE3` body-to-world pose (EDGE3 without vertices: the odometry chain) | [`BetweenFactor`](slam_factors::BetweenFactor), one per edge | the first pose held fixed | sparse Cholesky |
//! | g2o lines and planes ([`g2o_addons`]) | per vertex an `SE3` body-to-world pose (robot poses and sensor offsets), an orthonormal line, a quaternion plane | g2o's own errors (or the documents' line and plane factors), whitened by each edge's information | the file's `FIX` vertices | sparse Cholesky |
//! | KITTI stereo VO ([`stereo`]) | per pose an `SE3` camera-to-world pose; per landmark `Rn(3)` | [`StereoReprojection`](slam_factors::StereoReprojection), one per observation | the first pose held fixed, as GTSAM's example | explicit sparse Schur, landmarks eliminated |
//!
//! [`FactorChoice::Apex`] builds the same problem with apex-solver's own
//! hand-written factors, for comparison: its BAL `ProjectionFactor` (the
//! same variables), its `BetweenFactor` with the edge's square-root
//! information as its noise model (the same variables), and its
//! `StereoFactor`, whose poses are world-to-camera (the inverses of this
//! project's: another chart, so another path to the same optimum).
//!
//! Blocks are added in the order the solver evaluates them (observations
//! grouped by eliminated point or landmark, in the order of the points),
//! so the first and the last block added time the passes ([`crate::timing`]).

pub mod bundle;
pub mod g2o_addons;
pub mod pose_graph;
pub mod stereo;

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use apex_solver::NoiseModel;
use apex_solver::core::VarKey;
use apex_solver::core::loss_functions::{HuberLoss, LossFunction};
use apex_solver::core::problem::Problem;
use apex_solver::core::variable::ManifoldVariable;
use apex_solver::factors::Factor;
use apex_solver::linalg::LinearSolverType;
use factor_core::FactorError;
use slotmap::SlotMap;

use crate::adapter::{Kernels, Rejections};
use crate::losses::Cauchy;
use crate::timing::PhaseClock;

/// The factors a problem is built with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FactorChoice {
    /// This project's factors, linearized as given.
    Ours(Kernels),
    /// apex-solver's own hand-written factors.
    Apex,
}

impl FactorChoice {
    /// `generated`, `dual` or `apex`.
    pub fn name(self) -> &'static str {
        match self {
            FactorChoice::Ours(kernels) => kernels.name(),
            FactorChoice::Apex => "apex",
        }
    }
}

/// A robust loss on every block: `½ ρ(‖r‖²)` instead of `½ ‖r‖²`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Robust {
    /// Huber: quadratic up to `‖r‖ = δ`, linear beyond.
    Huber(f64),
    /// Cauchy: `δ² log(1 + ‖r‖²/δ²)`.
    Cauchy(f64),
}

impl Robust {
    /// The loss served to apex-solver: apex's Huber, this crate's Cauchy
    /// (apex's rounds its cost to 0 for a large δ: see [`crate::losses`]).
    pub(crate) fn loss(self) -> Result<Box<dyn LossFunction + Send + Sync>, BuildError> {
        match self {
            Robust::Huber(delta) => HuberLoss::new(delta)
                .map(|l| Box::new(l) as _)
                .map_err(|e| BuildError::Solver(e.to_string())),
            Robust::Cauchy(delta) => Cauchy::new(delta)
                .map(|l| Box::new(l) as _)
                .map_err(BuildError::Solver),
        }
    }
}

/// The range of a robust loss's δ: the readers' range of magnitudes
/// (`slam_data::MAX_MAGNITUDE`), so that `δ²` stays within `f64`.
pub const ROBUST_SCALES: (f64, f64) = (1e-100, 1e100);

/// `huber:δ` or `cauchy:δ`.
impl fmt::Display for Robust {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Robust::Huber(delta) => write!(f, "huber:{delta}"),
            Robust::Cauchy(delta) => write!(f, "cauchy:{delta}"),
        }
    }
}

/// Reads `huber:δ` or `cauchy:δ` with `δ` in [`ROBUST_SCALES`].
impl FromStr for Robust {
    type Err = String;
    fn from_str(text: &str) -> Result<Self, String> {
        let (name, delta) = text
            .split_once(':')
            .ok_or_else(|| format!("`{text}`: expected huber:δ or cauchy:δ"))?;
        let (low, high) = ROBUST_SCALES;
        let delta: f64 = delta
            .parse()
            .ok()
            .filter(|d: &f64| (low..=high).contains(d))
            .ok_or_else(|| {
                format!("`{text}`: δ must be a number above 0, from {low:e} to {high:e}")
            })?;
        match name {
            "huber" => Ok(Robust::Huber(delta)),
            "cauchy" => Ok(Robust::Cauchy(delta)),
            _ => Err(format!("`{text}`: unknown loss `{name}` (huber or cauchy)")),
        }
    }
}

/// How to build a problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuildOptions {
    /// Which factors.
    pub factors: FactorChoice,
    /// A robust loss on every block, or plain least squares.
    pub robust: Option<Robust>,
    /// Keep a handle on every block ([`Built::kept`]) to call it directly.
    pub keep_blocks: bool,
}

/// Why a problem cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BuildError {
    /// A block is degenerate at the initial values.
    #[error("{which}: {error}")]
    Degenerate {
        /// The observation or edge, in words.
        which: String,
        /// The factor's error.
        error: FactorError,
    },
    /// A block's generated kernel is stale: a debug build compared it with
    /// dual numbers at the initial values ([`factor_core::kernel`]).
    #[error("{which}: {error}")]
    StaleKernel {
        /// The factor, in words.
        which: String,
        /// [`FactorError::StaleKernel`].
        error: FactorError,
    },
    /// The data cannot make a problem (an information matrix that is not
    /// positive definite, no odometry to initialise from, ...).
    #[error("{0}")]
    Data(String),
    /// The factors asked for do not exist for this problem.
    #[error("{0}")]
    Unavailable(String),
    /// apex-solver refused the problem.
    #[error("apex-solver: {0}")]
    Solver(String),
    /// The adapter cannot serve a factor.
    #[error(transparent)]
    Adapter(#[from] crate::AdapterError),
}

/// The variable keys of a problem, by data-set entity, to read the solution.
#[derive(Debug, Clone)]
pub enum Keys {
    /// Bundle adjustment.
    Bundle(bundle::BundleKeys),
    /// A pose graph.
    PoseGraph(pose_graph::PoseGraphKeys),
    /// Stereo visual odometry.
    Stereo(stereo::StereoKeys),
    /// A g2o line and plane graph.
    G2oAddons(g2o_addons::G2oGraphKeys),
    /// A problem built with [`crate::builder::ProblemBuilder`]'s typed API:
    /// its variables' handles are the caller's.
    Custom,
}

/// An apex problem built from a data set.
pub struct Built {
    /// The problem, ready to solve.
    pub problem: Problem,
    /// Where each entity's variable is.
    pub keys: Keys,
    /// The linear solver the problem is meant for.
    pub linear_solver: LinearSolverType,
    /// How Levenberg–Marquardt damps its steps on this problem.
    pub damping: crate::solve::Damping,
    /// The residual blocks (observations or edges).
    pub blocks: usize,
    /// The cost at the initial values, `Σ ½ ρ(‖S r‖²)`.
    pub initial_cost: f64,
    /// The times of the latest passes.
    pub clock: Arc<PhaseClock>,
    /// Evaluations this project's factors rejected.
    pub rejections: Arc<Rejections>,
    /// Every block, when [`BuildOptions::keep_blocks`] asked for them.
    pub kept: Option<Vec<KeptBlock>>,
}

/// Builds the apex problem of `data`.
///
/// # Errors
///
/// A block degenerate at the initial values (this project's factors are
/// validated as they are built), data that cannot make a problem, factors
/// apex does not have for it, or apex's refusal.
pub fn build(data: &slam_data::Problem, options: &BuildOptions) -> Result<Built, BuildError> {
    if let Some(empty) = nothing_to_solve(data) {
        return Err(BuildError::Data(empty));
    }
    match data {
        slam_data::Problem::Bal(bal) => bundle::build(bal, options),
        slam_data::Problem::Bundler(bundler) => bundle::build(&bundler.to_bal(), options),
        slam_data::Problem::G2o(graph) | slam_data::Problem::Edge3(graph) => {
            pose_graph::build(graph, options)
        }
        slam_data::Problem::KittiVo(vo) => stereo::build(vo, options),
        slam_data::Problem::G2oAddons(graph) => {
            g2o_addons::build_with(graph, options, g2o_addons::LandmarkFactors::G2o)
        }
    }
}

/// Why `data` has nothing to solve, if it has not: no observation or no
/// edge makes a cost that is identically 0, with no step to take, and a
/// g2o graph whose `FIX` lines hold every vertex has no value to estimate.
pub fn nothing_to_solve(data: &slam_data::Problem) -> Option<String> {
    let what = match data {
        slam_data::Problem::G2o(_)
        | slam_data::Problem::Edge3(_)
        | slam_data::Problem::G2oAddons(_) => "edges",
        _ => "observations",
    };
    if data.measurements() == 0 {
        return Some(format!("nothing to solve: the problem has no {what}"));
    }
    if let slam_data::Problem::G2oAddons(graph) = data {
        let fixed: std::collections::HashSet<usize> = graph.fixed.iter().copied().collect();
        let vertices = graph.poses.iter().map(|v| v.id);
        let vertices = vertices
            .chain(graph.lines.iter().map(|v| v.id))
            .chain(graph.planes.iter().map(|v| v.id))
            .chain(graph.points.iter().map(|v| v.id));
        if vertices.clone().all(|id| fixed.contains(&id)) {
            return Some(format!(
                "nothing to solve: the FIX lines hold every one of the {} vertices",
                vertices.count()
            ));
        }
    }
    None
}

impl Built {
    /// `data` with its variables replaced by `values` (the solver's result):
    /// the optimized problem, in the input's format.
    pub fn write_back(
        &self,
        data: &slam_data::Problem,
        values: &SlotMap<VarKey, Box<dyn ManifoldVariable>>,
    ) -> slam_data::Problem {
        let value = |key: VarKey| values.get(key).map_or(&[][..], |v| v.as_param_slice());
        match (&self.keys, data) {
            (Keys::Bundle(keys), slam_data::Problem::Bal(bal)) => {
                slam_data::Problem::Bal(keys.write_bal(bal, value))
            }
            (Keys::Bundle(keys), slam_data::Problem::Bundler(bundler)) => {
                slam_data::Problem::Bundler(keys.write_bundler(bundler, value))
            }
            (Keys::PoseGraph(keys), slam_data::Problem::G2o(graph)) => {
                slam_data::Problem::G2o(keys.write(graph, value))
            }
            (Keys::PoseGraph(keys), slam_data::Problem::Edge3(graph)) => {
                slam_data::Problem::Edge3(keys.write(graph, value))
            }
            (Keys::Stereo(keys), slam_data::Problem::KittiVo(vo)) => {
                slam_data::Problem::KittiVo(keys.write(vo, value))
            }
            (Keys::G2oAddons(keys), slam_data::Problem::G2oAddons(graph)) => {
                slam_data::Problem::G2oAddons(keys.write(graph, values))
            }
            // Keys are built from the same data they write back.
            _ => data.clone(),
        }
    }
}

/// The reprojection error of each observation (pixels: `‖predicted −
/// observed‖`, two coordinates for BAL and Bundler, `[u_L, u_R, v]` for
/// stereo) at the problem's values, through this project's factors; `None`
/// for a pose graph (with or without lines and planes). An observation degenerate at these values is NaN.
pub fn reprojection_errors(data: &slam_data::Problem) -> Option<Vec<f64>> {
    match data {
        slam_data::Problem::Bal(bal) => Some(bundle::reprojection_errors(bal)),
        slam_data::Problem::Bundler(bundler) => {
            Some(bundle::reprojection_errors(&bundler.to_bal()))
        }
        slam_data::Problem::KittiVo(vo) => Some(stereo::reprojection_errors(vo)),
        slam_data::Problem::G2o(_)
        | slam_data::Problem::Edge3(_)
        | slam_data::Problem::G2oAddons(_) => None,
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
