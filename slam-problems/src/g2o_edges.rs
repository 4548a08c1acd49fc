//! g2o's graphs of lines, planes and points as this project's variables
//! and factors, whichever solver takes them: the vertices' initial values
//! ([`Vertices`]), each edge as the factor of g2o's own error definition
//! with its noise model ([`G2oEdge`]), and a solution written back as a
//! graph ([`solution`]); which factors measure the lines and planes
//! ([`LandmarkFactors`]). Crate `factor-apex` builds them for apex-solver,
//! crate `factor-schur` for its own solver.

use std::collections::HashMap;

use factor_core::Factor;
use factor_core::geometry::{InfinitePlane, OrthonormalLine};
use factor_core::lie::{Quaternion, Se3, Se3RhoTheta, So3};
use factor_core::noise::Noise;
use nalgebra::{DMatrix, Matrix6, SMatrix, Vector3, Vector4, Vector6};
use slam_data::{G2oGraph, LineVertex, PlaneVertex, PointVertex, Pose, Rotation, Vertex};
use slam_factors::g2o::{line_landmark, line_observation, plane_observation};
use slam_factors::{
    G2oLineEdge, G2oPlaneEdge, G2oPointEdge, G2oPriorEdge, G2oSe3Edge, LineObservation, PlaneFactor,
};

use crate::error::ProblemError;
use crate::pose_graph;

/// Which factors measure the lines and planes of a graph.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LandmarkFactors {
    /// g2o's own errors ([`G2oLineEdge`], [`G2oPlaneEdge`]): the cost is
    /// g2o's.
    #[default]
    G2o,
    /// The documents' orthonormal-line and quaternion-plane factors
    /// ([`LineObservation`], [`PlaneFactor`]).
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

/// A file's pose with its quaternion as written (g2o's factors use it so).
fn as_written(pose: &Pose) -> Se3<f64> {
    match pose.rotation {
        Rotation::Quaternion([x, y, z, w]) => Se3::new(
            So3::from_quaternion(Quaternion::new(x, y, z, w)),
            pose.translation,
        ),
        Rotation::RollPitchYaw(_) => pose_graph::se3(pose),
    }
}

/// The noise model of an information matrix `Ω`: `S = Lᵀ`, `Ω = L Lᵀ`.
fn sqrt_information<const N: usize>(
    information: &SMatrix<f64, N, N>,
    which: &dyn Fn() -> String,
) -> Result<Noise, ProblemError> {
    let l = information.cholesky().ok_or_else(|| {
        ProblemError::Data(format!(
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

/// The initial values of a graph's vertices, by kind, in file order; pose
/// quaternions normalized, as the solvers keep them (g2o's files write six
/// digits, so they are unit only to about 1e-6), while the measurements
/// are used as written.
#[derive(Debug, Clone)]
pub struct Vertices {
    /// Robot poses and sensor offsets (body to world).
    pub poses: Vec<(usize, Se3RhoTheta<f64>)>,
    /// Lines.
    pub lines: Vec<(usize, OrthonormalLine<f64>)>,
    /// Planes.
    pub planes: Vec<(usize, InfinitePlane<f64>)>,
    /// Points.
    pub points: Vec<(usize, Vector3<f64>)>,
}

impl Vertices {
    /// The vertices of `graph`, which must [validate](G2oGraph::validate).
    ///
    /// # Errors
    ///
    /// A graph that does not validate, or a line without an orthonormal
    /// representation.
    pub fn read(graph: &G2oGraph) -> Result<Self, ProblemError> {
        graph.validate().map_err(ProblemError::Data)?;
        let poses = graph
            .poses
            .iter()
            .map(|Vertex { id, pose }| (*id, Se3RhoTheta::new(pose_graph::se3(pose))))
            .collect();
        let lines = graph
            .lines
            .iter()
            .map(|LineVertex { id, line }| {
                line_landmark(line)
                    .map(|value| (*id, value))
                    .map_err(|e| ProblemError::Data(format!("line vertex {id}: {e}")))
            })
            .collect::<Result<_, _>>()?;
        let planes = graph
            .planes
            .iter()
            .map(|PlaneVertex { id, plane }| (*id, InfinitePlane::from_coefficients(plane)))
            .collect();
        let points = graph
            .points
            .iter()
            .map(|PointVertex { id, point }| (*id, *point))
            .collect();
        Ok(Vertices {
            poses,
            lines,
            planes,
            points,
        })
    }
}

/// One of g2o's error definitions, as this project's factor.
#[derive(Debug, Clone)]
pub enum G2oFactor {
    /// `EDGE_SE3:QUAT` on `[from, to]`.
    Pose(G2oSe3Edge),
    /// `EDGE_SE3_LINE3D` on `[pose, line]`.
    Line(G2oLineEdge),
    /// `EDGE_SE3_PLANE_CALIB` on `[pose, plane, offset]`.
    Plane(G2oPlaneEdge),
    /// `EDGE_SE3_TRACKXYZ` on `[pose, point]`.
    Point(G2oPointEdge),
    /// `EDGE_SE3_PRIOR` on `[pose]`.
    Prior(G2oPriorEdge),
}

/// An edge of a graph: its factor, the ids of its vertices in the factor's
/// variable order, its noise model (the square root of its information),
/// and its position among the edges of its tag.
#[derive(Debug, Clone)]
pub struct G2oEdge {
    /// The factor at the vertices' initial values.
    pub factor: G2oFactor,
    /// Vertex ids, one per variable of the factor.
    pub vertices: Vec<usize>,
    /// `S` with `SᵀS` the edge's information.
    pub noise: Noise,
    /// Its index among the edges of its tag (`G2oGraph::line_edges`, …).
    pub index: usize,
}

impl G2oEdge {
    /// The edge in words, for errors: `line edge 3 (pose 7 → line 2)`.
    pub fn describe(&self) -> String {
        let tag = match self.factor {
            G2oFactor::Pose(_) => Tag::Pose,
            G2oFactor::Line(_) => Tag::Line,
            G2oFactor::Plane(_) => Tag::Plane,
            G2oFactor::Point(_) => Tag::Point,
            G2oFactor::Prior(_) => Tag::Prior,
        };
        describe(tag, self.index, &self.vertices)
    }
}

/// An edge's tag.
#[derive(Clone, Copy)]
enum Tag {
    Pose,
    Line,
    Plane,
    Point,
    Prior,
}

/// Edge `k` of its tag on vertices `v` (in the factor's variable order),
/// in words.
fn describe(tag: Tag, k: usize, v: &[usize]) -> String {
    match tag {
        Tag::Pose => format!("pose edge {k} ({} → {})", v[0], v[1]),
        Tag::Line => format!("line edge {k} (pose {} → line {})", v[0], v[1]),
        Tag::Plane => format!(
            "plane edge {k} (pose {} → plane {}, offset {})",
            v[0], v[1], v[2]
        ),
        Tag::Point => format!("point edge {k} (pose {} → point {})", v[0], v[1]),
        Tag::Prior => format!("prior edge {k} (pose {})", v[0]),
    }
}

/// A vertex's value by id, or the edge's error.
fn find<V: Copy>(
    values: &HashMap<usize, V>,
    id: usize,
    which: &dyn Fn() -> String,
) -> Result<V, ProblemError> {
    values.get(&id).copied().ok_or_else(|| {
        ProblemError::Data(format!(
            "{}: vertex {id} is not of the kind joined",
            which()
        ))
    })
}

/// Every edge of `graph` as its g2o factor at `vertices`, by tag in the
/// file's order within each: pose edges, line edges, plane edges, point
/// edges, priors.
///
/// # Errors
///
/// An edge joining a vertex of the wrong kind, a parameter not defined, or
/// an information matrix that is not positive definite (semi-definite for
/// a prior).
pub fn edges(graph: &G2oGraph, vertices: &Vertices) -> Result<Vec<G2oEdge>, ProblemError> {
    let poses: HashMap<usize, Se3RhoTheta<f64>> = vertices.poses.iter().copied().collect();
    let lines: HashMap<usize, OrthonormalLine<f64>> = vertices.lines.iter().copied().collect();
    let planes: HashMap<usize, InfinitePlane<f64>> = vertices.planes.iter().copied().collect();
    let points: HashMap<usize, Vector3<f64>> = vertices.points.iter().copied().collect();
    // Sensor offsets by parameter id, quaternions as written (g2o's).
    let offsets: HashMap<usize, Se3<f64>> = graph
        .offsets
        .iter()
        .map(|p| (p.id, as_written(&p.offset)))
        .collect();
    let offset = |id: usize, which: &dyn Fn() -> String| {
        offsets.get(&id).copied().ok_or_else(|| {
            ProblemError::Data(format!("{}: parameter {id} is not defined", which()))
        })
    };
    let mut out = Vec::new();
    for (index, e) in graph.pose_edges.iter().enumerate() {
        let which = || describe(Tag::Pose, index, &[e.from, e.to]);
        let factor = G2oSe3Edge {
            measured: as_written(&e.measurement),
            pose_i: find(&poses, e.from, &which)?,
            pose_j: find(&poses, e.to, &which)?,
        };
        out.push(G2oEdge {
            factor: G2oFactor::Pose(factor),
            vertices: vec![e.from, e.to],
            noise: sqrt_information(&e.information, &which)?,
            index,
        });
    }
    for (index, e) in graph.line_edges.iter().enumerate() {
        let which = || describe(Tag::Line, index, &[e.pose, e.line]);
        let factor = G2oLineEdge {
            measured: e.measurement,
            pose: find(&poses, e.pose, &which)?,
            line: find(&lines, e.line, &which)?,
        };
        out.push(G2oEdge {
            factor: G2oFactor::Line(factor),
            vertices: vec![e.pose, e.line],
            noise: sqrt_information(&e.information, &which)?,
            index,
        });
    }
    for (index, e) in graph.plane_edges.iter().enumerate() {
        let which = || describe(Tag::Plane, index, &[e.pose, e.plane, e.offset]);
        let factor = G2oPlaneEdge {
            measured: e.measurement,
            pose: find(&poses, e.pose, &which)?,
            plane: find(&planes, e.plane, &which)?,
            offset: find(&poses, e.offset, &which)?,
        };
        out.push(G2oEdge {
            factor: G2oFactor::Plane(factor),
            vertices: vec![e.pose, e.plane, e.offset],
            noise: sqrt_information(&e.information, &which)?,
            index,
        });
    }
    for (index, e) in graph.point_edges.iter().enumerate() {
        let which = || describe(Tag::Point, index, &[e.pose, e.point]);
        let factor = G2oPointEdge {
            measured: e.measurement,
            offset: offset(e.offset, &which)?,
            pose: find(&poses, e.pose, &which)?,
            point: find(&points, e.point, &which)?,
        };
        out.push(G2oEdge {
            factor: G2oFactor::Point(factor),
            vertices: vec![e.pose, e.point],
            noise: sqrt_information(&e.information, &which)?,
            index,
        });
    }
    for (index, e) in graph.priors.iter().enumerate() {
        let which = || describe(Tag::Prior, index, &[e.pose]);
        let factor = G2oPriorEdge {
            measured: as_written(&e.measurement),
            offset: offset(e.offset, &which)?,
            pose: find(&poses, e.pose, &which)?,
        };
        out.push(G2oEdge {
            factor: G2oFactor::Prior(factor),
            vertices: vec![e.pose],
            noise: sqrt_semidefinite_information(&e.information),
            index,
        });
    }
    Ok(out)
}

/// `graph` with the solution's vertices, where `solved` has them: poses as
/// unit quaternions, lines as `[w, d]` (unit direction), planes as `[n, d]`
/// (unit normal), points as they are. Vertices it does not have are left
/// as they were.
pub fn solution(graph: &G2oGraph, solved: &Vertices) -> G2oGraph {
    let mut out = graph.clone();
    let poses: HashMap<usize, Se3<f64>> = solved.poses.iter().map(|(i, p)| (*i, p.se3())).collect();
    for vertex in &mut out.poses {
        if let Some(pose) = poses.get(&vertex.id) {
            let q = pose.rotation.quaternion;
            vertex.pose = Pose {
                translation: pose.translation,
                rotation: Rotation::Quaternion([q.x, q.y, q.z, q.w]),
            };
        }
    }
    let lines: HashMap<usize, &OrthonormalLine<f64>> =
        solved.lines.iter().map(|(i, l)| (*i, l)).collect();
    for vertex in &mut out.lines {
        if let Some(line) = lines.get(&vertex.id) {
            let (w, d) = (line.moment(), line.direction());
            vertex.line = Vector6::new(w.x, w.y, w.z, d.x, d.y, d.z);
        }
    }
    let planes: HashMap<usize, &InfinitePlane<f64>> =
        solved.planes.iter().map(|(i, p)| (*i, p)).collect();
    for vertex in &mut out.planes {
        if let Some(plane) = planes.get(&vertex.id) {
            let (n, d) = plane.normal_offset();
            vertex.plane = Vector4::new(n.x, n.y, n.z, d);
        }
    }
    let points: HashMap<usize, &Vector3<f64>> =
        solved.points.iter().map(|(i, p)| (*i, p)).collect();
    for vertex in &mut out.points {
        if let Some(point) = points.get(&vertex.id) {
            vertex.point = **point;
        }
    }
    out
}

/// The documents' factor of a line or plane edge, in place of g2o's own
/// ([`LandmarkFactors::Documents`]): its pose is the
/// world-to-camera `T = X⁻¹` of the edge's body-to-world vertex `X`.
#[derive(Debug, Clone)]
pub enum DocumentsFactor {
    /// The orthonormal-line observation of an `EDGE_SE3_LINE3D`.
    Line(LineObservation),
    /// The plane factor of an `EDGE_SE3_PLANE_CALIB`, the measurement
    /// moved into the body frame through the (fixed) sensor offset.
    Plane(PlaneFactor),
}

/// The documents' factor of the line or plane `edge` of `graph` at its
/// initial values, and its noise model: the edge's information moved into
/// the factor's residual space
/// ([`slam_factors::g2o::line_observation`],
/// [`slam_factors::g2o::plane_observation`]).
///
/// # Errors
///
/// A measurement without an orthonormal representation, a plane edge whose
/// sensor offset is free (the documents' plane factor has one pose), a
/// factor degenerate at the initial values, an information matrix that is
/// not positive definite; `None` for an edge that is neither a line nor a
/// plane.
pub fn documents_factor(
    graph: &G2oGraph,
    edge: &G2oEdge,
) -> Option<Result<(DocumentsFactor, Noise), ProblemError>> {
    let which = || edge.describe();
    let degenerate = |error| ProblemError::at_initial_values(which(), error);
    Some(match &edge.factor {
        G2oFactor::Line(f) => {
            let e = &graph.line_edges[edge.index];
            line_observation(&f.pose.se3(), &f.line, &e.measurement, &e.information)
                .map_err(|err| ProblemError::Data(format!("{}: {err}", which())))
                .and_then(|(factor, information)| {
                    factor.validate().map_err(degenerate)?;
                    let noise = sqrt_information(&information, &which)?;
                    Ok((DocumentsFactor::Line(factor), noise))
                })
        }
        G2oFactor::Plane(f) => {
            let e = &graph.plane_edges[edge.index];
            if !graph.fixed.contains(&e.offset) {
                return Some(Err(ProblemError::Unavailable(format!(
                    "{}: the sensor offset is free (calibrated), which the documents' plane \
                     factor (one pose) cannot estimate; solve it with g2o's factors",
                    which()
                ))));
            }
            plane_observation(
                &f.pose.se3(),
                &f.plane,
                &f.offset.se3(),
                &e.measurement,
                &e.information,
            )
            .map_err(degenerate)
            .and_then(|(factor, information)| {
                let noise = sqrt_information(&information, &which)?;
                Ok((DocumentsFactor::Plane(factor), noise))
            })
        }
        _ => return None,
    })
}
