//! g2o's graphs of lines, planes and points (`types_slam3d_addons` and
//! `types_slam3d`, what g2o's simulators write) with g2o's own error
//! definitions, built from the same vertices and edges as the general path
//! (`slam_problems::g2o_edges`), each edge whitened by the square
//! root of its information, so the cost is half g2o's χ²; or with the
//! documents' line and plane factors in place of g2o's line and plane
//! edges ([`LandmarkFactors::Documents`]: `slam_factors::g2o`'s
//! `LineObservationOnBody` and `PlaneFactorOnBody`, the documents' factors
//! on g2o's body-to-world pose, the information moved into their residual
//! spaces as `g2o_edges::documents_factor` moves it).
//!
//! The poses (robot poses and sensor offsets) are reduced. A line, plane
//! or point is eliminated when at most [`MAX_OBSERVERS`] poses observe it;
//! one seen from more stays in the reduced system, where the sparse
//! Cholesky factorization's fill-reducing ordering puts it last (a row of
//! fill), because eliminated it would join all its poses pairwise (on
//! g2o's simulated graphs, three lines seen from all 160 poses made the
//! reduced system dense: 12 ms per factorization against 0.3 ms).
//!
//! None of g2o's factors has fused normal-equation kernels: each goes
//! through the per-factor path (`Problem::add_linearized`), with
//! [`Jacobians::Kernel`] (`EDGE_SE3:QUAT` through its generated kernel,
//! the line, plane, point and prior edges by dual numbers) or, with
//! `Kernels::Dual`, every edge by dual numbers.

use std::collections::{HashMap, HashSet};

use factor_core::lie::Se3RhoTheta;
use factor_core::noise::Noise;
use factor_core::{Factor, Storage};
use factor_minimizer::Damping;
use slam_data::G2oGraph;
use slam_factors::g2o::{LineObservationOnBody, PlaneFactorOnBody};
use slam_problems::Kernels;
use slam_problems::ProblemError;
use slam_problems::g2o_edges::LandmarkFactors;
use slam_problems::g2o_edges::{self, DocumentsFactor, G2oFactor, Vertices};

use super::error::BuildError;
use crate::problem::{Jacobians, Problem, VariableId};

/// The variables of a line and plane graph, by vertex id, in file order.
#[derive(Debug, Clone)]
pub struct G2oGraphKeys {
    /// Robot poses and sensor offsets (`Se3RhoTheta`, body to world).
    pub poses: Vec<(usize, VariableId)>,
    /// Lines (`OrthonormalLine`).
    pub lines: Vec<(usize, VariableId)>,
    /// Planes (`InfinitePlane`).
    pub planes: Vec<(usize, VariableId)>,
    /// Points (`Vector3`).
    pub points: Vec<(usize, VariableId)>,
}

/// The most poses that may observe a landmark that is eliminated.
pub const MAX_OBSERVERS: usize = 16;

/// A variable per vertex of `values`, recorded by id in `by_id`; held
/// fixed when among the graph's `fixed`, else eliminated when `eliminate`
/// says so of its id.
fn add_all<V: Storage<f64>>(
    problem: &mut Problem,
    values: &[(usize, V)],
    eliminate: impl Fn(usize) -> bool,
    fixed: &[usize],
    by_id: &mut HashMap<usize, VariableId>,
) -> Vec<(usize, VariableId)> {
    values
        .iter()
        .map(|(id, value)| {
            let variable = problem.add_variable(&value.to_scalars());
            if fixed.contains(id) {
                problem.fix(variable);
            } else if eliminate(*id) {
                problem.eliminate(variable);
            }
            by_id.insert(*id, variable);
            (*id, variable)
        })
        .collect()
}

/// Builds `graph` as the general path does with `landmarks`' factors for
/// the lines and planes: the file's `FIX` vertices held fixed, damped
/// uniformly (metres and radians, whitened by the edges' information, as a
/// pose graph).
pub(super) fn build(
    graph: &G2oGraph,
    kernels: Kernels,
    landmarks: LandmarkFactors,
) -> Result<(Problem, G2oGraphKeys), BuildError> {
    let vertices = Vertices::read(graph)?;
    let mut problem = Problem::new();
    let mut by_id = HashMap::new();
    let fixed = &graph.fixed;
    let edges = g2o_edges::edges(graph, &vertices)?;
    // The distinct poses that observe each landmark.
    let mut observers: HashMap<usize, HashSet<usize>> = HashMap::new();
    for edge in &edges {
        if let [pose, landmark, ..] = edge.vertices[..]
            && !matches!(edge.factor, G2oFactor::Pose(_))
        {
            observers.entry(landmark).or_default().insert(pose);
        }
    }
    let few = |id: usize| observers.get(&id).is_some_and(|o| o.len() <= MAX_OBSERVERS);
    let keys = G2oGraphKeys {
        poses: add_all(&mut problem, &vertices.poses, |_| false, fixed, &mut by_id),
        lines: add_all(&mut problem, &vertices.lines, few, fixed, &mut by_id),
        planes: add_all(&mut problem, &vertices.planes, few, fixed, &mut by_id),
        points: add_all(&mut problem, &vertices.points, few, fixed, &mut by_id),
    };
    let jacobians = Jacobians::from(kernels);
    for edge in edges {
        let ids: Vec<VariableId> = edge.vertices.iter().map(|id| by_id[id]).collect();
        let which = || edge.describe();
        if landmarks == LandmarkFactors::Documents
            && let Some(documents) = g2o_edges::documents_factor(graph, &edge)
        {
            let (factor, noise) = documents?;
            add_documents(&mut problem, factor, &ids[..2], &noise, jacobians, &which)?;
            continue;
        }
        match &edge.factor {
            G2oFactor::Pose(f) => add(&mut problem, f, &ids, &edge.noise, jacobians, &which),
            G2oFactor::Line(f) => add(&mut problem, f, &ids, &edge.noise, jacobians, &which),
            G2oFactor::Plane(f) => add(&mut problem, f, &ids, &edge.noise, jacobians, &which),
            G2oFactor::Point(f) => add(&mut problem, f, &ids, &edge.noise, jacobians, &which),
            G2oFactor::Prior(f) => add(&mut problem, f, &ids, &edge.noise, jacobians, &which),
        }?;
    }
    problem.set_damping(Damping::Uniform);
    Ok((problem, keys))
}

/// Adds the documents' `factor` of a line or plane edge on its pose and
/// landmark `ids`, as the factor on the body-to-world pose that `ids[0]`
/// holds, so the solver keeps g2o's vertices whichever factors measure them
/// (the sensor offset of a plane edge, fixed, is already in the
/// measurement).
fn add_documents(
    problem: &mut Problem,
    factor: DocumentsFactor,
    ids: &[VariableId],
    noise: &Noise,
    jacobians: Jacobians,
    which: &dyn Fn() -> String,
) -> Result<(), BuildError> {
    let pose = Se3RhoTheta::from_scalars(problem.value(ids[0]));
    match factor {
        DocumentsFactor::Line(f) => {
            let on_body = LineObservationOnBody::new(&f, pose);
            add(problem, &on_body, ids, noise, jacobians, which)
        }
        DocumentsFactor::Plane(f) => {
            let on_body = PlaneFactorOnBody::new(&f, pose);
            add(problem, &on_body, ids, noise, jacobians, which)
        }
    }
}

/// Adds `factor` on `ids` with `noise`, linearized one at a time by
/// `jacobians`, after its validation at the initial values.
fn add<F: Factor + Send + Sync + 'static>(
    problem: &mut Problem,
    factor: &F,
    ids: &[VariableId],
    noise: &Noise,
    jacobians: Jacobians,
    which: &dyn Fn() -> String,
) -> Result<(), BuildError> {
    factor
        .validate()
        .map_err(|e| ProblemError::at_initial_values(which(), e))?;
    problem.add_linearized(factor, ids, noise, None, jacobians)?;
    Ok(())
}

impl G2oGraphKeys {
    /// `graph` with the vertices' values `value` gives (after a solve, the
    /// solution; `g2o_edges::solution`).
    pub fn write<'a>(&self, graph: &G2oGraph, value: impl Fn(VariableId) -> &'a [f64]) -> G2oGraph {
        fn read<'a, V: Storage<f64>>(
            keys: &[(usize, VariableId)],
            value: &impl Fn(VariableId) -> &'a [f64],
        ) -> Vec<(usize, V)> {
            keys.iter()
                .map(|&(id, v)| (id, V::from_scalars(value(v))))
                .collect()
        }
        let solved = Vertices {
            poses: read(&self.poses, &value),
            lines: read(&self.lines, &value),
            planes: read(&self.planes, &value),
            points: read(&self.points, &value),
        };
        g2o_edges::solution(graph, &solved)
    }
}
