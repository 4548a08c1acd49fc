//! Pose-graph optimization of g2o and EDGE3 graphs: the vertices a solve
//! starts from, each edge's factor and name in errors, and a solution
//! written back as a graph.

use std::collections::HashMap;

use factor_core::lie::{Quaternion, Se3, Se3RhoTheta, So3};
use slam_data::{Edge, Pose, PoseGraph, Rotation, Vertex, ordinal};
use slam_factors::{BetweenFactor, SqrtInformation6};

use crate::error::ProblemError;

/// The variables of a pose graph: each vertex id and its pose's key, in the
/// file's vertex order (or the odometry chain's, for a file without
/// vertices).
///
/// By key type `K`: each solver's own (apex-solver's `VarKey`, the
/// Schur-complement solver's variable ids).
#[derive(Debug, Clone)]
pub struct PoseGraphKeys<K> {
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

/// The vertices a solve starts from: the file's, or for a file without
/// vertices (EDGE3) the odometry chain's.
///
/// # Errors
///
/// [`ProblemError::Data`] for a file without vertices whose odometry does
/// not chain.
pub fn initial_vertices(graph: &PoseGraph) -> Result<Vec<Vertex>, ProblemError> {
    if graph.vertices.is_empty() {
        graph
            .odometry_initial_values()
            .map_err(|e| ProblemError::Data(format!("no vertices to start from: {e}")))
    } else {
        Ok(graph.vertices.clone())
    }
}

/// The variables, keys `T`, of the two poses edge `index` joins.
///
/// # Errors
///
/// [`ProblemError::Data`] for an edge on a pose `by_id` does not hold.
pub fn endpoints<T: Copy>(
    graph: &PoseGraph,
    index: usize,
    by_id: &HashMap<usize, T>,
) -> Result<(T, T), ProblemError> {
    let e = &graph.edges[index];
    match (by_id.get(&e.from), by_id.get(&e.to)) {
        (Some(i), Some(j)) => Ok((*i, *j)),
        _ => Err(ProblemError::Data(format!(
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
pub fn factor_of(e: &Edge, i: &Se3<f64>, j: &Se3<f64>) -> Result<BetweenFactor, ProblemError> {
    let sqrt_information = SqrtInformation6::from_information(&e.information).ok_or_else(|| {
        ProblemError::Data(format!(
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

impl<K: Copy> PoseGraphKeys<K> {
    /// `graph` with the vertices of the values `value(key)` (a solution's;
    /// all of them, also when the file had none), each pose read from its
    /// values by `pose` (in the solver's chart).
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

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix6, Vector3};

    use super::*;

    /// An edge whose information is not positive definite makes no factor:
    /// a data error naming the edge, not a panic.
    #[test]
    fn an_indefinite_information_is_a_data_error() {
        let identity = Se3::identity();
        let mut information = Matrix6::identity();
        information[(2, 2)] = -1.0;
        let edge = Edge {
            from: 3,
            to: 4,
            measurement: Pose {
                translation: Vector3::new(1.0, 0.0, 0.0),
                rotation: Rotation::Quaternion([0.0, 0.0, 0.0, 1.0]),
            },
            information,
        };
        assert_eq!(
            factor_of(&edge, &identity, &identity).unwrap_err(),
            ProblemError::Data(
                "edge 3 → 4: the information matrix is not positive definite".into()
            )
        );
        information[(2, 2)] = 1.0;
        let edge = Edge {
            information,
            ..edge
        };
        assert!(factor_of(&edge, &identity, &identity).is_ok());
    }
}
