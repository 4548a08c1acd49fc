//! g2o's graphs of lines, planes and points (`types_slam3d_addons` and
//! `types_slam3d`, what g2o's simulators write): robot poses, 3D lines,
//! planes, points, sensor offsets and pose priors, solved with g2o's own
//! error definitions (so the cost is g2o's `χ² / 2`) or with the documents'
//! line and plane factors.
//!
//! | record | variable / factor ([`LandmarkFactors::G2o`]) | [`LandmarkFactors::Documents`] |
//! | --- | --- | --- |
//! | `VERTEX_SE3:QUAT` | `Se3RhoTheta` (body to world; a sensor offset too) | the same |
//! | `VERTEX_LINE3D` | `OrthonormalLine` | the same |
//! | `VERTEX_PLANE` | `InfinitePlane` | the same |
//! | `VERTEX_TRACKXYZ` | `Vector3` (Euclidean) | the same |
//! | `EDGE_SE3:QUAT` | [`G2oSe3Edge`](slam_factors::G2oSe3Edge), generated kernel | the same |
//! | `EDGE_SE3_LINE3D` | [`G2oLineEdge`](slam_factors::G2oLineEdge), dual numbers | [`LineObservation`](slam_factors::LineObservation) (generated kernel) on `X⁻¹` ([`InversePose`]), information moved into its residual space ([`slam_factors::g2o::line_observation`]) |
//! | `EDGE_SE3_PLANE_CALIB` | [`G2oPlaneEdge`](slam_factors::G2oPlaneEdge), dual numbers | [`PlaneFactor`](slam_factors::PlaneFactor) (generated kernel) on `X⁻¹`, the measurement moved into the body frame through the offset, which must be fixed ([`slam_factors::g2o::plane_observation`]) |
//! | `EDGE_SE3_TRACKXYZ` | [`G2oPointEdge`](slam_factors::G2oPointEdge), dual numbers, its `PARAMS_SE3OFFSET` a constant | the same |
//! | `EDGE_SE3_PRIOR` | [`G2oPriorEdge`](slam_factors::G2oPriorEdge), dual numbers, its `PARAMS_SE3OFFSET` a constant | the same |
//!
//! Each edge is whitened by the square root `Lᵀ` of its information `Ω =
//! L Lᵀ`, so its cost is `½ eᵀ Ω e`: the problem's cost is half g2o's χ².
//! A prior's information may be positive semi-definite (g2o's planar-motion
//! prior weighs the height only): it is whitened by `S = √Λ Vᵀ` of `Ω = V Λ
//! Vᵀ`, whose rows of zero eigenvalues weigh nothing.
//! The vertices of the file's `FIX` lines are held fixed (g2o's gauge).
//! Pose quaternions become apex's unit quaternions (g2o's files write six
//! digits, so they are unit only to about 1e-6: the initial cost differs
//! from g2o's by about 1e-7 relative); measurements are used as written.

use std::collections::HashMap;
use std::sync::Arc;

use apex_solver::core::VarKey;
use apex_solver::core::variable::ManifoldVariable;
use apex_solver::linalg::LinearSolverType;
use factor_core::geometry::{InfinitePlane, OrthonormalLine};
use factor_core::lie::Se3RhoTheta;
use nalgebra::Vector3;
use slam_data::G2oGraph;
use slotmap::SlotMap;

use slam_problems::ProblemError;
pub use slam_problems::g2o_edges::LandmarkFactors;
use slam_problems::g2o_edges::{self, DocumentsFactor, G2oEdge, G2oFactor, Vertices};

use crate::adapter::{ApexFactor, Kernels};
use crate::builder::{AnyVariable, Noise, ProblemBuilder, Variable, value_of};
use crate::built::{Built, Damping};
use crate::inverse_pose::InversePose;
use crate::options::{BuildError, BuildOptions, FactorChoice, Robust};

/// The variables of a line and plane graph, by vertex id, in file order.
#[derive(Debug, Clone)]
pub struct G2oGraphKeys {
    /// Robot poses and sensor offsets.
    pub poses: Vec<(usize, Variable<Se3RhoTheta<f64>>)>,
    /// Lines.
    pub lines: Vec<(usize, Variable<OrthonormalLine<f64>>)>,
    /// Planes.
    pub planes: Vec<(usize, Variable<InfinitePlane<f64>>)>,
    /// Points.
    pub points: Vec<(usize, Variable<Vector3<f64>>)>,
}

/// Builds the graph with `landmarks`' factors for the lines and planes.
///
/// # Errors
///
/// A graph that does not [validate](G2oGraph::validate), a landmark without
/// an orthonormal representation, an edge degenerate at the initial values,
/// the documents' plane factor asked for with a free sensor offset, apex's
/// refusal.
pub fn build_with(
    graph: &G2oGraph,
    options: &BuildOptions,
    landmarks: LandmarkFactors,
) -> Result<Built<G2oGraphKeys>, BuildError> {
    let vertices = Vertices::read(graph)?;
    let kernels = match options.factors {
        FactorChoice::Ours(kernels) => kernels,
        FactorChoice::Apex => {
            return Err(ProblemError::Unavailable(
                "apex-solver has no factors for g2o's lines and planes".into(),
            )
            .into());
        }
    };
    let mut builder = ProblemBuilder::with_options(options);
    let mut by_id: HashMap<usize, AnyVariable> = HashMap::new();
    let keys = G2oGraphKeys {
        poses: add_all(&mut builder, &vertices.poses, &mut by_id),
        lines: add_all(&mut builder, &vertices.lines, &mut by_id),
        planes: add_all(&mut builder, &vertices.planes, &mut by_id),
        points: add_all(&mut builder, &vertices.points, &mut by_id),
    };
    for id in &graph.fixed {
        if let Some(v) = by_id.get(id) {
            builder.fix_any(v)?;
        }
    }
    let loss = options.robust;
    for edge in g2o_edges::edges(graph, &vertices)? {
        let which = || edge.describe();
        let variables: Vec<AnyVariable> =
            edge.vertices.iter().map(|id| by_id[id].clone()).collect();
        let noise = &edge.noise;
        let added = match (&edge.factor, landmarks) {
            (G2oFactor::Pose(f), _) => builder.add_factor(f, &variables, noise, loss),
            (G2oFactor::Line(f), LandmarkFactors::G2o) => {
                builder.add_factor_dual(f, &variables, noise, loss)
            }
            (G2oFactor::Plane(f), LandmarkFactors::G2o) => {
                builder.add_factor_dual(f, &variables, noise, loss)
            }
            (G2oFactor::Point(f), _) => builder.add_factor_dual(f, &variables, noise, loss),
            (G2oFactor::Prior(f), _) => builder.add_factor_dual(f, &variables, noise, loss),
            (G2oFactor::Line(_) | G2oFactor::Plane(_), LandmarkFactors::Documents) => {
                documents_factor(&mut builder, graph, &edge, &variables, kernels, loss)
            }
        };
        added.map_err(|err| within(err, &which))?;
    }
    // Metres and radians, whitened by the edges' information, as pose
    // graphs: uniform damping.
    builder.damping(Damping::Uniform);
    builder.finish(keys, LinearSolverType::SparseCholesky)
}

/// Adds a variable per vertex of `values` (in order), recorded by id in
/// `by_id`; their keys.
fn add_all<V>(
    builder: &mut ProblemBuilder,
    values: &[(usize, V)],
    by_id: &mut HashMap<usize, AnyVariable>,
) -> Vec<(usize, Variable<V>)>
where
    V: factor_core::host::HostMap<factor_core::host::Apex> + factor_core::Storage<f64> + 'static,
{
    values
        .iter()
        .map(|(id, value)| {
            let variable = builder.add_variable(value);
            by_id.insert(*id, variable.erase());
            (*id, variable)
        })
        .collect()
}

/// Adds the documents' factor of a line or plane `edge` on `variables`
/// (the pose, then the landmark), served on the body-to-world pose
/// ([`g2o_edges::documents_factor`]).
fn documents_factor(
    builder: &mut ProblemBuilder,
    graph: &G2oGraph,
    edge: &G2oEdge,
    variables: &[AnyVariable],
    kernels: Kernels,
    loss: Option<Robust>,
) -> Result<(), BuildError> {
    let which = || edge.describe();
    let keys: Vec<VarKey> = [variables[0].keys(), variables[1].keys()].concat();
    let (factor, noise) = g2o_edges::documents_factor(graph, edge)
        .expect("only lines and planes have documents' factors")?;
    match factor {
        DocumentsFactor::Line(f) => {
            on_inverse_pose(builder, &f, kernels, &keys, &noise, loss, &which)
        }
        DocumentsFactor::Plane(f) => {
            on_inverse_pose(builder, &f, kernels, &keys, &noise, loss, &which)
        }
    }
}

/// `which: ` before an error's message.
fn within(error: BuildError, which: &dyn Fn() -> String) -> BuildError {
    match error {
        BuildError::Problem(ProblemError::Data(what)) => {
            ProblemError::Data(format!("{}: {what}", which())).into()
        }
        BuildError::Problem(ProblemError::Degenerate { error, .. }) => {
            ProblemError::at_initial_values(which(), error).into()
        }
        other => other,
    }
}

/// Adds a documents' factor whose first variable is the world-to-camera
/// pose, on the body-to-world pose variable `keys[0]` ([`InversePose`]).
fn on_inverse_pose<F: factor_core::host::HostKernel<factor_core::host::Apex> + 'static>(
    builder: &mut ProblemBuilder,
    factor: &F,
    kernels: Kernels,
    keys: &[VarKey],
    noise: &Noise,
    loss: Option<Robust>,
    which: &dyn Fn() -> String,
) -> Result<(), BuildError> {
    let model = crate::builder::model(noise, F::RESIDUAL_DIM)
        .map_err(|e| ProblemError::Data(format!("{}: noise model: {e}", which())))?;
    let served = ApexFactor::new(factor, kernels)?.with_rejections(builder.rejections());
    builder.block_with_loss(
        keys,
        Arc::new(InversePose::new(Arc::new(served))),
        model,
        loss,
    )
}

impl G2oGraphKeys {
    /// `graph` with the solution's vertices ([`g2o_edges::solution`]).
    pub fn write(
        &self,
        graph: &G2oGraph,
        values: &SlotMap<VarKey, Box<dyn ManifoldVariable>>,
    ) -> G2oGraph {
        fn read<V>(
            values: &SlotMap<VarKey, Box<dyn ManifoldVariable>>,
            keys: &[(usize, Variable<V>)],
        ) -> Vec<(usize, V)>
        where
            V: factor_core::host::HostMap<factor_core::host::Apex> + factor_core::Storage<f64>,
        {
            keys.iter()
                .map(|(id, v)| (*id, value_of(values, v)))
                .collect()
        }
        let solved = Vertices {
            poses: read(values, &self.poses),
            lines: read(values, &self.lines),
            planes: read(values, &self.planes),
            points: read(values, &self.points),
        };
        g2o_edges::solution(graph, &solved)
    }
}
