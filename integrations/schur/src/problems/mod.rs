//! Real problems for this solver: bundle adjustment (BAL, Bundler), stereo
//! visual odometry (KITTI VO) and pose graphs (g2o, EDGE3), built from
//! `slam-data` with the factors of crate `slam-problems` and the same
//! variables, gauge, damping and initial values as the apex-solver path
//! (`factor_apex::problems`), the points and landmarks eliminated; and the solution written back in the input's
//! format.
//!
//! | data set | reduced variables | eliminated | factor | gauge |
//! | --- | --- | --- | --- | --- |
//! | BAL, Bundler ([`bundle`]) | per camera its world-to-camera pose (`Se3RhoTheta`) and `[f, k1, k2]` | the points | `SnavelyReprojection` | camera 0's pose fixed |
//! | KITTI VO ([`stereo`]) | per pose its camera-to-world pose | the landmarks | `StereoReprojection` | the first pose fixed |
//! | g2o, EDGE3 ([`pose_graph`]) | per vertex its body-to-world pose (EDGE3 without vertices: the odometry chain) | nothing | `BetweenFactor` (uniform damping) | the first pose fixed |
//! | g2o lines, planes and points ([`g2o_addons`]) | robot poses and sensor offsets (body to world) | lines, planes, points | g2o's own edges (or the documents' line and plane factors, [`build_with`]), one at a time (uniform damping) | the file's `FIX` vertices |

pub mod bundle;
mod error;
pub mod g2o_addons;
pub mod pose_graph;
pub mod stereo;

pub use error::BuildError;
use factor_core::Storage;
use factor_core::lie::{Se3, Se3RhoTheta};
use slam_problems::Kernels;
use slam_problems::g2o_edges::LandmarkFactors;

use crate::problem::{Problem, VariableId};

/// The variables of a problem, by data-set entity, to read the solution.
#[derive(Debug, Clone)]
pub enum Keys {
    /// Bundle adjustment.
    Bundle(bundle::BundleKeys),
    /// Stereo visual odometry.
    Stereo(stereo::StereoKeys),
    /// A pose graph.
    PoseGraph(pose_graph::PoseGraphKeys),
    /// A g2o line and plane graph.
    G2oAddons(g2o_addons::G2oGraphKeys),
}

/// A problem built from a data set.
pub struct Built {
    /// The problem, ready to solve.
    pub problem: Problem,
    /// Where each entity's variable is.
    pub keys: Keys,
    /// The factors (observations).
    pub blocks: usize,
}

/// Builds `data`'s problem, with `robust` on every factor, its factors
/// differentiated by `kernels`: the generated kernels (fused normal
/// equations in lane batches where the factor has them, else its kernel
/// one factor at a time), or dual numbers one factor at a time.
///
/// # Errors
///
/// A factor degenerate at the initial values, or data that refer to what
/// they lack.
pub fn build(
    data: &slam_data::Problem,
    robust: Option<slam_problems::Robust>,
    kernels: Kernels,
) -> Result<Built, BuildError> {
    build_with(data, robust, kernels, LandmarkFactors::G2o)
}

/// [`build`], with `landmarks`' factors for the lines and planes of g2o's
/// line and plane graphs (g2o's own edges, or the documents' factors; other
/// data sets have none).
///
/// # Errors
///
/// As [`build`]; with the documents' factors, also a plane edge whose sensor
/// offset is free, and a measurement without an orthonormal representation.
pub fn build_with(
    data: &slam_data::Problem,
    robust: Option<slam_problems::Robust>,
    kernels: Kernels,
    landmarks: LandmarkFactors,
) -> Result<Built, BuildError> {
    let mut built = match data {
        slam_data::Problem::Bal(bal) => Built::of(bundle::build(bal, kernels)?, Keys::Bundle),
        slam_data::Problem::Bundler(bundler) => {
            Built::of(bundle::build(&bundler.to_bal(), kernels)?, Keys::Bundle)
        }
        slam_data::Problem::KittiVo(vo) => Built::of(stereo::build(vo, kernels)?, Keys::Stereo),
        slam_data::Problem::G2o(graph) | slam_data::Problem::Edge3(graph) => {
            Built::of(pose_graph::build(graph, kernels)?, Keys::PoseGraph)
        }
        slam_data::Problem::G2oAddons(graph) => Built::of(
            g2o_addons::build(graph, kernels, landmarks)?,
            Keys::G2oAddons,
        ),
    };
    built.problem.set_robust(robust);
    Ok(built)
}

impl Built {
    /// A data set's problem, its keys by entity made `Keys` by `keys`, one
    /// block per factor.
    fn of<K>((problem, entity): (Problem, K), keys: impl FnOnce(K) -> Keys) -> Built {
        Built {
            blocks: problem.factor_count(),
            keys: keys(entity),
            problem,
        }
    }

    /// `data` with its variables replaced by the problem's values (after a
    /// solve, the solution), in the input's format.
    pub fn write_back(&self, data: &slam_data::Problem) -> slam_data::Problem {
        let value = |id: VariableId| self.problem.value(id);
        match (&self.keys, data) {
            (Keys::Bundle(keys), slam_data::Problem::Bal(bal)) => {
                slam_data::Problem::Bal(keys.write_bal(bal, se3, value))
            }
            (Keys::Bundle(keys), slam_data::Problem::Bundler(bundler)) => {
                slam_data::Problem::Bundler(keys.write_bundler(bundler, se3, value))
            }
            (Keys::PoseGraph(keys), slam_data::Problem::G2o(graph)) => {
                slam_data::Problem::G2o(keys.write(graph, se3, value))
            }
            (Keys::PoseGraph(keys), slam_data::Problem::Edge3(graph)) => {
                slam_data::Problem::Edge3(keys.write(graph, se3, value))
            }
            (Keys::Stereo(keys), slam_data::Problem::KittiVo(vo)) => {
                slam_data::Problem::KittiVo(keys.write(vo, se3, value))
            }
            (Keys::G2oAddons(keys), slam_data::Problem::G2oAddons(graph)) => {
                slam_data::Problem::G2oAddons(keys.write(graph, value))
            }
            // Keys are built from the same data they write back.
            _ => data.clone(),
        }
    }
}

/// The pose of a `Se3RhoTheta` variable's stored scalars (every pose of
/// these problems).
fn se3(stored: &[f64]) -> Se3<f64> {
    Se3RhoTheta::<f64>::from_scalars(stored).se3()
}
