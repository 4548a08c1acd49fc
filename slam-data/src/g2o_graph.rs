//! g2o graphs with 3D lines and planes (g2o's `types_slam3d_addons`), 3D
//! points and pose priors (its `types_slam3d`) beside the poses of a pose
//! graph: what [`crate::g2o::read_graph`] reads.
//!
//! Values are kept exactly as written; what g2o does with them on loading
//! (it normalises planes to a unit normal, and builds rotation matrices from
//! the pose quaternions without normalising them) is the business of the
//! factors that reproduce its errors (`slam_factors::g2o`).

use std::collections::hash_map::Entry;
use std::collections::{HashMap, HashSet};

use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3, Vector4, Vector6};

use crate::checks::{check_information, check_semidefinite_information};
use crate::input::{MAX_MAGNITUDE, all_in_range, in_range};
use crate::pose_graph::{Edge, Pose, PoseGraph, Vertex};

/// `PARAMS_SE3OFFSET id x y z qx qy qz qw`: a sensor offset parameter, the
/// pose of a sensor in the robot frame. g2o's line edge names one but does
/// not use it; its prior and point edges do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Se3Offset {
    /// The parameter id edges refer to.
    pub id: usize,
    /// Sensor-to-robot pose.
    pub offset: Pose,
}

/// `VERTEX_LINE3D id wx wy wz dx dy dz`: an infinite 3D line in Plücker
/// coordinates `[w, d]` (g2o's `Line3D`): the moment `w = p × d` of any
/// point `p` of the line, and the direction `d` (g2o writes it unit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineVertex {
    /// The vertex id.
    pub id: usize,
    /// `[w, d]` as written.
    pub line: Vector6<f64>,
}

/// `VERTEX_PLANE id nx ny nz d`: the plane `n · x + d = 0` (g2o's
/// `Plane3D`, which normalises it to `|n| = 1` on loading; see
/// [`unit_normal_plane`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneVertex {
    /// The vertex id.
    pub id: usize,
    /// `[n, d]` as written.
    pub plane: Vector4<f64>,
}

/// `EDGE_SE3_LINE3D pose line parameter wx wy wz dx dy dz I₁₁ … I₄₄`: the
/// line `line` measured in the frame of the robot pose `pose`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineEdge {
    /// Id of the robot pose (`VERTEX_SE3:QUAT`).
    pub pose: usize,
    /// Id of the line (`VERTEX_LINE3D`).
    pub line: usize,
    /// Id of the sensor-offset parameter (`PARAMS_SE3OFFSET`), which g2o
    /// resolves but does not use.
    pub offset: usize,
    /// The measured line `[w, d]` in the robot frame, as written.
    pub measurement: Vector6<f64>,
    /// Information matrix in the order of g2o's error: the vector part of
    /// the quaternion of `U`, then the angle of `W` (orthonormal
    /// representation).
    pub information: Matrix4<f64>,
}

/// `EDGE_SE3_PLANE_CALIB 3 pose plane offset nx ny nz d I₁₁ … I₃₃`: the plane
/// `plane` measured by a sensor mounted at the pose `offset` (a
/// `VERTEX_SE3:QUAT`, sensor to robot) on the robot at pose `pose`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneEdge {
    /// Id of the robot pose.
    pub pose: usize,
    /// Id of the plane (`VERTEX_PLANE`).
    pub plane: usize,
    /// Id of the sensor-offset pose (a `VERTEX_SE3:QUAT`, possibly free:
    /// its calibration).
    pub offset: usize,
    /// The measured plane `[n, d]` in the sensor frame, as written.
    pub measurement: Vector4<f64>,
    /// Information matrix in the order of g2o's error: azimuth, elevation,
    /// distance.
    pub information: Matrix3<f64>,
}

/// `VERTEX_TRACKXYZ id x y z`: a 3D point of the world (g2o's
/// `VertexPointXYZ`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointVertex {
    /// The vertex id.
    pub id: usize,
    /// The point, world frame.
    pub point: Vector3<f64>,
}

/// `EDGE_SE3_TRACKXYZ pose point offset x y z I₁₁ … I₃₃`: the point `point`
/// measured in the frame of the sensor mounted at the parameter `offset` on
/// the robot at pose `pose` (g2o's `EdgeSE3PointXYZ`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointEdge {
    /// Id of the robot pose (`VERTEX_SE3:QUAT`).
    pub pose: usize,
    /// Id of the point (`VERTEX_TRACKXYZ`).
    pub point: usize,
    /// Id of the sensor-offset parameter (`PARAMS_SE3OFFSET`).
    pub offset: usize,
    /// The measured point in the sensor frame.
    pub measurement: Vector3<f64>,
    /// Information matrix of the error `[x, y, z]`.
    pub information: Matrix3<f64>,
}

/// `EDGE_SE3_PRIOR pose offset x y z qx qy qz qw I₁₁ … I₆₆`: a prior on the
/// pose of the sensor mounted at the parameter `offset` on the robot at
/// pose `pose`, `X · P ≈ measurement` (g2o's `EdgeSE3Prior`).
///
/// Its information may be positive **semi**-definite: g2o's
/// `simulator_3d_plane --planar_motion=true` writes `diag(0, 0, 1e9, 0, 0,
/// 0)` to hold the robot on the plane `z = 0` and nothing else.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PriorEdge {
    /// Id of the robot pose (`VERTEX_SE3:QUAT`).
    pub pose: usize,
    /// Id of the sensor-offset parameter (`PARAMS_SE3OFFSET`).
    pub offset: usize,
    /// The measured world-from-sensor pose, quaternion as written.
    pub measurement: Pose,
    /// Information matrix in tangent order `[δω, δρ]`, as that of a pose
    /// edge: g2o's `[δt, δq]` upper triangle with its 3×3 blocks swapped.
    pub information: Matrix6<f64>,
}

/// A g2o graph of poses, 3D lines, planes and points (the records of g2o's
/// `types_slam3d` and `types_slam3d_addons` its simulators write), each
/// list in file order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct G2oGraph {
    /// `PARAMS_SE3OFFSET` parameters.
    pub offsets: Vec<Se3Offset>,
    /// `VERTEX_SE3:QUAT`: world-from-body poses (robot poses and sensor
    /// offsets).
    pub poses: Vec<Vertex>,
    /// `VERTEX_LINE3D`.
    pub lines: Vec<LineVertex>,
    /// `VERTEX_PLANE`.
    pub planes: Vec<PlaneVertex>,
    /// `VERTEX_TRACKXYZ`.
    pub points: Vec<PointVertex>,
    /// `EDGE_SE3:QUAT`, information in `[δω, δρ]` order as in
    /// [`PoseGraph`].
    pub pose_edges: Vec<Edge>,
    /// `EDGE_SE3_LINE3D`.
    pub line_edges: Vec<LineEdge>,
    /// `EDGE_SE3_PLANE_CALIB`.
    pub plane_edges: Vec<PlaneEdge>,
    /// `EDGE_SE3_TRACKXYZ`.
    pub point_edges: Vec<PointEdge>,
    /// `EDGE_SE3_PRIOR`.
    pub priors: Vec<PriorEdge>,
    /// Ids of the vertices of the `FIX` lines, in file order.
    pub fixed: Vec<usize>,
}

/// The kind of vertex an id names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VertexKind {
    /// `VERTEX_SE3:QUAT`.
    Pose,
    /// `VERTEX_LINE3D`.
    Line,
    /// `VERTEX_PLANE`.
    Plane,
    /// `VERTEX_TRACKXYZ`.
    Point,
}

impl VertexKind {
    /// The record tag.
    pub fn tag(self) -> &'static str {
        match self {
            VertexKind::Pose => "VERTEX_SE3:QUAT",
            VertexKind::Line => "VERTEX_LINE3D",
            VertexKind::Plane => "VERTEX_PLANE",
            VertexKind::Point => "VERTEX_TRACKXYZ",
        }
    }
}

/// The element of a [`G2oGraph`] a defect is in (its index in its list).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Item {
    Offset(usize),
    Pose(usize),
    Line(usize),
    Plane(usize),
    Point(usize),
    PoseEdge(usize),
    LineEdge(usize),
    PlaneEdge(usize),
    PointEdge(usize),
    Prior(usize),
    Fixed(usize),
}

/// `[n, d]` scaled to a unit normal, as g2o's `Plane3D` stores a plane
/// (`coeffs · (1 / |n|)`); `None` for a zero normal.
pub fn unit_normal_plane(plane: &Vector4<f64>) -> Option<Vector4<f64>> {
    let n = plane.xyz().norm();
    (n > 0.0 && n.is_finite()).then(|| plane * (1.0 / n))
}

impl G2oGraph {
    /// The poses and their edges as a [`PoseGraph`].
    pub fn pose_graph(&self) -> PoseGraph {
        PoseGraph {
            vertices: self.poses.clone(),
            edges: self.pose_edges.clone(),
        }
    }

    /// The kind of every vertex, by id (the ids of a valid graph are
    /// distinct).
    pub fn vertex_kinds(&self) -> HashMap<usize, VertexKind> {
        let poses = self.poses.iter().map(|v| (v.id, VertexKind::Pose));
        let lines = self.lines.iter().map(|v| (v.id, VertexKind::Line));
        let planes = self.planes.iter().map(|v| (v.id, VertexKind::Plane));
        let points = self.points.iter().map(|v| (v.id, VertexKind::Point));
        poses.chain(lines).chain(planes).chain(points).collect()
    }

    /// Fails, saying what is wrong, unless the graph is one the reader
    /// accepts: numbers finite and at most [`crate::MAX_MAGNITUDE`],
    /// quaternions unit within [`crate::QUATERNION_TOLERANCE`], line
    /// directions and plane normals non-zero, information matrices
    /// symmetric positive definite (a prior's positive semi-definite and
    /// not zero), vertex ids distinct over all kinds and parameter ids
    /// distinct, every edge between vertices of the kinds it joins (and a
    /// pose edge or a plane edge's robot pose and sensor offset between two
    /// different poses), every parameter an edge names defined, every fixed
    /// id a vertex, fixed once.
    pub fn validate(&self) -> Result<(), String> {
        match self.find_defect() {
            None => Ok(()),
            Some((item, what)) => {
                let (name, k) = match item {
                    Item::Offset(k) => ("parameter", k),
                    Item::Pose(k) => ("pose vertex", k),
                    Item::Line(k) => ("line vertex", k),
                    Item::Plane(k) => ("plane vertex", k),
                    Item::Point(k) => ("point vertex", k),
                    Item::PoseEdge(k) => ("pose edge", k),
                    Item::LineEdge(k) => ("line edge", k),
                    Item::PlaneEdge(k) => ("plane edge", k),
                    Item::PointEdge(k) => ("point edge", k),
                    Item::Prior(k) => ("prior edge", k),
                    Item::Fixed(k) => ("fixed id", k),
                };
                Err(format!("{name} {k}: {what}"))
            }
        }
    }

    /// The first defect [`G2oGraph::validate`] looks for, and where it is.
    pub(crate) fn find_defect(&self) -> Option<(Item, String)> {
        let mut offsets = HashSet::with_capacity(self.offsets.len());
        for (k, p) in self.offsets.iter().enumerate() {
            let defect = p.offset.check().and_then(|()| {
                if offsets.insert(p.id) {
                    Ok(())
                } else {
                    Err(format!("parameter id {} defined again", p.id))
                }
            });
            if let Err(what) = defect {
                return Some((Item::Offset(k), what));
            }
        }
        let mut kinds: HashMap<usize, VertexKind> = HashMap::new();
        let mut define = |id: usize, kind: VertexKind| match kinds.entry(id) {
            Entry::Occupied(first) => Err(format!(
                "vertex id {id} defined again (first as a {})",
                first.get().tag()
            )),
            Entry::Vacant(slot) => {
                slot.insert(kind);
                Ok(())
            }
        };
        for (k, v) in self.poses.iter().enumerate() {
            if let Err(what) = v.pose.check().and_then(|()| define(v.id, VertexKind::Pose)) {
                return Some((Item::Pose(k), what));
            }
        }
        for (k, v) in self.lines.iter().enumerate() {
            if let Err(what) = check_line(&v.line).and_then(|()| define(v.id, VertexKind::Line)) {
                return Some((Item::Line(k), what));
            }
        }
        for (k, v) in self.planes.iter().enumerate() {
            if let Err(what) = check_plane(&v.plane).and_then(|()| define(v.id, VertexKind::Plane))
            {
                return Some((Item::Plane(k), what));
            }
        }
        for (k, v) in self.points.iter().enumerate() {
            let defect = if all_in_range(v.point.iter()) {
                define(v.id, VertexKind::Point)
            } else {
                Err("non-finite or too large point coordinate".into())
            };
            if let Err(what) = defect {
                return Some((Item::Point(k), what));
            }
        }
        let expect = |id: usize, kind: VertexKind| match kinds.get(&id) {
            None => Err(format!("vertex {id} is not defined")),
            Some(found) if *found != kind => Err(format!(
                "vertex {id} is a {}, not a {}",
                found.tag(),
                kind.tag()
            )),
            Some(_) => Ok(()),
        };
        let parameter = |id: usize| {
            if offsets.contains(&id) {
                Ok(())
            } else {
                Err(format!("parameter {id} is not defined"))
            }
        };
        for (k, e) in self.pose_edges.iter().enumerate() {
            let defect = e
                .check()
                .and_then(|()| expect(e.from, VertexKind::Pose))
                .and_then(|()| expect(e.to, VertexKind::Pose));
            if let Err(what) = defect {
                return Some((Item::PoseEdge(k), what));
            }
        }
        for (k, e) in self.line_edges.iter().enumerate() {
            let defect = check_line(&e.measurement)
                .map_err(|what| format!("measurement: {what}"))
                .and_then(|()| check_information(&e.information))
                .and_then(|()| expect(e.pose, VertexKind::Pose))
                .and_then(|()| expect(e.line, VertexKind::Line))
                .and_then(|()| parameter(e.offset));
            if let Err(what) = defect {
                return Some((Item::LineEdge(k), what));
            }
        }
        for (k, e) in self.plane_edges.iter().enumerate() {
            let defect = check_plane(&e.measurement)
                .map_err(|what| format!("measurement: {what}"))
                .and_then(|()| check_information(&e.information))
                .and_then(|()| expect(e.pose, VertexKind::Pose))
                .and_then(|()| expect(e.plane, VertexKind::Plane))
                .and_then(|()| expect(e.offset, VertexKind::Pose))
                .and_then(|()| {
                    if e.pose == e.offset {
                        Err(format!(
                            "the robot pose and the sensor offset are the same vertex {}",
                            e.pose
                        ))
                    } else {
                        Ok(())
                    }
                });
            if let Err(what) = defect {
                return Some((Item::PlaneEdge(k), what));
            }
        }
        for (k, e) in self.point_edges.iter().enumerate() {
            let defect = if all_in_range(e.measurement.iter()) {
                Ok(())
            } else {
                Err("measurement: non-finite or too large point coordinate".into())
            };
            let defect = defect
                .and_then(|()| check_information(&e.information))
                .and_then(|()| expect(e.pose, VertexKind::Pose))
                .and_then(|()| expect(e.point, VertexKind::Point))
                .and_then(|()| parameter(e.offset));
            if let Err(what) = defect {
                return Some((Item::PointEdge(k), what));
            }
        }
        for (k, e) in self.priors.iter().enumerate() {
            let defect = e
                .measurement
                .check()
                .map_err(|what| format!("measurement: {what}"))
                .and_then(|()| check_semidefinite_information(&e.information))
                .and_then(|()| expect(e.pose, VertexKind::Pose))
                .and_then(|()| parameter(e.offset));
            if let Err(what) = defect {
                return Some((Item::Prior(k), what));
            }
        }
        let mut fixed = HashSet::with_capacity(self.fixed.len());
        for (k, id) in self.fixed.iter().enumerate() {
            let defect = if !kinds.contains_key(id) {
                Err(format!("fixed vertex {id} is not defined"))
            } else if !fixed.insert(*id) {
                Err(format!("vertex {id} is fixed twice"))
            } else {
                Ok(())
            };
            if let Err(what) = defect {
                return Some((Item::Fixed(k), what));
            }
        }
        None
    }
}

/// The largest `|w · d| / (|w| |d|)` a line may have: g2o writes six
/// significant digits, which moves the cosine of a Plücker line's `w` and
/// `d` (0 exactly) by up to about 2e-5.
const PLUCKER_COSINE: f64 = 1e-4;

/// Fails unless the Plücker coordinates `[w, d]` are in range with a
/// non-zero direction and a moment perpendicular to it (`w · d = 0`, the
/// Klein quadric, to the digits g2o writes: [`PLUCKER_COSINE`]).
fn check_line(line: &Vector6<f64>) -> Result<(), String> {
    if !all_in_range(line.iter()) {
        return Err("non-finite or too large line coordinate".into());
    }
    let (w, d) = (line.fixed_rows::<3>(0), line.fixed_rows::<3>(3));
    if d == Vector3::zeros() {
        return Err("the line direction d is zero".into());
    }
    // Each vector divided by its largest entry first, so that no square
    // underflows (a direction of 1e-200).
    let (w_max, d_max) = (w.amax(), d.amax());
    let (w_scaled, d_scaled) = (w / w_max.max(f64::MIN_POSITIVE), d / d_max);
    let distance = w_max * w_scaled.norm() / (d_max * d_scaled.norm());
    if !in_range(distance) {
        return Err(format!(
            "the line is {distance:.1e} from the origin (|w| / |d|), beyond the range of \
             coordinates (at most {MAX_MAGNITUDE:e})"
        ));
    }
    if w_max > 0.0 {
        let cosine = w_scaled.normalize().dot(&d_scaled.normalize());
        if cosine.abs() > PLUCKER_COSINE {
            return Err(format!(
                "not a Plücker line: the moment w and the direction d must be perpendicular \
                 (w · d = 0), their cosine is {cosine:.6}"
            ));
        }
    }
    Ok(())
}

/// Fails unless the plane `[n, d]` is in range with a non-zero normal.
fn check_plane(plane: &Vector4<f64>) -> Result<(), String> {
    if !all_in_range(plane.iter()) {
        return Err("non-finite or too large plane coefficient".into());
    }
    if plane.xyz() == Vector3::zeros() {
        return Err("the plane normal n is zero".into());
    }
    Ok(())
}
