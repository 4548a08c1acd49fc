//! Pose graphs (g2o, EDGE3): no variable eliminated, the poses' system
//! solved by the sparse Cholesky factorization whole.

use std::collections::HashMap;

use factor_core::lie::Se3RhoTheta;
use factor_core::{Factor, Storage};
use factor_minimizer::Damping;
use slam_data::PoseGraph;
use slam_problems::ProblemError;
use slam_problems::pose_graph::{edge_name, endpoints, factor_of, initial_vertices, se3};

use factor_core::noise::Noise;
use slam_problems::Kernels;

use super::error::BuildError;
use crate::problem::{Problem, VariableId};

/// The variables of a pose graph: each vertex id and its body-to-world pose
/// (`Se3RhoTheta`), in the file's vertex order (or the odometry chain's, for
/// a file without vertices).
pub type PoseGraphKeys = slam_problems::pose_graph::PoseGraphKeys<VariableId>;

/// Builds the pose graph of `graph` as the general path does: a
/// `BetweenFactor` per edge, whitened by its information, the first pose
/// fixed, damped uniformly (one unit system).
pub(super) fn build(
    graph: &PoseGraph,
    kernels: Kernels,
) -> Result<(Problem, PoseGraphKeys), BuildError> {
    let vertices = initial_vertices(graph)?;
    let mut problem = Problem::new();
    let mut keys = PoseGraphKeys {
        poses: Vec::with_capacity(vertices.len()),
    };
    let mut by_id = HashMap::with_capacity(vertices.len());
    for v in &vertices {
        let pose = se3(&v.pose);
        let id = problem.add_variable(&Se3RhoTheta::new(pose).to_scalars());
        keys.poses.push((v.id, id));
        by_id.insert(v.id, (id, pose));
    }
    for (index, e) in graph.edges.iter().enumerate() {
        let ((i, pose_i), (j, pose_j)) = endpoints(graph, index, &by_id)?;
        let factor = factor_of(e, &pose_i, &pose_j)?;
        factor
            .validate()
            .map_err(|e| ProblemError::at_initial_values(edge_name(graph, index), e))?;
        problem.add_by(&factor, &[i, j], &Noise::Unit, None, kernels)?;
    }
    if let Some(&(_, id)) = keys.poses.first() {
        problem.fix(id);
    }
    problem.set_damping(Damping::Uniform);
    Ok((problem, keys))
}
