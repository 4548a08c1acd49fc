//! A problem of any format: read by path with the format detected or
//! given, written back in its format.

use std::io::BufRead;
use std::path::{Path, PathBuf};

use crate::bal::{self, BalProblem};
use crate::bundler::{self, BundlerProblem};
use crate::edge3;
use crate::error::Error;
use crate::format::{Format, sniff};
use crate::g2o;
use crate::g2o_graph::G2oGraph;
use crate::input;
use crate::kitti_vo::{self, StereoVo, VoFiles};
use crate::pose_graph::PoseGraph;

/// A problem read from a file, tagged with its format.
#[derive(Debug, Clone, PartialEq)]
pub enum Problem {
    /// A BAL bundle-adjustment problem.
    Bal(BalProblem),
    /// A Bundler reconstruction.
    Bundler(BundlerProblem),
    /// A g2o pose graph.
    G2o(PoseGraph),
    /// A g2o graph with 3D lines, planes, points or priors.
    G2oAddons(G2oGraph),
    /// An EDGE3 pose graph.
    Edge3(PoseGraph),
    /// A KITTI stereo VO problem.
    KittiVo(StereoVo),
}

impl Problem {
    /// Reads the problem at `path`, in `format` or else the one its name
    /// tells or, for any other name, its content ([`Format::from_name`],
    /// [`Format::from_content`]). The file is opened and read once, so a
    /// pipe (`/dev/stdin`) reads as a file does. A KITTI VO problem is named
    /// by any of its three files ([`VoFiles::beside`]).
    pub fn read(path: impl AsRef<Path>, format: Option<Format>) -> Result<Problem, Error> {
        let path = path.as_ref();
        let format = format.or_else(|| Format::from_name(path));
        if format == Some(Format::KittiVo) {
            return Ok(Problem::KittiVo(kitti_vo::read(&VoFiles::beside(path)?)?));
        }
        let (reader, name) = input::open(path)?;
        Problem::read_from(reader, &name, format)
    }

    /// Reads a problem from `reader` (`name` names it in errors), in
    /// `format` or else the one its content tells; the input is read once
    /// (what telling the format read is replayed to the reader). A KITTI VO
    /// problem is three files and cannot be read from one input.
    pub fn read_from(
        reader: impl BufRead,
        name: &str,
        format: Option<Format>,
    ) -> Result<Problem, Error> {
        match format {
            Some(format) => Problem::parse(reader, name, format),
            None => {
                let (format, input) = sniff(reader, name);
                Problem::parse(input, name, format?)
            }
        }
    }

    fn parse(reader: impl BufRead, name: &str, format: Format) -> Result<Problem, Error> {
        Ok(match format {
            Format::Bal => Problem::Bal(bal::read_from(reader, name)?),
            Format::Bundler => Problem::Bundler(bundler::read_from(reader, name)?),
            Format::G2o => Problem::G2o(g2o::read_from(reader, name)?),
            Format::G2oAddons => Problem::G2oAddons(g2o::read_graph_from(reader, name)?),
            Format::Edge3 => Problem::Edge3(edge3::read_from(reader, name)?),
            Format::KittiVo => {
                return Err(Error::file(
                    name,
                    "a KITTI VO problem is three files: name one of them (VO_*.txt)",
                ));
            }
        })
    }

    /// The files the problem that `path` names is read from, in `format`
    /// or the one its name tells: the three files of a KITTI VO problem
    /// ([`VoFiles::beside`]), else `path` itself. Nothing is read.
    pub fn files_read(path: &Path, format: Option<Format>) -> Result<Vec<PathBuf>, Error> {
        if format.or_else(|| Format::from_name(path)) == Some(Format::KittiVo) {
            Ok(VoFiles::beside(path)?.all().map(Path::to_path_buf).into())
        } else {
            Ok(vec![path.to_path_buf()])
        }
    }

    /// The files [`Problem::write`] writes for `path`, a problem in
    /// `format` (`None`: a format of one file, not yet told): the three
    /// files of a KITTI VO problem ([`VoFiles::named`]), else `path`
    /// itself. Nothing is written.
    pub fn files_written(path: &Path, format: Option<Format>) -> Result<Vec<PathBuf>, Error> {
        if format == Some(Format::KittiVo) {
            Ok(VoFiles::named(path)?.all().map(Path::to_path_buf).into())
        } else {
            Ok(vec![path.to_path_buf()])
        }
    }

    /// The problem's measurements: observations (bundle adjustment, stereo
    /// VO) or edges (pose, line and plane graphs).
    pub fn measurements(&self) -> usize {
        match self {
            Problem::Bal(p) => p.observations.len(),
            Problem::Bundler(p) => p.observations.len(),
            Problem::G2o(g) | Problem::Edge3(g) => g.edges.len(),
            Problem::G2oAddons(g) => {
                g.pose_edges.len()
                    + g.line_edges.len()
                    + g.plane_edges.len()
                    + g.point_edges.len()
                    + g.priors.len()
            }
            Problem::KittiVo(vo) => vo.observations.len(),
        }
    }

    /// The problem's format.
    pub fn format(&self) -> Format {
        match self {
            Problem::Bal(_) => Format::Bal,
            Problem::Bundler(_) => Format::Bundler,
            Problem::G2o(_) => Format::G2o,
            Problem::G2oAddons(_) => Format::G2oAddons,
            Problem::Edge3(_) => Format::Edge3,
            Problem::KittiVo(_) => Format::KittiVo,
        }
    }

    /// Writes the problem at `path` in its format (a KITTI VO problem to the
    /// three files [`VoFiles::named`] names), each file to a temporary file
    /// renamed into place once complete.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), Error> {
        let path = path.as_ref();
        match self {
            Problem::Bal(problem) => bal::write(problem, path),
            Problem::Bundler(problem) => bundler::write(problem, path),
            Problem::G2o(graph) => g2o::write(graph, path),
            Problem::G2oAddons(graph) => g2o::write_graph(graph, path),
            Problem::Edge3(graph) => edge3::write(graph, path),
            Problem::KittiVo(vo) => kitti_vo::write(vo, &VoFiles::named(path)?),
        }
    }
}
