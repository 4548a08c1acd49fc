//! Reading and writing the text of a [`G2oGraph`], one record per line.

use std::io::{BufRead, Write};

use nalgebra::SVector;

use crate::error::{Error, quoted};
use crate::g2o_graph::{
    G2oGraph, Item, LineEdge, LineVertex, PlaneEdge, PlaneVertex, PointEdge, PointVertex,
    PriorEdge, Se3Offset,
};
use crate::graph_file::{
    G2O, read_pose, read_upper_triangle, swap_rotation_translation, write_pose,
    write_upper_triangle,
};
use crate::input::{Cursor, Fields, Lines, parse_integer};
use crate::output::{Real, io_error};
use crate::pose_graph::{Edge, Vertex};

const PARAMS: &str = "PARAMS_SE3OFFSET";
const POSE: &str = "VERTEX_SE3:QUAT";
const LINE: &str = "VERTEX_LINE3D";
const PLANE: &str = "VERTEX_PLANE";
const POINT: &str = "VERTEX_TRACKXYZ";
const POSE_EDGE: &str = "EDGE_SE3:QUAT";
const LINE_EDGE: &str = "EDGE_SE3_LINE3D";
const PLANE_EDGE: &str = "EDGE_SE3_PLANE_CALIB";
const POINT_EDGE: &str = "EDGE_SE3_TRACKXYZ";
const PRIOR: &str = "EDGE_SE3_PRIOR";
const FIX: &str = "FIX";

/// Every tag read, in the order they are written.
const TAGS: [&str; 11] = [
    PARAMS, POSE, LINE, PLANE, POINT, POSE_EDGE, LINE_EDGE, PLANE_EDGE, POINT_EDGE, PRIOR, FIX,
];

/// The line numbers of the items read, list by list, to report a defect
/// found after reading at its line.
#[derive(Default)]
struct ItemLines {
    offsets: Vec<usize>,
    poses: Vec<usize>,
    lines: Vec<usize>,
    planes: Vec<usize>,
    points: Vec<usize>,
    pose_edges: Vec<usize>,
    line_edges: Vec<usize>,
    plane_edges: Vec<usize>,
    point_edges: Vec<usize>,
    priors: Vec<usize>,
    fixed: Vec<usize>,
}

impl ItemLines {
    fn of(&self, item: Item) -> usize {
        match item {
            Item::Offset(k) => self.offsets[k],
            Item::Pose(k) => self.poses[k],
            Item::Line(k) => self.lines[k],
            Item::Plane(k) => self.planes[k],
            Item::Point(k) => self.points[k],
            Item::PoseEdge(k) => self.pose_edges[k],
            Item::LineEdge(k) => self.line_edges[k],
            Item::PlaneEdge(k) => self.plane_edges[k],
            Item::PointEdge(k) => self.point_edges[k],
            Item::Prior(k) => self.priors[k],
            Item::Fixed(k) => self.fixed[k],
        }
    }
}

pub(crate) fn read(reader: impl BufRead, name: &str) -> Result<G2oGraph, Error> {
    let mut lines = Lines::new(reader, name);
    let mut graph = G2oGraph::default();
    let mut at = ItemLines::default();
    while let Some(line) = lines.next_record()? {
        let number = line.number;
        let mut fields = line.fields();
        let tag = fields.token("a tag")?;
        match tag {
            PARAMS => {
                let id = fields.integer("the parameter id")?;
                let offset = read_pose(&mut fields, &G2O)?;
                graph.offsets.push(Se3Offset { id, offset });
                at.offsets.push(number);
            }
            POSE => {
                let id = fields.integer("the vertex id")?;
                let pose = read_pose(&mut fields, &G2O)?;
                graph.poses.push(Vertex { id, pose });
                at.poses.push(number);
            }
            LINE => {
                let id = fields.integer("the vertex id")?;
                let line = read_vector(&mut fields, LINE_COORDINATE)?;
                graph.lines.push(LineVertex { id, line });
                at.lines.push(number);
            }
            PLANE => {
                let id = fields.integer("the vertex id")?;
                let plane = read_vector(&mut fields, PLANE_COEFFICIENT)?;
                graph.planes.push(PlaneVertex { id, plane });
                at.planes.push(number);
            }
            POINT => {
                let id = fields.integer("the vertex id")?;
                let point = read_vector(&mut fields, POINT_COORDINATE)?;
                graph.points.push(PointVertex { id, point });
                at.points.push(number);
            }
            POSE_EDGE => {
                let from = fields.integer("the first pose id")?;
                let to = fields.integer("the second pose id")?;
                let measurement = read_pose(&mut fields, &G2O)?;
                let information = read_upper_triangle(&mut fields)?;
                graph.pose_edges.push(Edge {
                    from,
                    to,
                    measurement,
                    information: swap_rotation_translation(&information),
                });
                at.pose_edges.push(number);
            }
            LINE_EDGE => {
                let pose = fields.integer("the pose id")?;
                let line = fields.integer("the line id")?;
                let offset = fields.integer("the parameter id")?;
                let measurement = read_vector(&mut fields, LINE_COORDINATE)?;
                let information = read_upper_triangle(&mut fields)?;
                graph.line_edges.push(LineEdge {
                    pose,
                    line,
                    offset,
                    measurement,
                    information,
                });
                at.line_edges.push(number);
            }
            PLANE_EDGE => {
                let count = fields.integer("the number of vertices")?;
                if count != 3 {
                    return Err(line.error(format!(
                        "{PLANE_EDGE} joins 3 vertices (robot pose, plane, sensor offset), \
                         not {count}"
                    )));
                }
                let pose = fields.integer("the pose id")?;
                let plane = fields.integer("the plane id")?;
                let offset = fields.integer("the sensor offset id")?;
                let measurement = read_vector(&mut fields, PLANE_COEFFICIENT)?;
                let information = read_upper_triangle(&mut fields)?;
                graph.plane_edges.push(PlaneEdge {
                    pose,
                    plane,
                    offset,
                    measurement,
                    information,
                });
                at.plane_edges.push(number);
            }
            POINT_EDGE => {
                let pose = fields.integer("the pose id")?;
                let point = fields.integer("the point id")?;
                let offset = fields.integer("the parameter id")?;
                let measurement = read_vector(&mut fields, POINT_COORDINATE)?;
                let information = read_upper_triangle(&mut fields)?;
                graph.point_edges.push(PointEdge {
                    pose,
                    point,
                    offset,
                    measurement,
                    information,
                });
                at.point_edges.push(number);
            }
            PRIOR => {
                let pose = fields.integer("the pose id")?;
                let offset = fields.integer("the parameter id")?;
                let measurement = read_pose(&mut fields, &G2O)?;
                let information = read_upper_triangle(&mut fields)?;
                graph.priors.push(PriorEdge {
                    pose,
                    offset,
                    measurement,
                    information: swap_rotation_translation(&information),
                });
                at.priors.push(number);
            }
            FIX => {
                let before = graph.fixed.len();
                while let Some(token) = fields.next_token() {
                    let id = parse_integer(token)
                        .map_err(|message| line.error(format!("a fixed vertex id: {message}")))?;
                    graph.fixed.push(id);
                    at.fixed.push(number);
                }
                if graph.fixed.len() == before {
                    return Err(line.error("FIX without a vertex id"));
                }
            }
            "VERTEX3" | "EDGE3" => {
                return Err(line.error(format!(
                    "{tag} is a line of the edge3 format, not g2o: read the file as edge3"
                )));
            }
            _ => {
                return Err(line.error(format!(
                    "unsupported tag {} (a g2o graph of lines, planes and points has {} lines)",
                    quoted(tag),
                    TAGS.join(", ")
                )));
            }
        }
        fields.finish()?;
    }
    match graph.find_defect() {
        None => Ok(graph),
        Some((item, what)) => Err(Error::at_line(lines.file(), at.of(item), what)),
    }
}

const LINE_COORDINATE: &str = "a line coordinate (wx wy wz dx dy dz)";
const PLANE_COEFFICIENT: &str = "a plane coefficient (nx ny nz d)";
const POINT_COORDINATE: &str = "a point coordinate (x y z)";

/// `N` numbers.
fn read_vector<const N: usize>(
    fields: &mut Fields<'_>,
    what: &str,
) -> Result<SVector<f64, N>, Error> {
    let mut v = SVector::<f64, N>::zeros();
    for x in v.iter_mut() {
        *x = fields.real(what)?;
    }
    Ok(v)
}

pub(crate) fn write(graph: &G2oGraph, out: &mut impl Write, name: &str) -> Result<(), Error> {
    graph.validate().map_err(|what| Error::file(name, what))?;
    write_unchecked(graph, out).map_err(|e| io_error(name, e))
}

fn write_numbers(out: &mut impl Write, values: &[f64]) -> std::io::Result<()> {
    for v in values {
        write!(out, " {}", Real(*v))?;
    }
    Ok(())
}

fn write_unchecked(graph: &G2oGraph, out: &mut impl Write) -> std::io::Result<()> {
    for p in &graph.offsets {
        write!(out, "{PARAMS} {}", p.id)?;
        write_pose(out, &p.offset, &G2O)?;
        writeln!(out)?;
    }
    for v in &graph.poses {
        write!(out, "{POSE} {}", v.id)?;
        write_pose(out, &v.pose, &G2O)?;
        writeln!(out)?;
    }
    for v in &graph.lines {
        write!(out, "{LINE} {}", v.id)?;
        write_numbers(out, v.line.as_slice())?;
        writeln!(out)?;
    }
    for v in &graph.planes {
        write!(out, "{PLANE} {}", v.id)?;
        write_numbers(out, v.plane.as_slice())?;
        writeln!(out)?;
    }
    for v in &graph.points {
        write!(out, "{POINT} {}", v.id)?;
        write_numbers(out, v.point.as_slice())?;
        writeln!(out)?;
    }
    for e in &graph.pose_edges {
        write!(out, "{POSE_EDGE} {} {}", e.from, e.to)?;
        write_pose(out, &e.measurement, &G2O)?;
        write_upper_triangle(out, &swap_rotation_translation(&e.information))?;
        writeln!(out)?;
    }
    for e in &graph.line_edges {
        write!(out, "{LINE_EDGE} {} {} {}", e.pose, e.line, e.offset)?;
        write_numbers(out, e.measurement.as_slice())?;
        write_upper_triangle(out, &e.information)?;
        writeln!(out)?;
    }
    for e in &graph.plane_edges {
        write!(out, "{PLANE_EDGE} 3 {} {} {}", e.pose, e.plane, e.offset)?;
        write_numbers(out, e.measurement.as_slice())?;
        write_upper_triangle(out, &e.information)?;
        writeln!(out)?;
    }
    for e in &graph.point_edges {
        write!(out, "{POINT_EDGE} {} {} {}", e.pose, e.point, e.offset)?;
        write_numbers(out, e.measurement.as_slice())?;
        write_upper_triangle(out, &e.information)?;
        writeln!(out)?;
    }
    for e in &graph.priors {
        write!(out, "{PRIOR} {} {}", e.pose, e.offset)?;
        write_pose(out, &e.measurement, &G2O)?;
        write_upper_triangle(out, &swap_rotation_translation(&e.information))?;
        writeln!(out)?;
    }
    if !graph.fixed.is_empty() {
        write!(out, "{FIX}")?;
        for id in &graph.fixed {
            write!(out, " {id}")?;
        }
        writeln!(out)?;
    }
    Ok(())
}
