//! `EDGE3` 3D pose graphs (the format of iSAM's and GTSAM's `sphere2500`).
//!
//! One record per line; blank lines and lines starting with `#` are skipped:
//!
//! ```text
//! VERTEX3 id x y z roll pitch yaw
//! EDGE3 i j x y z roll pitch yaw I₁₁ I₁₂ … I₁₆ I₂₂ … I₆₆
//! ```
//!
//! The rotation is `R = Rz(yaw) Ry(pitch) Rx(roll)` (angles in radians), as
//! GTSAM's `load3D` builds it with `Rot3::Ypr(yaw, pitch, roll)`. A vertex
//! is the world-from-body pose of `id`; an edge measures the pose of `j` in
//! the frame of `i`, `T_i⁻¹ T_j`. The 21 numbers are the upper triangle, row
//! by row, of a symmetric 6×6 information matrix, taken as GTSAM takes it:
//! unchanged, in GTSAM's tangent order `[δω, δρ]`. (iSAM, where the format
//! comes from, read them as the upper-triangular *square-root* information
//! in `[x y z roll pitch yaw]` order; for `sphere2500`'s
//! `diag(10, 10, 10, 100, 100, 25)` that is a different noise model, σ =
//! 0.1 in translation and 0.01/0.01/0.04 rad, against GTSAM's σ = 0.316 rad
//! in rotation and 0.1/0.1/0.2 in translation.)
//!
//! Files without vertices are initialised with
//! [`PoseGraph::odometry_initial_values`]. Any other tag is an error.

use std::io::{BufRead, Write};
use std::path::Path;

use crate::error::Error;
use crate::graph_file::{self, Dialect};
use crate::input;
use crate::output::write_file;
use crate::pose_graph::PoseGraph;

const DIALECT: Dialect = Dialect {
    name: "edge3",
    vertex_tag: "VERTEX3",
    edge_tag: "EDGE3",
    quaternions: false,
    translation_first: false,
    other: ("g2o", ["VERTEX_SE3:QUAT", "EDGE_SE3:QUAT"]),
};

/// Reads the EDGE3 file at `path`.
pub fn read(path: impl AsRef<Path>) -> Result<PoseGraph, Error> {
    let (reader, name) = input::open(path.as_ref())?;
    read_from(reader, &name)
}

/// Reads EDGE3 text; `name` is the file name used in errors.
pub fn from_text(text: &str, name: &str) -> Result<PoseGraph, Error> {
    read_from(text.as_bytes(), name)
}

/// Reads EDGE3 text from `reader`; `name` is the file name used in errors.
pub fn read_from(reader: impl BufRead, name: &str) -> Result<PoseGraph, Error> {
    graph_file::read(reader, name, &DIALECT)
}

/// Writes `graph` as an EDGE3 file at `path`: vertices, then edges.
pub fn write(graph: &PoseGraph, path: impl AsRef<Path>) -> Result<(), Error> {
    write_file(path.as_ref(), |out, name| write_to(graph, out, name))
}

/// Writes `graph` as EDGE3 text to `out`; `name` is used in errors. Fails
/// without writing if the graph does not [validate](PoseGraph::validate).
/// Quaternion rotations are written as roll, pitch, yaw.
pub fn write_to(graph: &PoseGraph, out: &mut impl Write, name: &str) -> Result<(), Error> {
    graph_file::write(graph, out, name, &DIALECT)
}
