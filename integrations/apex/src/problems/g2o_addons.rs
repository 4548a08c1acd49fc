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
//! | `EDGE_SE3:QUAT` | [`G2oSe3Edge`], generated kernel | the same |
//! | `EDGE_SE3_LINE3D` | [`G2oLineEdge`], dual numbers | [`LineObservation`](slam_factors::LineObservation) (generated kernel) on `X⁻¹` ([`InversePose`]), information moved into its residual space ([`slam_factors::g2o::line_observation`]) |
//! | `EDGE_SE3_PLANE_CALIB` | [`G2oPlaneEdge`], dual numbers | [`PlaneFactor`](slam_factors::PlaneFactor) (generated kernel) on `X⁻¹`, the measurement moved into the body frame through the offset, which must be fixed ([`slam_factors::g2o::plane_observation`]) |
//! | `EDGE_SE3_TRACKXYZ` | [`G2oPointEdge`], dual numbers, its `PARAMS_SE3OFFSET` a constant | the same |
//! | `EDGE_SE3_PRIOR` | [`G2oPriorEdge`], dual numbers, its `PARAMS_SE3OFFSET` a constant | the same |
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
use factor_core::lie::{Quaternion, Se3, Se3RhoTheta, So3};
use nalgebra::{DMatrix, Matrix6, SMatrix, Vector3};
use slam_data::{G2oGraph, LineVertex, PlaneVertex, PointVertex, Pose, Rotation, Vertex};
use slam_factors::g2o::{line_landmark, line_observation, plane_observation};
use slam_factors::{G2oLineEdge, G2oPlaneEdge, G2oPointEdge, G2oPriorEdge, G2oSe3Edge};
use slotmap::SlotMap;

use crate::adapter::{ApexFactor, Kernels};
use crate::builder::{Noise, ProblemBuilder, Variable, value_of};
use crate::built::{Built, Damping};
use crate::inverse_pose::InversePose;
use crate::options::{BuildError, BuildOptions, FactorChoice};

/// Which factors measure the lines and planes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LandmarkFactors {
    /// g2o's own errors ([`G2oLineEdge`], [`G2oPlaneEdge`]): the cost is
    /// g2o's.
    #[default]
    G2o,
    /// The documents' orthonormal-line and quaternion-plane factors
    /// ([`slam_factors::LineObservation`], [`slam_factors::PlaneFactor`]).
    Documents,
}

impl LandmarkFactors {
    /// `g2o` or `documents`.
    pub fn name(self) -> &'static str {
        match self {
            LandmarkFactors::G2o => "g2o",
            LandmarkFactors::Documents => "documents",
        }
    }
}

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

/// A file's pose with its quaternion as written (g2o's factors use it so).
fn as_written(pose: &Pose) -> Se3<f64> {
    match pose.rotation {
        Rotation::Quaternion([x, y, z, w]) => Se3::new(
            So3::from_quaternion(Quaternion::new(x, y, z, w)),
            pose.translation,
        ),
        Rotation::RollPitchYaw(_) => crate::problems::pose_graph::se3(pose),
    }
}

/// The noise model of an information matrix `Ω`: `S = Lᵀ`, `Ω = L Lᵀ`.
fn sqrt_information<const N: usize>(
    information: &SMatrix<f64, N, N>,
    which: &dyn Fn() -> String,
) -> Result<Noise, BuildError> {
    let l = information.cholesky().ok_or_else(|| {
        BuildError::Data(format!(
            "{}: the information matrix is not positive definite",
            which()
        ))
    })?;
    let s = l.l().transpose();
    Ok(Noise::SqrtInformation(DMatrix::from_column_slice(
        N,
        N,
        s.as_slice(),
    )))
}

/// The noise model of a positive semi-definite information matrix `Ω = V Λ
/// Vᵀ` (a prior's): `S = √Λ Vᵀ`, so `Sᵀ S = Ω`; eigenvalues that rounding
/// left below zero count as zero (the reader rejects any below `−1e-12`
/// times the largest).
fn sqrt_semidefinite_information(information: &Matrix6<f64>) -> Noise {
    let eigen = information.symmetric_eigen();
    let roots = eigen.eigenvalues.map(|l| l.max(0.0).sqrt());
    let s = Matrix6::from_diagonal(&roots) * eigen.eigenvectors.transpose();
    Noise::SqrtInformation(DMatrix::from_column_slice(6, 6, s.as_slice()))
}

/// A vertex's variable by id, or the edge's error.
fn find<'a, V>(
    vars: &'a HashMap<usize, (Variable<V>, V)>,
    id: usize,
    which: &dyn Fn() -> String,
) -> Result<&'a (Variable<V>, V), BuildError> {
    vars.get(&id).ok_or_else(|| {
        BuildError::Data(format!(
            "{}: vertex {id} is not of the kind joined",
            which()
        ))
    })
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
    graph.validate().map_err(BuildError::Data)?;
    let kernels = match options.factors {
        FactorChoice::Ours(kernels) => kernels,
        FactorChoice::Apex => {
            return Err(BuildError::Unavailable(
                "apex-solver has no factors for g2o's lines and planes".into(),
            ));
        }
    };
    let mut builder = ProblemBuilder::with_options(options);
    let mut keys = G2oGraphKeys {
        poses: Vec::new(),
        lines: Vec::new(),
        planes: Vec::new(),
        points: Vec::new(),
    };
    let mut poses = HashMap::new();
    for Vertex { id, pose } in &graph.poses {
        let value = Se3RhoTheta::new(as_written(pose));
        let variable = builder.add_variable(&value);
        keys.poses.push((*id, variable.clone()));
        poses.insert(*id, (variable, value));
    }
    let mut lines = HashMap::new();
    for LineVertex { id, line } in &graph.lines {
        let value =
            line_landmark(line).map_err(|e| BuildError::Data(format!("line vertex {id}: {e}")))?;
        let variable = builder.add_variable(&value);
        keys.lines.push((*id, variable.clone()));
        lines.insert(*id, (variable, value));
    }
    let mut planes = HashMap::new();
    for PlaneVertex { id, plane } in &graph.planes {
        let value = InfinitePlane::from_coefficients(plane);
        let variable = builder.add_variable(&value);
        keys.planes.push((*id, variable.clone()));
        planes.insert(*id, (variable, value));
    }
    let mut points = HashMap::new();
    for PointVertex { id, point } in &graph.points {
        let variable = builder.add_variable(point);
        keys.points.push((*id, variable.clone()));
        points.insert(*id, (variable, *point));
    }
    for id in &graph.fixed {
        if let Some((v, _)) = poses.get(id) {
            builder.fix_variable(v)?;
        } else if let Some((v, _)) = lines.get(id) {
            builder.fix_variable(v)?;
        } else if let Some((v, _)) = planes.get(id) {
            builder.fix_variable(v)?;
        } else if let Some((v, _)) = points.get(id) {
            builder.fix_variable(v)?;
        }
    }
    // Sensor offsets by parameter id, quaternions as written (g2o's).
    let offsets: HashMap<usize, Se3<f64>> = graph
        .offsets
        .iter()
        .map(|p| (p.id, as_written(&p.offset)))
        .collect();
    let offset = |id: usize, which: &dyn Fn() -> String| {
        offsets
            .get(&id)
            .copied()
            .ok_or_else(|| BuildError::Data(format!("{}: parameter {id} is not defined", which())))
    };
    let loss = options.robust;
    for (k, e) in graph.pose_edges.iter().enumerate() {
        let which = || format!("pose edge {k} ({} → {})", e.from, e.to);
        let (vi, xi) = find(&poses, e.from, &which)?;
        let (vj, xj) = find(&poses, e.to, &which)?;
        let factor = G2oSe3Edge {
            measured: as_written(&e.measurement),
            pose_i: *xi,
            pose_j: *xj,
        };
        let noise = sqrt_information(&e.information, &which)?;
        builder
            .add_factor(&factor, &[vi.erase(), vj.erase()], &noise, loss)
            .map_err(|err| within(err, &which))?;
    }
    for (k, e) in graph.line_edges.iter().enumerate() {
        let which = || format!("line edge {k} (pose {} → line {})", e.pose, e.line);
        let (vx, x) = find(&poses, e.pose, &which)?;
        let (vl, line) = find(&lines, e.line, &which)?;
        match landmarks {
            LandmarkFactors::G2o => {
                let factor = G2oLineEdge {
                    measured: e.measurement,
                    pose: *x,
                    line: *line,
                };
                let noise = sqrt_information(&e.information, &which)?;
                builder
                    .add_factor_dual(&factor, &[vx.erase(), vl.erase()], &noise, loss)
                    .map_err(|err| within(err, &which))?;
            }
            LandmarkFactors::Documents => {
                let (factor, information) =
                    line_observation(&x.se3(), line, &e.measurement, &e.information)
                        .map_err(|err| BuildError::Data(format!("{}: {err}", which())))?;
                let noise = sqrt_information(&information, &which)?;
                let keys: Vec<VarKey> = [vx.keys(), vl.keys()].concat();
                on_inverse_pose(&mut builder, &factor, kernels, &keys, &noise, loss, &which)?;
            }
        }
    }
    for (k, e) in graph.plane_edges.iter().enumerate() {
        let which = || {
            format!(
                "plane edge {k} (pose {} → plane {}, offset {})",
                e.pose, e.plane, e.offset
            )
        };
        let (vx, x) = find(&poses, e.pose, &which)?;
        let (vp, plane) = find(&planes, e.plane, &which)?;
        let (vs, s) = find(&poses, e.offset, &which)?;
        match landmarks {
            LandmarkFactors::G2o => {
                let factor = G2oPlaneEdge {
                    measured: e.measurement,
                    pose: *x,
                    plane: *plane,
                    offset: *s,
                };
                let noise = sqrt_information(&e.information, &which)?;
                builder
                    .add_factor_dual(&factor, &[vx.erase(), vp.erase(), vs.erase()], &noise, loss)
                    .map_err(|err| within(err, &which))?;
            }
            LandmarkFactors::Documents => {
                if !graph.fixed.contains(&e.offset) {
                    return Err(BuildError::Unavailable(format!(
                        "{}: the sensor offset is free (calibrated), which the documents' plane \
                         factor (one pose) cannot estimate; solve it with g2o's factors",
                        which()
                    )));
                }
                let (factor, information) =
                    plane_observation(&x.se3(), plane, &s.se3(), &e.measurement, &e.information)
                        .map_err(|error| BuildError::Degenerate {
                            which: format!("{} at the initial values", which()),
                            error,
                        })?;
                let noise = sqrt_information(&information, &which)?;
                let keys: Vec<VarKey> = [vx.keys(), vp.keys()].concat();
                on_inverse_pose(&mut builder, &factor, kernels, &keys, &noise, loss, &which)?;
            }
        }
    }
    for (k, e) in graph.point_edges.iter().enumerate() {
        let which = || format!("point edge {k} (pose {} → point {})", e.pose, e.point);
        let (vx, x) = find(&poses, e.pose, &which)?;
        let (vp, p) = find(&points, e.point, &which)?;
        let factor = G2oPointEdge {
            measured: e.measurement,
            offset: offset(e.offset, &which)?,
            pose: *x,
            point: *p,
        };
        let noise = sqrt_information(&e.information, &which)?;
        builder
            .add_factor_dual(&factor, &[vx.erase(), vp.erase()], &noise, loss)
            .map_err(|err| within(err, &which))?;
    }
    for (k, e) in graph.priors.iter().enumerate() {
        let which = || format!("prior edge {k} (pose {})", e.pose);
        let (vx, x) = find(&poses, e.pose, &which)?;
        let factor = G2oPriorEdge {
            measured: as_written(&e.measurement),
            offset: offset(e.offset, &which)?,
            pose: *x,
        };
        let noise = sqrt_semidefinite_information(&e.information);
        builder
            .add_factor_dual(&factor, &[vx.erase()], &noise, loss)
            .map_err(|err| within(err, &which))?;
    }
    // Metres and radians, whitened by the edges' information, as pose
    // graphs: uniform damping.
    builder.damping(Damping::Uniform);
    builder.finish(keys, LinearSolverType::SparseCholesky)
}

/// `which: ` before an error's message.
fn within(error: BuildError, which: &dyn Fn() -> String) -> BuildError {
    match error {
        BuildError::Data(what) => BuildError::Data(format!("{}: {what}", which())),
        BuildError::Degenerate { error, .. } => BuildError::Degenerate {
            which: format!("{} at the initial values", which()),
            error,
        },
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
    loss: Option<crate::options::Robust>,
    which: &dyn Fn() -> String,
) -> Result<(), BuildError> {
    factor.validate().map_err(|error| BuildError::Degenerate {
        which: format!("{} at the initial values", which()),
        error,
    })?;
    let model = crate::builder::model(noise, F::RESIDUAL_DIM)
        .map_err(|e| BuildError::Data(format!("{}: noise model: {e}", which())))?;
    let served = ApexFactor::new(factor, kernels)?.with_rejections(builder.rejections());
    builder.block_with_loss(
        keys,
        Arc::new(InversePose::new(Arc::new(served))),
        model,
        loss,
    )
}

impl G2oGraphKeys {
    /// `graph` with the solution's vertices: poses as unit quaternions,
    /// lines as `[w, d]` (unit direction), planes as `[n, d]` (unit normal),
    /// points as they are.
    pub fn write(
        &self,
        graph: &G2oGraph,
        values: &SlotMap<VarKey, Box<dyn ManifoldVariable>>,
    ) -> G2oGraph {
        let mut solved = graph.clone();
        let poses: HashMap<usize, Se3<f64>> = self
            .poses
            .iter()
            .map(|(id, v)| (*id, value_of(values, v).se3()))
            .collect();
        for vertex in &mut solved.poses {
            if let Some(pose) = poses.get(&vertex.id) {
                let q = pose.rotation.quaternion;
                vertex.pose = Pose {
                    translation: pose.translation,
                    rotation: Rotation::Quaternion([q.x, q.y, q.z, q.w]),
                };
            }
        }
        let lines: HashMap<usize, OrthonormalLine<f64>> = self
            .lines
            .iter()
            .map(|(id, v)| (*id, value_of(values, v)))
            .collect();
        for vertex in &mut solved.lines {
            if let Some(line) = lines.get(&vertex.id) {
                let (w, d) = (line.moment(), line.direction());
                vertex.line = nalgebra::Vector6::new(w.x, w.y, w.z, d.x, d.y, d.z);
            }
        }
        let planes: HashMap<usize, InfinitePlane<f64>> = self
            .planes
            .iter()
            .map(|(id, v)| (*id, value_of(values, v)))
            .collect();
        for vertex in &mut solved.planes {
            if let Some(plane) = planes.get(&vertex.id) {
                let (n, d) = plane.normal_offset();
                vertex.plane = nalgebra::Vector4::new(n.x, n.y, n.z, d);
            }
        }
        let points: HashMap<usize, Vector3<f64>> = self
            .points
            .iter()
            .map(|(id, v)| (*id, value_of(values, v)))
            .collect();
        for vertex in &mut solved.points {
            if let Some(point) = points.get(&vertex.id) {
                vertex.point = *point;
            }
        }
        solved
    }
}
