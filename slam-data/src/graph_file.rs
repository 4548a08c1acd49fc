//! Reading and writing pose-graph text, one record per line, in a dialect:
//! g2o's `VERTEX_SE3:QUAT`/`EDGE_SE3:QUAT` or the `VERTEX3`/`EDGE3` format.

use std::io::{BufRead, Write};

use nalgebra::{Matrix6, SMatrix};

use crate::error::{Error, quoted};
use crate::input::{Cursor, Fields, Lines};
use crate::output::{Real, io_error};
use crate::pose_graph::{Edge, Item, Pose, PoseGraph, Rotation, Vertex};

/// How a pose-graph format writes its records.
pub(crate) struct Dialect {
    /// The format's name in messages.
    pub(crate) name: &'static str,
    pub(crate) vertex_tag: &'static str,
    pub(crate) edge_tag: &'static str,
    /// Whether rotations are quaternions `qx qy qz qw` (else `roll pitch yaw`).
    pub(crate) quaternions: bool,
    /// Whether the file's information matrices are in tangent order
    /// `[δρ, δω]` (translation first), so that their blocks are swapped on
    /// reading and writing.
    pub(crate) translation_first: bool,
    /// The other dialect's name and tags, to point at it.
    pub(crate) other: (&'static str, [&'static str; 2]),
}

/// g2o's `VERTEX_SE3:QUAT`/`EDGE_SE3:QUAT` (also the pose records of its
/// line and plane graphs).
pub(crate) const G2O: Dialect = Dialect {
    name: "g2o",
    vertex_tag: "VERTEX_SE3:QUAT",
    edge_tag: "EDGE_SE3:QUAT",
    quaternions: true,
    translation_first: true,
    other: ("edge3", ["VERTEX3", "EDGE3"]),
};

pub(crate) fn read(
    reader: impl BufRead,
    name: &str,
    dialect: &Dialect,
) -> Result<PoseGraph, Error> {
    let mut lines = Lines::new(reader, name);
    let mut graph = PoseGraph::default();
    let (mut vertex_lines, mut edge_lines) = (Vec::new(), Vec::new());
    while let Some(line) = lines.next_record()? {
        let mut fields = line.fields();
        let tag = fields.token("a tag")?;
        if tag == dialect.vertex_tag {
            let id = fields.integer("the vertex id")?;
            let pose = read_pose(&mut fields, dialect)?;
            fields.finish()?;
            graph.vertices.push(Vertex { id, pose });
            vertex_lines.push(line.number);
        } else if tag == dialect.edge_tag {
            let from = fields.integer("the first pose id")?;
            let to = fields.integer("the second pose id")?;
            let measurement = read_pose(&mut fields, dialect)?;
            let mut information: Matrix6<f64> = read_upper_triangle(&mut fields)?;
            fields.finish()?;
            if dialect.translation_first {
                information = swap_rotation_translation(&information);
            }
            graph.edges.push(Edge {
                from,
                to,
                measurement,
                information,
            });
            edge_lines.push(line.number);
        } else if dialect.other.1.contains(&tag) {
            let other = dialect.other.0;
            return Err(line.error(format!(
                "{tag} is a line of the {other} format, not {}: read the file as {other}",
                dialect.name
            )));
        } else {
            return Err(line.error(format!(
                "unsupported tag {} (a {} file has {} and {} lines)",
                quoted(tag),
                dialect.name,
                dialect.vertex_tag,
                dialect.edge_tag
            )));
        }
    }
    match graph.find_defect() {
        None => Ok(graph),
        Some((item, what)) => {
            let line = match item {
                Item::Vertex(k) => vertex_lines[k],
                Item::Edge(k) => edge_lines[k],
            };
            Err(Error::at_line(lines.file(), line, what))
        }
    }
}

/// A symmetric `N × N` matrix from its upper triangle, row by row.
pub(crate) fn read_upper_triangle<const N: usize>(
    fields: &mut Fields<'_>,
) -> Result<SMatrix<f64, N, N>, Error> {
    let what = format!("an information entry ({} expected)", N * (N + 1) / 2);
    let mut m = SMatrix::zeros();
    for i in 0..N {
        for j in i..N {
            let value = fields.real(&what)?;
            m[(i, j)] = value;
            m[(j, i)] = value;
        }
    }
    Ok(m)
}

/// Writes the upper triangle of `m`, row by row, each entry after a space.
pub(crate) fn write_upper_triangle<const N: usize>(
    out: &mut impl Write,
    m: &SMatrix<f64, N, N>,
) -> std::io::Result<()> {
    for i in 0..N {
        for j in i..N {
            write!(out, " {}", Real(m[(i, j)]))?;
        }
    }
    Ok(())
}

/// A pose `x y z` then the dialect's rotation.
pub(crate) fn read_pose(fields: &mut Fields<'_>, dialect: &Dialect) -> Result<Pose, Error> {
    let translation = fields.vector3("a translation component")?;
    let rotation = if dialect.quaternions {
        let mut q = [0.0; 4];
        for c in &mut q {
            *c = fields.real("a quaternion coefficient (qx qy qz qw)")?;
        }
        Rotation::Quaternion(q)
    } else {
        let mut angles = [0.0; 3];
        for a in &mut angles {
            *a = fields.real("an angle (roll pitch yaw)")?;
        }
        Rotation::RollPitchYaw(angles)
    };
    Ok(Pose {
        translation,
        rotation,
    })
}

/// `m` with its 3×3 blocks swapped: between tangent orders `[δω, δρ]` and
/// `[δρ, δω]` (its own inverse).
pub(crate) fn swap_rotation_translation(m: &Matrix6<f64>) -> Matrix6<f64> {
    Matrix6::from_fn(|i, j| m[((i + 3) % 6, (j + 3) % 6)])
}

pub(crate) fn write(
    graph: &PoseGraph,
    out: &mut impl Write,
    name: &str,
    dialect: &Dialect,
) -> Result<(), Error> {
    graph.validate().map_err(|what| Error::file(name, what))?;
    write_unchecked(graph, out, dialect).map_err(|e| io_error(name, e))
}

fn write_unchecked(
    graph: &PoseGraph,
    out: &mut impl Write,
    dialect: &Dialect,
) -> std::io::Result<()> {
    for v in &graph.vertices {
        write!(out, "{} {}", dialect.vertex_tag, v.id)?;
        write_pose(out, &v.pose, dialect)?;
        writeln!(out)?;
    }
    for e in &graph.edges {
        write!(out, "{} {} {}", dialect.edge_tag, e.from, e.to)?;
        write_pose(out, &e.measurement, dialect)?;
        let information = if dialect.translation_first {
            swap_rotation_translation(&e.information)
        } else {
            e.information
        };
        write_upper_triangle(out, &information)?;
        writeln!(out)?;
    }
    Ok(())
}

/// Writes ` x y z` then the dialect's rotation.
pub(crate) fn write_pose(
    out: &mut impl Write,
    pose: &Pose,
    dialect: &Dialect,
) -> std::io::Result<()> {
    for t in pose.translation.iter() {
        write!(out, " {}", Real(*t))?;
    }
    if dialect.quaternions {
        for c in pose.rotation.quaternion_coefficients() {
            write!(out, " {}", Real(c))?;
        }
    } else {
        for a in pose.rotation.roll_pitch_yaw() {
            write!(out, " {}", Real(a))?;
        }
    }
    Ok(())
}
