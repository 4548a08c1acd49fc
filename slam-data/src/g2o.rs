//! g2o 3D pose graphs (`VERTEX_SE3:QUAT`, `EDGE_SE3:QUAT`).
//!
//! One record per line; blank lines and lines starting with `#` are skipped:
//!
//! ```text
//! VERTEX_SE3:QUAT id x y z qx qy qz qw
//! EDGE_SE3:QUAT i j x y z qx qy qz qw I₁₁ I₁₂ … I₁₆ I₂₂ … I₆₆
//! ```
//!
//! A vertex is the world-from-body pose of `id`; an edge measures the pose
//! of `j` in the frame of `i`, `T_i⁻¹ T_j`. The quaternion is Hamilton,
//! `[x, y, z, w]`, accepted within [`crate::QUATERNION_TOLERANCE`] of unit
//! norm and renormalised when used. The 21 numbers are the upper triangle,
//! row by row, of the symmetric 6×6 information matrix in g2o's error order
//! `[δt (3), δq (3)]`: translation first, then the vector part of the
//! error quaternion. It is returned in `[δω, δρ]` order, its 3×3 blocks
//! swapped exactly as GTSAM's `readG2o` does (and swapped back on writing).
//! Like GTSAM, nothing is rescaled, although `δq ≈ δω / 2`: the
//! rotation-vector information equivalent to g2o's has its rotation block
//! divided by 4 and its off-diagonal blocks by 2.
//!
//! Any other tag is an error (GTSAM skips unknown tags silently).
//!
//! # Lines, planes, points and priors
//!
//! [`read_graph`] reads the records of g2o's 3D line and plane types
//! (`types_slam3d_addons`, what g2o's `simulator_3d_line` and
//! `simulator_3d_plane` write) and its 3D points and pose priors
//! (`types_slam3d`) beside the poses, into a [`G2oGraph`]:
//!
//! ```text
//! PARAMS_SE3OFFSET id x y z qx qy qz qw
//! VERTEX_SE3:QUAT id x y z qx qy qz qw
//! VERTEX_LINE3D id wx wy wz dx dy dz
//! VERTEX_PLANE id nx ny nz d
//! VERTEX_TRACKXYZ id x y z
//! EDGE_SE3:QUAT i j x y z qx qy qz qw I₁₁ … I₆₆
//! EDGE_SE3_LINE3D pose line parameter wx wy wz dx dy dz I₁₁ … I₄₄
//! EDGE_SE3_PLANE_CALIB 3 pose plane offset nx ny nz d I₁₁ … I₃₃
//! EDGE_SE3_TRACKXYZ pose point parameter x y z I₁₁ … I₃₃
//! EDGE_SE3_PRIOR pose parameter x y z qx qy qz qw I₁₁ … I₆₆
//! FIX id…
//! ```
//!
//! A line is in Plücker coordinates `[w, d]` (moment `w = p × d`,
//! direction `d`), a plane is `n · x + d = 0`; the measurement of
//! `EDGE_SE3_LINE3D` is the line in the frame of the robot pose (the
//! parameter, a sensor offset, is named but g2o does not use it), that of
//! `EDGE_SE3_PLANE_CALIB` the plane in the frame of the sensor mounted at
//! the pose `offset` (sensor to robot) on the robot. The parameter of
//! `EDGE_SE3_TRACKXYZ` and `EDGE_SE3_PRIOR` is the sensor offset `P`
//! (sensor to robot, a `PARAMS_SE3OFFSET`): the point edge measures the
//! point in the sensor frame, `(X P)⁻¹ p`, the prior the world-from-sensor
//! pose `X P`. (g2o registers only these `TRACKXYZ` names for its
//! `VertexPointXYZ` and `EdgeSE3PointXYZ`; `VERTEX_POINTXYZ` is not a g2o
//! tag.) The information matrices of line, plane and point edges are upper
//! triangles in the order of g2o's errors (orthonormal line: quaternion
//! vector part of `U`, angle of `W`; plane: azimuth, elevation, distance;
//! point: x, y, z) and kept in it; those of `EDGE_SE3:QUAT` and
//! `EDGE_SE3_PRIOR` are reordered to `[δω, δρ]` as above. A prior's may be
//! positive semi-definite (g2o's planar-motion simulator constrains only
//! the height). `FIX` lists vertices held fixed (g2o's gauge); there may be
//! several `FIX` lines. Vertex ids are one space over all kinds; see
//! [`G2oGraph::validate`] for what is checked. Values are kept as written,
//! so read → write → read is exact.

use std::io::{BufRead, Write};
use std::path::Path;

use crate::error::Error;
use crate::g2o_graph::G2oGraph;
use crate::g2o_graph_file;
use crate::graph_file::{self, G2O};
use crate::input;
use crate::output::write_file;
use crate::pose_graph::PoseGraph;

/// Reads the g2o file at `path`.
pub fn read(path: impl AsRef<Path>) -> Result<PoseGraph, Error> {
    let (reader, name) = input::open(path.as_ref())?;
    read_from(reader, &name)
}

/// Reads g2o text; `name` is the file name used in errors.
pub fn from_text(text: &str, name: &str) -> Result<PoseGraph, Error> {
    read_from(text.as_bytes(), name)
}

/// Reads g2o text from `reader`; `name` is the file name used in errors.
pub fn read_from(reader: impl BufRead, name: &str) -> Result<PoseGraph, Error> {
    graph_file::read(reader, name, &G2O)
}

/// Writes `graph` as a g2o file at `path`: vertices, then edges.
pub fn write(graph: &PoseGraph, path: impl AsRef<Path>) -> Result<(), Error> {
    write_file(path.as_ref(), |out, name| write_to(graph, out, name))
}

/// Writes `graph` as g2o text to `out`; `name` is used in errors. Fails
/// without writing if the graph does not [validate](PoseGraph::validate).
/// Roll-pitch-yaw rotations are written as quaternions.
pub fn write_to(graph: &PoseGraph, out: &mut impl Write, name: &str) -> Result<(), Error> {
    graph_file::write(graph, out, name, &G2O)
}

/// Reads the g2o line and plane graph at `path`.
pub fn read_graph(path: impl AsRef<Path>) -> Result<G2oGraph, Error> {
    let (reader, name) = input::open(path.as_ref())?;
    read_graph_from(reader, &name)
}

/// Reads a g2o line and plane graph from text; `name` is the file name
/// used in errors.
pub fn graph_from_text(text: &str, name: &str) -> Result<G2oGraph, Error> {
    read_graph_from(text.as_bytes(), name)
}

/// Reads a g2o line and plane graph from `reader`; `name` is the file name
/// used in errors.
pub fn read_graph_from(reader: impl BufRead, name: &str) -> Result<G2oGraph, Error> {
    g2o_graph_file::read(reader, name)
}

/// Writes `graph` as a g2o file at `path`: parameters, vertices (poses,
/// lines, planes, points), edges (pose, line, plane, point, prior), then
/// one `FIX` line.
pub fn write_graph(graph: &G2oGraph, path: impl AsRef<Path>) -> Result<(), Error> {
    write_file(path.as_ref(), |out, name| write_graph_to(graph, out, name))
}

/// Writes `graph` as g2o text to `out`; `name` is used in errors. Fails
/// without writing if the graph does not [validate](G2oGraph::validate).
pub fn write_graph_to(graph: &G2oGraph, out: &mut impl Write, name: &str) -> Result<(), Error> {
    g2o_graph_file::write(graph, out, name)
}
