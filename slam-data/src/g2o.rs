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

use std::io::{BufRead, Write};
use std::path::Path;

use crate::error::Error;
use crate::graph_file::{self, Dialect};
use crate::input;
use crate::output::write_file;
use crate::pose_graph::PoseGraph;

const DIALECT: Dialect = Dialect {
    name: "g2o",
    vertex_tag: "VERTEX_SE3:QUAT",
    edge_tag: "EDGE_SE3:QUAT",
    quaternions: true,
    translation_first: true,
    other: ("edge3", ["VERTEX3", "EDGE3"]),
};

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
    graph_file::read(reader, name, &DIALECT)
}

/// Writes `graph` as a g2o file at `path`: vertices, then edges.
pub fn write(graph: &PoseGraph, path: impl AsRef<Path>) -> Result<(), Error> {
    write_file(path.as_ref(), |out, name| write_to(graph, out, name))
}

/// Writes `graph` as g2o text to `out`; `name` is used in errors. Fails
/// without writing if the graph does not [validate](PoseGraph::validate).
/// Roll-pitch-yaw rotations are written as quaternions.
pub fn write_to(graph: &PoseGraph, out: &mut impl Write, name: &str) -> Result<(), Error> {
    graph_file::write(graph, out, name, &DIALECT)
}
