//! Pose-graph optimization of g2o and EDGE3 graphs.

use std::collections::HashMap;
use std::sync::Arc;

use apex_solver::core::VarKey;
use apex_solver::factors::pose::BetweenFactor as ApexBetween;
use apex_solver::linalg::LinearSolverType;
use apex_solver::manifold::LieGroup;
use apex_solver::{ManifoldType, NoiseModel, SE3};
use factor_core::Factor;
use slam_data::PoseGraph;
use slam_factors::SqrtInformation6;
use slam_problems::ProblemError;
pub use slam_problems::pose_graph::{edge_name, endpoints, factor_of, initial_vertices, se3};

use crate::adapter::ApexFactor;
use crate::builder::ProblemBuilder;
use crate::built::{Built, Damping};
use crate::options::{BuildError, BuildOptions, FactorChoice};
use crate::variables::apex_pose;

/// The variables of a pose graph, as apex's keys.
pub type PoseGraphKeys = slam_problems::pose_graph::PoseGraphKeys<VarKey>;

/// `P U Pᵀ`: the square-root information in apex's residual order `[ρ, θ]`
/// (this project's is `[δω, δρ]`), for apex's own between factor.
fn apex_sqrt_information(u: &SqrtInformation6<f64>) -> nalgebra_apex::DMatrix<f64> {
    let m = u.matrix();
    let p = |i: usize| (i + 3) % 6;
    nalgebra_apex::DMatrix::from_fn(6, 6, |a, b| m[(p(a), p(b))])
}

/// Builds the pose graph of `graph`.
pub(super) fn build(
    graph: &PoseGraph,
    options: &BuildOptions,
) -> Result<Built<PoseGraphKeys>, BuildError> {
    let vertices = initial_vertices(graph)?;
    let mut builder = ProblemBuilder::with_options(options);
    let mut keys = PoseGraphKeys {
        poses: Vec::with_capacity(vertices.len()),
    };
    let mut by_id = HashMap::with_capacity(vertices.len());
    for v in &vertices {
        let pose = se3(&v.pose);
        let key = builder.variable(ManifoldType::SE3, apex_pose(&pose));
        keys.poses.push((v.id, key));
        by_id.insert(v.id, (key, pose));
    }
    for (index, e) in graph.edges.iter().enumerate() {
        let ((key_i, pose_i), (key_j, pose_j)) = endpoints(graph, index, &by_id)?;
        let factor = factor_of(e, &pose_i, &pose_j)?;
        match options.factors {
            FactorChoice::Ours(kernels) => {
                factor
                    .validate()
                    .map_err(|e| ProblemError::at_initial_values(edge_name(graph, index), e))?;
                let served =
                    ApexFactor::new(&factor, kernels)?.with_rejections(builder.rejections());
                builder.block(&[key_i, key_j], Arc::new(served), None)?;
            }
            FactorChoice::Apex => {
                let measured = SE3::from_param_slice(&apex_pose(&factor.measured));
                let noise =
                    NoiseModel::from_sqrt_info(apex_sqrt_information(&factor.sqrt_information))
                        .map_err(|e| BuildError::Solver(e.to_string()))?;
                builder.block(
                    &[key_i, key_j],
                    Arc::new(ApexBetween::new(measured)),
                    Some(noise),
                )?;
            }
        }
    }
    // The gauge: the first pose fixed.
    if let Some(&(_, key)) = keys.poses.first() {
        builder.fix(key, 6)?;
    }
    // Poses are in one unit system (metres and radians, whitened by the
    // edges' information): uniform damping, which reaches sphere2500's
    // optimum in a third of the iterations the diagonal one needs.
    builder.damping(Damping::Uniform);
    builder.finish(keys, LinearSolverType::SparseCholesky)
}
