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

use apex_solver::core::VarKey;
use apex_solver::core::variable::ManifoldVariable;
use slam_problems::ProblemError;
use slotmap::SlotMap;

pub use slam_problems::{g2o_edges, nothing_to_solve, reprojection_errors};

pub use crate::built::KeptBlock;
pub use crate::options::{BuildError, BuildOptions, FactorChoice, ROBUST_SCALES, Robust};
use crate::variables::apex_se3;

/// An apex problem built from a data set, its keys by data-set entity.
pub type Built = crate::built::Built<Keys>;

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
        return Err(ProblemError::Data(empty).into());
    }
    match data {
        slam_data::Problem::Bal(bal) => {
            bundle::build(bal, options).map(|b| b.map_keys(Keys::Bundle))
        }
        slam_data::Problem::Bundler(bundler) => {
            bundle::build(&bundler.to_bal(), options).map(|b| b.map_keys(Keys::Bundle))
        }
        slam_data::Problem::G2o(graph) | slam_data::Problem::Edge3(graph) => {
            pose_graph::build(graph, options).map(|b| b.map_keys(Keys::PoseGraph))
        }
        slam_data::Problem::KittiVo(vo) => {
            stereo::build(vo, options).map(|b| b.map_keys(Keys::Stereo))
        }
        slam_data::Problem::G2oAddons(graph) => {
            g2o_addons::build_with(graph, options, g2o_addons::LandmarkFactors::G2o)
                .map(|b| b.map_keys(Keys::G2oAddons))
        }
    }
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
                slam_data::Problem::Bal(keys.write_bal(bal, apex_se3, value))
            }
            (Keys::Bundle(keys), slam_data::Problem::Bundler(bundler)) => {
                slam_data::Problem::Bundler(keys.write_bundler(bundler, apex_se3, value))
            }
            (Keys::PoseGraph(keys), slam_data::Problem::G2o(graph)) => {
                slam_data::Problem::G2o(keys.write(graph, apex_se3, value))
            }
            (Keys::PoseGraph(keys), slam_data::Problem::Edge3(graph)) => {
                slam_data::Problem::Edge3(keys.write(graph, apex_se3, value))
            }
            (Keys::Stereo(keys), slam_data::Problem::KittiVo(vo)) => {
                slam_data::Problem::KittiVo(keys.write(vo, apex_se3, value))
            }
            (Keys::G2oAddons(keys), slam_data::Problem::G2oAddons(graph)) => {
                slam_data::Problem::G2oAddons(keys.write(graph, values))
            }
            // Keys are built from the same data they write back.
            _ => data.clone(),
        }
    }
}
