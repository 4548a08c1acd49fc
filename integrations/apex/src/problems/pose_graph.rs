//! Pose-graph optimization of g2o and EDGE3 graphs.

use std::collections::HashMap;
use std::sync::Arc;

use apex_solver::core::VarKey;
use apex_solver::factors::pose::BetweenFactor as ApexBetween;
use apex_solver::linalg::LinearSolverType;
use apex_solver::manifold::LieGroup;
use apex_solver::{ManifoldType, NoiseModel, SE3};
use factor_core::Factor;
use factor_core::lie::{Quaternion, Se3, Se3RhoTheta, So3};
use slam_data::{Edge, Pose, PoseGraph, Rotation, Vertex, ordinal};
use slam_factors::{BetweenFactor, SqrtInformation6};

use crate::adapter::ApexFactor;
use crate::builder::ProblemBuilder;
use crate::built::{Built, Damping};
use crate::options::{BuildError, BuildOptions, FactorChoice};
use crate::variables::apex_pose;

/// The variables of a pose graph: each vertex id and its pose's key, in the
/// file's vertex order (or the odometry chain's, for a file without
/// vertices).
///
/// By key type `K`: apex's `VarKey` here, the Schur-complement solver's
/// variable ids in crate `factor-schur`, which builds the same problem.
#[derive(Debug, Clone)]
pub struct PoseGraphKeys<K = VarKey> {
    /// `(id, key)` per pose.
    pub poses: Vec<(usize, K)>,
}

/// A pose of a pose-graph file as this project's `Se3`.
pub fn se3(pose: &Pose) -> Se3<f64> {
    let q = pose.rotation.unit_quaternion();
    Se3::new(
        So3::from_quaternion(Quaternion::new(q.i, q.j, q.k, q.w)),
        pose.translation,
    )
}

/// `P U Pᵀ`: the square-root information in apex's residual order `[ρ, θ]`
/// (this project's is `[δω, δρ]`), for apex's own between factor.
fn apex_sqrt_information(u: &SqrtInformation6<f64>) -> nalgebra_apex::DMatrix<f64> {
    let m = u.matrix();
    let p = |i: usize| (i + 3) % 6;
    nalgebra_apex::DMatrix::from_fn(6, 6, |a, b| m[(p(a), p(b))])
}

/// The vertices a solve starts from: the file's, or for a file without
/// vertices (EDGE3) the odometry chain's.
///
/// # Errors
///
/// [`BuildError::Data`] for a file without vertices whose odometry does
/// not chain.
pub fn initial_vertices(graph: &PoseGraph) -> Result<Vec<Vertex>, BuildError> {
    if graph.vertices.is_empty() {
        graph
            .odometry_initial_values()
            .map_err(|e| BuildError::Data(format!("no vertices to start from: {e}")))
    } else {
        Ok(graph.vertices.clone())
    }
}

/// The variables, keys `T`, of the two poses edge `index` joins.
///
/// # Errors
///
/// [`BuildError::Data`] for an edge on a pose `by_id` does not hold.
pub fn endpoints<T: Copy>(
    graph: &PoseGraph,
    index: usize,
    by_id: &HashMap<usize, T>,
) -> Result<(T, T), BuildError> {
    let e = &graph.edges[index];
    match (by_id.get(&e.from), by_id.get(&e.to)) {
        (Some(i), Some(j)) => Ok((*i, *j)),
        _ => Err(BuildError::Data(format!(
            "{} joins poses {} and {}, not both initialised",
            ordinal("edge", index, graph.edges.len()),
            e.from,
            e.to
        ))),
    }
}

/// Edge `index` as errors name it: `edge 3 (pose 2 → pose 5)`.
pub fn edge_name(graph: &PoseGraph, index: usize) -> String {
    let e = &graph.edges[index];
    format!(
        "{} (pose {} → pose {})",
        ordinal("edge", index, graph.edges.len()),
        e.from,
        e.to
    )
}

/// The factor of edge `e` between poses `i` and `j`.
pub fn factor_of(e: &Edge, i: &Se3<f64>, j: &Se3<f64>) -> Result<BetweenFactor, BuildError> {
    let sqrt_information = SqrtInformation6::from_information(&e.information).ok_or_else(|| {
        BuildError::Data(format!(
            "edge {} → {}: the information matrix is not positive definite",
            e.from, e.to
        ))
    })?;
    Ok(BetweenFactor {
        sqrt_information,
        measured: se3(&e.measurement),
        pose_i: Se3RhoTheta::new(*i),
        pose_j: Se3RhoTheta::new(*j),
    })
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
                factor.validate().map_err(|error| BuildError::Degenerate {
                    which: format!("{} at the initial values", edge_name(graph, index)),
                    error,
                })?;
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

impl<K: Copy> PoseGraphKeys<K> {
    /// `graph` with the vertices of the values `value(key)` (a solution's;
    /// all of them, also when the file had none), each pose read from its
    /// values by `pose` (here [`apex_se3`](crate::variables::apex_se3)).
    pub fn write<'a>(
        &self,
        graph: &PoseGraph,
        pose: impl Fn(&[f64]) -> Se3<f64>,
        value: impl Fn(K) -> &'a [f64],
    ) -> PoseGraph {
        let vertices = self
            .poses
            .iter()
            .map(|&(id, key)| {
                let pose = pose(value(key));
                let q = pose.rotation.quaternion;
                Vertex {
                    id,
                    pose: Pose {
                        translation: pose.translation,
                        rotation: Rotation::Quaternion([q.x, q.y, q.z, q.w]),
                    },
                }
            })
            .collect();
        PoseGraph {
            vertices,
            edges: graph.edges.clone(),
        }
    }
}
